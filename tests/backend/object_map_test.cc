// The object map on its own (src/backend/object_map.h): tentative objects
// confirmed or dropped, unsupported objects pruned, flips that upgrade an
// object, a discrete object's angles (matched, folded by the class prior's
// order, or new), re-anchoring, and the detector's noise samples.
#include "backend/object_map.h"
#include "backend/object_track.h"

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "symba/factors/pose_component.h"
#include "symba/geometry/pi.h"
#include "test_support/random.h"

namespace symba::internal {
namespace {

Rigid3d At(double x, double y, double z) {
  return Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(x, y, z));
}

Eigen::Quaterniond AboutZ(double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
}

// The map and the graph over its objects, built as the backend builds them
// (the map keeps the graph's address until the graph exists).
struct MapAndGraph {
  MapAndGraph(const BackendOptions& options,
              const std::map<std::string, ClassPrior>& priors,
              const KeyframeList& keyframes,
              const PointList& points,
              BackendStatistics* statistics,
              std::vector<DetectionAssignment>* assignments)
      : map(options, priors, &graph, statistics, assignments),
        graph(options, keyframes, map.objects(), points, statistics) {}
  ObjectMap map;
  FactorGraph graph;
};

class ObjectMapTest : public ::testing::Test {
 protected:
  void Build(const BackendOptions& options,
             const std::map<std::string, ClassPrior>& priors = {}) {
    options_ = options;
    parts_ = std::make_unique<MapAndGraph>(
        options_, priors, keyframes_, points_, &statistics_, &assignments_);
    map_ = &parts_->map;
  }
  // A detection of object o in keyframe k, 2 m ahead of the camera.
  void Detect(int o, int k) {
    assignments_.push_back(
        {k, std::to_string(k), o, SymmetryType::kAsymmetric});
    map_->NoteDetection(o,
                        k,
                        static_cast<int>(assignments_.size()) - 1,
                        Eigen::Vector3d(0, 0, 2));
  }
  // Object o as a discrete object about z with one angle, theta 0.
  void MakeDiscrete(int o) {
    map_->Upgrade(o, SymmetryType::kDiscrete, Eigen::Vector3d::UnitZ(), {});
  }

  // Builds the map with a class prior that makes `class_name` discrete of
  // `order` about z, and returns a discrete object of it at (0, 0, 2) with
  // angle 0 (theta 0).
  int DiscreteOfKnownOrder(const std::string& class_name, int order) {
    ClassPrior prior;
    prior.symmetry = SymmetryType::kDiscrete;
    prior.order = order;
    prior.axis_o = Eigen::Vector3d::UnitZ();
    BackendOptions options;
    options.confirm_keyframes = 1;
    Build(options, {{class_name, prior}});
    const int o =
        map_->Create(class_name, SymmetryType::kAsymmetric, At(0, 0, 2), 0);
    MakeDiscrete(o);
    return o;
  }
  // A discrete "table" whose class prior gives order 2 about z and a
  // discrete "bench" without a prior, each with angle 0 (theta 0).
  std::pair<int, int> TableOfOrderTwoAndBench() {
    const int table = DiscreteOfKnownOrder("table", 2);
    const int bench =
        map_->Create("bench", SymmetryType::kAsymmetric, At(3, 0, 2), 0);
    MakeDiscrete(bench);
    return {table, bench};
  }

  BackendOptions options_;
  KeyframeList keyframes_;
  PointList points_;
  BackendStatistics statistics_;
  std::vector<DetectionAssignment> assignments_;
  std::unique_ptr<MapAndGraph> parts_;
  ObjectMap* map_ = nullptr;
};

TEST_F(ObjectMapTest, ATentativeObjectIsConfirmedOrDroppedWithItsDetections) {
  BackendOptions options;
  options.confirm_keyframes = 3;
  options.tentative_timeout = 4;
  Build(options);
  const int kept =
      map_->Create("box", SymmetryType::kAsymmetric, At(1, 2, 3), 0);
  const int lost =
      map_->Create("box", SymmetryType::kAsymmetric, At(5, 0, 0), 0);
  EXPECT_EQ(map_->objects()[kept]->position(), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(map_->ObjectsOfClass("box"), (std::vector<int>{kept, lost}));
  EXPECT_TRUE(map_->ObjectsOfClass("chair").empty());
  Detect(kept, 0);
  Detect(lost, 0);
  for (int k = 1; k <= 4; ++k) {
    if (k <= 2) Detect(kept, k);
    map_->UpdateTentative(k);
    EXPECT_EQ(map_->objects()[kept]->status,
              k < 2 ? ObjectStatus::kTentative : ObjectStatus::kConfirmed)
        << k;
  }
  EXPECT_EQ(map_->objects()[lost]->status, ObjectStatus::kDropped);
  EXPECT_EQ(statistics_.objects, 1);
  EXPECT_EQ(statistics_.objects_dropped, 1);
  EXPECT_EQ(assignments_[1].object, -1);  // the dropped object's detection
  EXPECT_EQ(assignments_[0].object, kept);
  EXPECT_EQ(map_->objects()[kept]->detections, 3);
  EXPECT_EQ(map_->objects()[kept]->keyframes_seen, 3);
}

// A duplicate merged into the object it is (loops from the objects): its
// detections and their assignments become the object's, the counts add up,
// the duplicate is gone and its observations are handed back for the
// caller's edges; the confirmed count drops by one.
TEST_F(ObjectMapTest, ADuplicateMergedIntoItsObjectHandsOverItsDetections) {
  BackendOptions options;
  options.confirm_keyframes = 1;
  Build(options);
  const int object =
      map_->Create("box", SymmetryType::kAsymmetric, At(1, 2, 3), 0);
  for (int k = 0; k < 3; ++k) Detect(object, k);
  const int duplicate =
      map_->Create("box", SymmetryType::kAsymmetric, At(1.1, 2, 3), 7);
  for (int k = 7; k < 9; ++k) Detect(duplicate, k);
  ObjectObservation observation;
  observation.keyframe = 8;
  map_->mutable_objects()[duplicate]->observations.push_back(observation);
  EXPECT_EQ(map_->confirmations(), 2);
  EXPECT_EQ(statistics_.objects, 2);

  const std::vector<ObjectObservation> handed =
      map_->MergeInto(duplicate, object);
  ASSERT_EQ(handed.size(), 1u);
  EXPECT_EQ(handed[0].keyframe, 8);
  EXPECT_EQ(map_->objects()[duplicate]->status, ObjectStatus::kDropped);
  const ObjectState& merged = *map_->objects()[object];
  EXPECT_EQ(merged.status, ObjectStatus::kConfirmed);
  EXPECT_EQ(merged.detections, 5);
  EXPECT_EQ(merged.keyframes_seen, 5);
  EXPECT_EQ(merged.last_keyframe, 8);
  EXPECT_EQ(merged.assignments, (std::vector<int>{0, 1, 2, 3, 4}));
  for (const DetectionAssignment& a : assignments_) {
    EXPECT_EQ(a.object, object) << a.detection;
  }
  EXPECT_EQ(statistics_.objects, 1);
  EXPECT_EQ(statistics_.objects_merged, 1);
  EXPECT_EQ(statistics_.objects_dropped, 0);
  EXPECT_EQ(map_->confirmations(), 2);  // never decreases
}

// min_support 0.5 over 4 views: an object in view (inside the cone and
// depth detections were seen in) but detected in 1 of 4 keyframes is
// dropped; one out of view is not counted.
TEST_F(ObjectMapTest, AnObjectInViewButRarelyDetectedIsPruned) {
  BackendOptions options;
  options.confirm_keyframes = 1;
  options.min_support = 0.5;
  options.min_support_views = 4;
  Build(options);
  const int ghost =
      map_->Create("box", SymmetryType::kAsymmetric, At(0, 0, 2), 0);
  const int behind =
      map_->Create("box", SymmetryType::kAsymmetric, At(0, 0, -2), 0);
  Detect(ghost, 0);
  for (int k = 0; k < 4; ++k) {
    map_->PruneUnsupported(k, Rigid3d());
    EXPECT_EQ(map_->objects()[ghost]->status,
              k < 3 ? ObjectStatus::kConfirmed : ObjectStatus::kDropped)
        << k;
  }
  EXPECT_EQ(map_->objects()[behind]->keyframes_in_view, 0);
  EXPECT_EQ(map_->objects()[behind]->status, ObjectStatus::kConfirmed);
  EXPECT_EQ(statistics_.objects, 1);
}

// A flip by `angle` about z in keyframe k of an object at the identity
// rotation, for RecordFlip (the detection is then noted, as the backend
// does).
ObjectMap::FlipOutcome FlipOutcomeOf(ObjectMap* map,
                                     int o,
                                     int k,
                                     double angle = kPi) {
  SymbaMatch flip;
  flip.object = o;
  flip.flip = true;
  flip.a_o = Eigen::Vector3d::UnitZ();
  flip.flip_angle = angle;
  flip.R_wo_flip = AboutZ(angle);
  return map->RecordFlip(o, k, flip);
}
bool ObjectMapTestFlip(ObjectMap* map, int o, int k, double angle = kPi) {
  return FlipOutcomeOf(map, o, k, angle) == ObjectMap::FlipOutcome::kUpgraded;
}

// upgrade_evidence 2, upgrade_min_fraction 0: three unflipped views, then
// flips by pi about z. The first two flips are not enough (odds
// exp(2.73) < 100 for 3 and 2, upgrade_evidence.h); the third, in another
// keyframe, upgrades the object to discrete of order 2 (exp(4.63)).
TEST_F(ObjectMapTest, RepeatedFlipsUpgradeAnAsymmetricObject) {
  BackendOptions options;
  options.confirm_keyframes = 1;
  options.upgrade_evidence = 2;
  options.upgrade_min_fraction = 0.0;
  Build(options);
  const int o =
      map_->Create("table", SymmetryType::kAsymmetric, At(0, 0, 2), 0);
  for (int k = 0; k < 3; ++k) Detect(o, k);
  EXPECT_FALSE(ObjectMapTestFlip(map_, o, 3));
  Detect(o, 3);
  EXPECT_EQ(statistics_.rotation_outliers, 1);
  EXPECT_FALSE(ObjectMapTestFlip(map_, o, 4));
  Detect(o, 4);
  EXPECT_TRUE(ObjectMapTestFlip(map_, o, 5));
  const ObjectState& object = *map_->objects()[o];
  EXPECT_EQ(object.type, SymmetryType::kDiscrete);
  ASSERT_TRUE(object.upgrade.has_value());
  EXPECT_EQ(object.upgrade->order, 2);
  EXPECT_EQ(object.upgrade->evidence, 3);
  EXPECT_EQ(object.upgrade->keyframe, 5);
  EXPECT_NEAR(object.upgrade->angle, kPi, 1e-12);
  ASSERT_EQ(object.thetas.size(), 1u);
  EXPECT_TRUE(object.flips.empty());
  EXPECT_EQ(statistics_.object_upgrades, 1);
  // The asymmetric pose is angle 0.
  EXPECT_LT(object.Rotation(0).angularDistance(Eigen::Quaterniond::Identity()),
            1e-12);
}

// An object made from one wrongly turned detection: every later detection
// is a flip by the same angle, each agreeing with the others. That is
// evidence against its first rotation, not a symmetry (the YCB-Video potted
// meat can and cracker box were upgraded so): no upgrade. Once the flips
// reject a symmetry too (one view and 19 flips: odds exp(-4.83) for two
// recurring rotations, upgrade_evidence.h) the object turns to the flips'
// rotation, and their detections are views of it from then on.
TEST_F(ObjectMapTest, AnObjectMadeFromATurnedDetectionTurnsAndIsNotUpgraded) {
  BackendOptions options;
  options.confirm_keyframes = 1;
  Build(options);
  const int o = map_->Create("can", SymmetryType::kAsymmetric, At(0, 0, 2), 0);
  Detect(o, 0);
  // Its one view, as the backend keeps it: the rotation it was made with.
  ObjectState& object = *map_->objects()[o];
  ObjectObservation view;
  view.keyframe = 0;
  view.components.push_back({At(0, 0, 2), Matrix6d::Identity(), 1.0});
  view.T_co_best = view.components.front().T_co;
  object.observations.push_back(view);
  const double angle = 86 * kPi / 180;
  for (int k = 1; k <= 18; ++k) {
    EXPECT_EQ(FlipOutcomeOf(map_, o, k, angle),
              ObjectMap::FlipOutcome::kOutlier)
        << "keyframe " << k;
    Detect(o, k);
  }
  // 18 flips of order 4 (86 deg within 10 of 90) in 19 keyframes.
  EXPECT_EQ(map_->ClassFlips("can").flip_keyframes_by_order.at(4), 18);
  EXPECT_EQ(FlipOutcomeOf(map_, o, 19, angle), ObjectMap::FlipOutcome::kTurned);
  EXPECT_EQ(object.type, SymmetryType::kAsymmetric);
  EXPECT_LT(object.Rotation(-1).angularDistance(AboutZ(angle)), 1e-12);
  // The view turned with the object and carries no information
  // (object_edges.h).
  EXPECT_TRUE(object.observations.front().turned_away);
  EXPECT_LT(
      object.observations.front().components.front().T_co.q.angularDistance(
          AboutZ(angle)),
      1e-12);
  // The view at the rotation it left is its one flip now, in its class's
  // counts too; the 19 flips that turned it are views.
  EXPECT_TRUE(object.flips.empty());
  EXPECT_EQ(object.flip_keyframes, 0);
  EXPECT_EQ(object.flips_left_behind, 1);
  EXPECT_EQ(map_->ClassFlips("can").flip_keyframes_by_order.at(4), 1);
  EXPECT_EQ(statistics_.objects_turned, 1);
  EXPECT_EQ(statistics_.object_upgrades, 0);
  EXPECT_EQ(object.chain.rotation_count, 0);
}

// A second object of a class that its detector turns by pi in half of the
// keyframes, as a symmetric object would be: upgraded when it is the only
// one of its class; not when the class's first object was seen unflipped in
// 40 keyframes (the class's flips of order 2 are then 6 of 52 keyframes,
// under upgrade_min_fraction 0.3): a class that rarely flips is not
// symmetric because one of its objects does.
TEST_F(ObjectMapTest, AClassThatRarelyFlipsIsNotUpgradedByOneObject) {
  for (const bool class_seen_before : {false, true}) {
    SCOPED_TRACE(class_seen_before ? "with a first object" : "alone");
    statistics_ = BackendStatistics();
    assignments_.clear();
    BackendOptions options;
    options.confirm_keyframes = 1;
    Build(options);
    int k = 0;
    if (class_seen_before) {
      const int first =
          map_->Create("can", SymmetryType::kAsymmetric, At(0, 0, 2), k);
      for (; k < 40; ++k) Detect(first, k);
    }
    const int o =
        map_->Create("can", SymmetryType::kAsymmetric, At(1, 0, 2), k);
    bool upgraded = false;
    for (int i = 0; i < 12; ++i, ++k) {
      if (i % 2 == 1) upgraded = upgraded || ObjectMapTestFlip(map_, o, k);
      Detect(o, k);
    }
    EXPECT_EQ(upgraded, !class_seen_before);
    EXPECT_EQ(statistics_.object_upgrades, class_seen_before ? 0 : 1);
    EXPECT_EQ(statistics_.objects_turned, 0);  // both rotations recur
  }
}

// An asymmetric object loaded from a map with 40 observations, upgraded
// before this run gave it an edge: angle 0, its pose, holds the 40 loaded
// observations as evidence (MapObjectEstimate::angle_evidence); a new angle
// starts with none, and evidence adds up per angle.
TEST_F(ObjectMapTest, AnUpgradeCountsTheLoadedObservationsForAngleZero) {
  Build(BackendOptions());
  MapObjectEstimate saved;
  saved.id = 0;
  saved.class_name = "mug";
  saved.symmetry = SymmetryType::kAsymmetric;
  saved.t_wo = Eigen::Vector3d(0, 0, 2);
  saved.poses = {At(0, 0, 2)};
  saved.observations = 40;
  map_->Load(saved);
  MakeDiscrete(0);
  const ObjectState& object = *map_->objects()[0];
  ASSERT_EQ(object.angle_evidence.size(), 1u);
  EXPECT_EQ(object.angle_evidence[0], 40.0);
  ObjectObservation turned;
  turned.T_co_best = Rigid3d(AboutZ(kPi), Eigen::Vector3d(0, 0, 2));
  const int angle = map_->MatchOrAddAngle(0, Rigid3d(), false, &turned);
  EXPECT_EQ(angle, 1);
  ASSERT_EQ(object.angle_evidence.size(), 2u);
  EXPECT_EQ(object.angle_evidence[1], 0.0);
  map_->AddAngleEvidence(0, 1, 0.25);
  map_->AddAngleEvidence(0, 1, 1.0);
  EXPECT_EQ(object.angle_evidence[1], 1.25);
}

// A discrete object with angle 0: a detection within gate_angle of it
// matches it; one turned by pi folds onto it when the class prior says the
// order is 2 (its rotation turned back by pi); without a prior it opens a
// new angle.
TEST_F(ObjectMapTest, AnglesMatchFoldByTheKnownOrderOrOpen) {
  const auto [table, other] = TableOfOrderTwoAndBench();
  auto observation = [](double angle) {
    ObjectObservation o;
    o.T_co_best = Rigid3d(AboutZ(angle), Eigen::Vector3d(0, 0, 2));
    PoseComponent component;
    component.T_co = o.T_co_best;
    o.components = {component};
    return o;
  };
  ObjectObservation near = observation(0.1);
  EXPECT_EQ(map_->MatchOrAddAngle(table, Rigid3d(), true, &near), 0);
  ObjectObservation turned = observation(kPi + 0.05);
  EXPECT_EQ(map_->MatchOrAddAngle(table, Rigid3d(), true, &turned), 0);
  EXPECT_EQ(statistics_.folded_angles, 1);
  EXPECT_LT(turned.T_co_best.q.angularDistance(AboutZ(0.05)), 1e-9);
  EXPECT_LT(turned.components[0].T_co.q.angularDistance(AboutZ(0.05)), 1e-9);
  // Several modes in one detection never fold.
  ObjectObservation unfolded = observation(kPi + 0.05);
  EXPECT_EQ(map_->MatchOrAddAngle(table, Rigid3d(), false, &unfolded), 1);
  ObjectObservation no_prior = observation(kPi);
  EXPECT_EQ(map_->MatchOrAddAngle(other, Rigid3d(), true, &no_prior), 1);
  EXPECT_NEAR(std::abs(*map_->objects()[other]->thetas[1]), kPi, 1e-9);
}

// A merge reads a duplicate's angle the same way (MatchOrAddAngle on a
// world rotation): a rotation turned by pi folds onto angle 0 of a class of
// order 2 with its multiple, and TurnByFold turns an observation at it back
// to angle 0; without a prior it opens a new angle, multiple 0.
TEST_F(ObjectMapTest, AMergedAngleFoldsByTheKnownOrder) {
  const auto [table, other] = TableOfOrderTwoAndBench();
  int multiple = 7;
  EXPECT_EQ(map_->MatchOrAddAngle(table, AboutZ(0.1), {}, &multiple), 0);
  EXPECT_EQ(multiple, 0);
  EXPECT_EQ(map_->MatchOrAddAngle(table, AboutZ(kPi + 0.05), {}, &multiple), 0);
  EXPECT_EQ(std::abs(multiple), 1);
  EXPECT_EQ(map_->objects()[table]->thetas.size(), 1u);
  EXPECT_EQ(statistics_.folded_angles, 1);
  ObjectObservation seen;
  seen.T_co_best = Rigid3d(AboutZ(kPi + 0.05), Eigen::Vector3d(0, 0, 2));
  PoseComponent component;
  component.T_co = seen.T_co_best;
  seen.components = {component};
  map_->TurnByFold(table, multiple, &seen);
  EXPECT_LT(seen.T_co_best.q.angularDistance(AboutZ(0.05)), 1e-9);
  EXPECT_LT(seen.components[0].T_co.q.angularDistance(AboutZ(0.05)), 1e-9);
  EXPECT_EQ(map_->MatchOrAddAngle(other, AboutZ(kPi), {}, &multiple), 1);
  EXPECT_EQ(multiple, 0);
  // An angle this merge took already is no fold target: a new angle opens.
  EXPECT_EQ(map_->MatchOrAddAngle(table, AboutZ(kPi + 0.05), {0}, &multiple),
            1);
  EXPECT_EQ(multiple, 0);
}

// Order 3, where the turn's direction matters: a rotation 2 pi / 3 + 0.05
// about the axis folds onto angle 0 with multiple 1 and turns back to 0.05;
// one at -2 pi / 3 + 0.05 with multiple -1.
TEST_F(ObjectMapTest, AFoldTurnsByItsMultipleTheRightWay) {
  const int prism = DiscreteOfKnownOrder("prism", 3);
  for (const auto& [angle, expected] :
       {std::pair{kTwoPi / 3 + 0.05, 1}, std::pair{-kTwoPi / 3 + 0.05, -1}}) {
    int multiple = 0;
    EXPECT_EQ(map_->MatchOrAddAngle(prism, AboutZ(angle), {}, &multiple), 0);
    EXPECT_EQ(multiple, expected);
    ObjectObservation seen;
    seen.T_co_best = Rigid3d(AboutZ(angle), Eigen::Vector3d(0, 0, 2));
    map_->TurnByFold(prism, multiple, &seen);
    EXPECT_LT(seen.T_co_best.q.angularDistance(AboutZ(0.05)), 1e-9) << angle;
  }
}

// An axis 50 deg from its anchor (reanchor_angle 45 deg) is re-anchored at
// itself; the object's rotations do not move. Within the angle nothing
// changes.
TEST_F(ObjectMapTest, ADriftedAxisIsReanchoredWithoutMovingTheObject) {
  BackendOptions options;
  options.confirm_keyframes = 1;
  Build(options);
  const int o =
      map_->Create("table", SymmetryType::kAsymmetric, At(0, 0, 2), 0);
  MakeDiscrete(o);
  ObjectState& object = *map_->mutable_objects()[o];
  *object.thetas[0] = 0.3;
  const Eigen::Vector3d tilted_40(std::sin(0.7), 0, std::cos(0.7));
  Eigen::Map<Eigen::Vector3d>(object.a_w) = tilted_40;
  EXPECT_FALSE(map_->ReanchorIfDrifted(o));
  const Eigen::Vector3d tilted_50(std::sin(0.88), 0, std::cos(0.88));
  Eigen::Map<Eigen::Vector3d>(object.a_w) = tilted_50;
  const Eigen::Quaterniond before = object.Rotation(0);
  EXPECT_TRUE(map_->ReanchorIfDrifted(o));
  EXPECT_LT((object.anchor.a_w0 - tilted_50).norm(), 1e-12);
  EXPECT_LT((object.axis_w() - tilted_50).norm(), 1e-12);
  EXPECT_LT(object.Rotation(0).angularDistance(before), 1e-12);
}

// Three detections of a confirmed object at chain positions 1, 1.3 and
// 1.0 m along x (keyframes 0, 1, 3): levels against the running mean
// |1.3 - 1| and |1.0 - 1.15|, one increment (keyframes 0 -> 1) of 0.3.
TEST_F(ObjectMapTest, NoiseSamplesAreTakenAtTheFrontEndsPose) {
  BackendOptions options;
  options.confirm_keyframes = 1;
  options.noise_min_samples = 1;
  Build(options);
  const int o = map_->Create("box", SymmetryType::kAsymmetric, At(1, 0, 0), 0);
  map_->SampleNoise(o, 0, At(1, 0, 0), Eigen::Vector3d::Zero(), std::nullopt);
  map_->SampleNoise(
      o, 1, At(0.3, 0, 0), Eigen::Vector3d(1, 0, 0), std::nullopt);
  map_->SampleNoise(o, 3, At(1, 0, 0), Eigen::Vector3d::Zero(), std::nullopt);
  const NoiseSamplesReport report = map_->noise().TranslationReport("box");
  EXPECT_EQ(report.levels, 2);
  EXPECT_EQ(report.increments, 1);
  ASSERT_TRUE(report.sigma_increment.has_value());
  EXPECT_NEAR(
      *report.sigma_increment, 0.3 / (kChi3Median * std::sqrt(2.0)), 1e-12);
  ASSERT_TRUE(report.sigma_level.has_value());
  // The median of {0.3, 0.15}.
  EXPECT_NEAR(*report.sigma_level, 0.225 / kChi3Median, 1e-12);
  EXPECT_EQ(map_->noise().RotationReport("box").levels, 0);
}

// A detector whose position errors are an AR(1) process,
// e_k = rho e_(k-1) + sqrt(1 - rho^2) n_k, n_k ~ N(0, sigma^2 I), sigma = 5
// cm, rho = 0.8, seen from a front end without error in 6000 consecutive
// keyframes: the noise report finds sigma, the correlation rho and the
// inflation sqrt((1 + rho) / (1 - rho)) = 3 within 15 % (the last 5000
// samples, about 550 independent ones at this correlation), and the
// estimate is sigma times that inflation.
TEST_F(ObjectMapTest, AnAr1ErrorGetsItsInflation) {
  BackendOptions options;
  options.confirm_keyframes = 1;
  options.noise_window = 5000;
  Build(options);
  constexpr double kSigma = 0.05;
  constexpr double kRho = 0.8;
  const Eigen::Vector3d t_co(0.2, -0.1, 1.5);
  const int o = map_->Create("box", SymmetryType::kAsymmetric, At(0, 0, 0), 0);
  testing::TestRandom random(7);
  Eigen::Vector3d e = random.NormalVector(kSigma);
  for (int k = 0; k < 6000; ++k) {
    map_->SampleNoise(o, k, At(0, 0, 0), t_co + e, std::nullopt);
    e = kRho * e + std::sqrt(1.0 - kRho * kRho) * random.NormalVector(kSigma);
  }
  const NoiseSamplesReport report = map_->noise().TranslationReport("box");
  ASSERT_TRUE(report.sigma_level && report.sigma_increment);
  EXPECT_NEAR(*report.sigma_level, kSigma, 0.15 * kSigma);
  EXPECT_NEAR(report.correlation, kRho, 0.15 * kRho);
  const double inflation = std::sqrt((1.0 + kRho) / (1.0 - kRho));
  EXPECT_NEAR(report.inflation, inflation, 0.15 * inflation);
  const ClassNoise estimate = map_->noise().Estimate("box");
  ASSERT_TRUE(estimate.sigma_t.has_value());
  EXPECT_NEAR(*estimate.sigma_t, kSigma * inflation, 0.15 * kSigma * inflation);
}

// A step's ratio r = |d| / sqrt(2 sigma_I^2 + G) (object_track.h).
TEST(ObjectTrack, AStepsRatioIsItsChangeOverItsExpectedSpread) {
  const double sigma_increment = 0.01;
  const TrackStep gap{0.05, 4.8e-4};
  EXPECT_NEAR(
      StepRatio(gap, sigma_increment), 0.05 / std::sqrt(2e-4 + 4.8e-4), 1e-12);
  const TrackStep next{0.02, 0.0};
  EXPECT_NEAR(StepRatio(next, sigma_increment), 0.02 / std::sqrt(2e-4), 1e-12);
  const TrackStep far{0.01, 3.1e-4};
  EXPECT_NEAR(
      StepRatio(far, sigma_increment), 0.01 / std::sqrt(2e-4 + 3.1e-4), 1e-12);
  // The middle of 1.917, 1.414 and 0.443.
  EXPECT_NEAR(MedianStepRatio({gap, next, far}, sigma_increment),
              0.02 / std::sqrt(2e-4),
              1e-12);
  EXPECT_EQ(MedianStepRatio({}, sigma_increment), 0.0);
  // No spread at all: only no change is static.
  EXPECT_EQ(StepRatio({0.0, 0.0}, 0.0), 0.0);
  EXPECT_TRUE(std::isinf(StepRatio({0.01, 0.0}, 0.0)));
}

// The reference keeps the last `window` steps and takes their ratios with
// the sigma_I it is asked with.
TEST(ObjectTrack, TheReferenceIsTheMedianRatioOfTheLastSteps) {
  TrackReference reference(3);
  EXPECT_EQ(reference.Ratio(0.01), 0.0);
  for (const double change : {0.5, 0.01, 0.02, 0.03}) {
    reference.Add({change, 0.0});
  }
  EXPECT_EQ(reference.size(), 3);  // 0.5 left the ring
  EXPECT_NEAR(reference.Ratio(0.01), 0.02 / std::sqrt(2e-4), 1e-12);
  EXPECT_NEAR(reference.Ratio(0.02), 0.02 / std::sqrt(8e-4), 1e-12);
}

// A confirmed box whose detections change by 1 cm from keyframe to
// keyframe (the map's keyframes state no motion noise) gives the class its
// frame-to-frame noise sigma_I = 0.01 / (1.5382 sqrt 2) and its reference
// ratio R = 0.01 / (sqrt 2 sigma_I) = 1.5382. From keyframe 8 three new
// boxes change by 2.9 cm (ratio 4.46, within 3 R = 4.61: confirmed with
// its third keyframe), by 3.1 cm (4.77: not) and by 30 cm (46.1: not); the
// two are dropped once no detection joined them for tentative_timeout
// keyframes. With track_tolerance 0, or without estimate_noise, all three
// are confirmed.
TEST_F(ObjectMapTest, AWanderingTentativeObjectIsNotConfirmed) {
  for (int k = 0; k <= 16; ++k) {
    keyframes_.push_back(std::make_unique<KeyframeState>());
  }
  struct Case {
    double tolerance;
    bool estimate_noise;
  };
  for (const Case c : {Case{3.0, true}, Case{0.0, true}, Case{3.0, false}}) {
    SCOPED_TRACE(c.tolerance);
    SCOPED_TRACE(c.estimate_noise);
    BackendOptions options;
    options.confirm_keyframes = 3;
    options.tentative_timeout = 4;
    options.noise_min_samples = 3;
    options.track_tolerance = c.tolerance;
    options.estimate_noise = c.estimate_noise;
    statistics_ = BackendStatistics();
    assignments_.clear();
    Build(options);
    auto detect = [&](int o, int k, double x) {
      Detect(o, k);
      map_->SampleNoise(
          o, k, At(x, 0, 0), Eigen::Vector3d::Zero(), std::nullopt);
    };
    const int box =
        map_->Create("box", SymmetryType::kAsymmetric, At(0, 0, 0), 0);
    const double changes[] = {0.029, 0.031, 0.3};
    std::vector<int> boxes;
    for (int k = 0; k <= 16; ++k) {
      detect(box, k, 0.01 * (k % 2));
      if (k == 8) {
        for (int i = 0; i < 3; ++i) {
          boxes.push_back(map_->Create(
              "box", SymmetryType::kAsymmetric, At(5 * (i + 1), 0, 0), k));
        }
      }
      if (k >= 8 && k <= 10) {
        for (int i = 0; i < 3; ++i) {
          detect(boxes[i], k, 5 * (i + 1) + changes[i] * (k % 2));
        }
      }
      map_->UpdateTentative(k);
      if (k == 7 && c.estimate_noise) {
        const auto sigma_increment =
            map_->noise().TranslationIncrementSigma("box");
        ASSERT_TRUE(sigma_increment.has_value());
        EXPECT_NEAR(
            *sigma_increment, 0.01 / (kChi3Median * std::sqrt(2.0)), 1e-12);
        const auto reference =
            map_->noise().TrackRatio("box", *sigma_increment);
        ASSERT_TRUE(reference.has_value());
        EXPECT_NEAR(*reference, kChi3Median, 1e-9);
        EXPECT_NEAR(MedianStepRatio({{0.3, 0.0}}, *sigma_increment),
                    0.3 / 0.01 * kChi3Median,
                    1e-9);
      }
    }
    EXPECT_EQ(map_->objects()[boxes[0]]->status, ObjectStatus::kConfirmed);
    EXPECT_TRUE(map_->objects()[boxes[0]]->track.empty());
    if (c.tolerance > 0.0 && c.estimate_noise) {
      EXPECT_EQ(map_->objects()[boxes[1]]->status, ObjectStatus::kDropped);
      EXPECT_EQ(map_->objects()[boxes[2]]->status, ObjectStatus::kDropped);
      EXPECT_EQ(statistics_.objects, 2);
      EXPECT_EQ(statistics_.objects_dropped, 2);
    } else {
      EXPECT_EQ(map_->objects()[boxes[1]]->status, ObjectStatus::kConfirmed);
      EXPECT_EQ(map_->objects()[boxes[2]]->status, ObjectStatus::kConfirmed);
      EXPECT_EQ(statistics_.objects, 4);
    }
  }
}

}  // namespace
}  // namespace symba::internal
