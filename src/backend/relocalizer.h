// Backend's relocalisation (docs/relocalization.md): a search backend
// estimates the run in its own frame from the keyframes given, its
// confirmed objects are matched with the loaded map's after every solve,
// and on a match its keyframes are handed back in the map's frame.
#ifndef SYMBA_SRC_BACKEND_RELOCALIZER_H_
#define SYMBA_SRC_BACKEND_RELOCALIZER_H_

#include <memory>
#include <utility>
#include <vector>

#include "symba/backend/backend.h"
#include "symba/backend/relocalization.h"

namespace symba::internal {

class Relocalizer {
 public:
  Relocalizer(std::unique_ptr<Backend> search,
              std::vector<MapObjectEstimate> map_objects,
              const RelocalizationOptions& options);

  bool searching() const {
    return report_.state == RelocalizationReport::State::kSearching;
  }
  Backend& search() { return *search_; }
  const Backend& search() const { return *search_; }
  const RelocalizationReport& report() const { return report_; }

  // Adds the keyframe to the search and keeps it for the map's frame; its
  // detections' assignments are pending (object -1) until relocalised.
  Status Add(const KeyframeInput& input,
             std::vector<DetectionAssignment>* assignments);
  // After the search's solve: matches its objects with the map's. True on
  // a match (the report says with what).
  bool TryMatch();
  bool Exhausted() const { return report_.keyframes >= options_.max_keyframes; }
  // Relocalised: the search's keyframes with every pose given moved into
  // the map's frame; the search and its keyframes are released.
  std::vector<KeyframeInput> TakeKeyframesInMapFrame();
  // Gave up: the search backend, to go on with.
  std::unique_ptr<Backend> GiveUp();
  // Keeps what the backend let go of alive until the backend goes.
  void Retire(std::unique_ptr<Backend> retired) {
    retired_ = std::move(retired);
  }
  void AddSeconds(double seconds) { report_.seconds += seconds; }

 private:
  std::unique_ptr<Backend> search_;
  std::unique_ptr<Backend> retired_;
  std::vector<MapObjectEstimate> map_objects_;
  RelocalizationOptions options_;
  std::vector<KeyframeInput> keyframes_;
  RelocalizationReport report_;
};

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_RELOCALIZER_H_
