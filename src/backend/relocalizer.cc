#include "backend/relocalizer.h"

#include <utility>

namespace symba {

const char* ToString(RelocalizationReport::State state) {
  switch (state) {
    case RelocalizationReport::State::kSearching:
      return "searching";
    case RelocalizationReport::State::kRelocalized:
      return "relocalized";
    case RelocalizationReport::State::kGaveUp:
      return "gave up";
  }
  return "unknown";
}

namespace internal {

Relocalizer::Relocalizer(std::unique_ptr<Backend> search,
                         std::vector<MapObjectEstimate> map_objects,
                         const RelocalizationOptions& options)
    : search_(std::move(search)),
      map_objects_(std::move(map_objects)),
      options_(options) {}

Status Relocalizer::Add(const KeyframeInput& input,
                        std::vector<DetectionAssignment>* assignments) {
  Status status = search_->AddKeyframe(input, assignments);
  if (!status.ok()) return status;
  keyframes_.push_back(input);
  ++report_.keyframes;
  if (assignments != nullptr) {
    for (DetectionAssignment& assignment : *assignments) {
      assignment.object = -1;
    }
  }
  return Status::Ok();
}

bool Relocalizer::TryMatch() {
  ++report_.attempts;
  const ConstellationMatchResult result =
      MatchConstellation(search_->Objects(), map_objects_, options_.match);
  report_.last_outcome = ToString(result.outcome);
  if (!result.match) return false;
  report_.state = RelocalizationReport::State::kRelocalized;
  report_.keyframe = keyframes_.back().id;
  report_.T_map_run = result.match->T_map_local;
  report_.correspondences = result.match->correspondences;
  report_.position_rmse = result.match->position_rmse;
  return true;
}

std::vector<KeyframeInput> Relocalizer::TakeKeyframesInMapFrame() {
  std::vector<KeyframeInput> keyframes = std::move(keyframes_);
  keyframes_.clear();
  for (KeyframeInput& keyframe : keyframes) {
    if (keyframe.T_wc) keyframe.T_wc = report_.T_map_run * *keyframe.T_wc;
  }
  search_.reset();
  map_objects_.clear();
  return keyframes;
}

std::unique_ptr<Backend> Relocalizer::GiveUp() {
  report_.state = RelocalizationReport::State::kGaveUp;
  keyframes_.clear();
  map_objects_.clear();
  return std::move(search_);
}

}  // namespace internal
}  // namespace symba
