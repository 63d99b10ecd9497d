#include "symba/matching/constellation_match.h"

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "symba/geometry/pi.h"

namespace symba {
namespace {

using Eigen::AngleAxisd;
using Eigen::Quaterniond;
using Eigen::Vector3d;

MapObjectEstimate Asymmetric(ObjectId id,
                             const std::string& class_name,
                             const Vector3d& t,
                             double yaw) {
  MapObjectEstimate object;
  object.id = id;
  object.class_name = class_name;
  object.symmetry = SymmetryType::kAsymmetric;
  object.t_wo = t;
  object.poses = {Rigid3d(Quaterniond(AngleAxisd(yaw, Vector3d::UnitZ())), t)};
  return object;
}

// An order-fold object about its z axis: one pose per angle 2 pi k / order.
MapObjectEstimate Discrete(ObjectId id,
                           const std::string& class_name,
                           const Vector3d& t,
                           double yaw,
                           int order) {
  MapObjectEstimate object;
  object.id = id;
  object.class_name = class_name;
  object.symmetry = SymmetryType::kDiscrete;
  object.t_wo = t;
  object.axis_o = Vector3d::UnitZ();
  object.axis_w = Vector3d::UnitZ();
  for (int k = 0; k < order; ++k) {
    const double angle = 2.0 * kPi * k / order;
    object.angles.push_back(angle);
    object.poses.emplace_back(
        Quaterniond(AngleAxisd(yaw + angle, Vector3d::UnitZ())), t);
  }
  return object;
}

MapObjectEstimate Continuous(ObjectId id,
                             const std::string& class_name,
                             const Vector3d& t) {
  MapObjectEstimate object;
  object.id = id;
  object.class_name = class_name;
  object.symmetry = SymmetryType::kContinuous;
  object.t_wo = t;
  object.axis_o = Vector3d::UnitZ();
  object.axis_w = Vector3d::UnitZ();
  object.poses = {Rigid3d(Quaterniond::Identity(), t)};
  return object;
}

// The object as seen from a frame where the world is T_local_map.
MapObjectEstimate Moved(const MapObjectEstimate& object,
                        const Rigid3d& T_local_map,
                        ObjectId id) {
  MapObjectEstimate moved = object;
  moved.id = id;
  moved.t_wo = T_local_map * object.t_wo;
  moved.axis_w = T_local_map.q * object.axis_w;
  for (Rigid3d& pose : moved.poses) pose = T_local_map * pose;
  return moved;
}

// A room: a chair, a two-fold table, a round table, a mug and a second
// chair (ids 10..14).
std::vector<MapObjectEstimate> Room(const Vector3d& offset = Vector3d::Zero(),
                                    ObjectId first_id = 10) {
  return {
      Asymmetric(first_id, "chair", offset + Vector3d(1.0, 0.5, 0.0), 0.3),
      Discrete(first_id + 1, "table", offset + Vector3d(0.0, 0.0, 0.0), 0.2, 2),
      Continuous(
          first_id + 2, "round_table", offset + Vector3d(-1.5, 1.0, 0.0)),
      Asymmetric(first_id + 3, "mug", offset + Vector3d(0.1, 0.0, 0.8), -1.0),
      Asymmetric(
          first_id + 4, "chair", offset + Vector3d(-1.0, -0.6, 0.0), 2.0)};
}

const Rigid3d kTLocalMap(Quaterniond(AngleAxisd(2.1, Vector3d::UnitZ()) *
                                     AngleAxisd(0.05, Vector3d::UnitX())),
                         Vector3d(4.0, -3.0, 0.2));

// The room seen from kTLocalMap with ids 100.. in reverse order and a few
// millimetres and milliradians of noise.
std::vector<MapObjectEstimate> LocalRoom(
    const std::vector<MapObjectEstimate>& map) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.005);
  std::vector<MapObjectEstimate> local;
  for (auto it = map.rbegin(); it != map.rend(); ++it) {
    MapObjectEstimate object =
        Moved(*it, kTLocalMap, 100 + static_cast<ObjectId>(local.size()));
    object.t_wo += Vector3d(noise(rng), noise(rng), noise(rng));
    const Quaterniond turn(AngleAxisd(noise(rng), Vector3d::UnitZ()));
    for (Rigid3d& pose : object.poses) pose.q = turn * pose.q;
    local.push_back(object);
  }
  return local;
}

void ExpectTransform(const ConstellationMatch& match,
                     const Rigid3d& expected,
                     double position_tolerance,
                     double angle_tolerance) {
  EXPECT_LT(match.T_map_local.q.angularDistance(expected.q), angle_tolerance);
  EXPECT_LT((match.T_map_local.t - expected.t).norm(), position_tolerance);
}

TEST(ConstellationMatch, RecoversAKnownTransformAndEveryCorrespondence) {
  const std::vector<MapObjectEstimate> map = Room();
  const ConstellationMatchResult result =
      MatchConstellation(LocalRoom(map), map);
  ASSERT_EQ(result.outcome, ConstellationMatchResult::Outcome::kMatched)
      << ToString(result.outcome);
  ASSERT_TRUE(result.match);
  // Local ids 100..104 are the map's 14..10.
  ASSERT_EQ(result.match->correspondences.size(), 5u);
  for (const ObjectCorrespondence& c : result.match->correspondences) {
    EXPECT_EQ(c.map, 114 - c.local) << c.local;
  }
  ExpectTransform(*result.match, kTLocalMap.Inverse(), 0.02, 0.01);
  EXPECT_LT(result.match->position_rmse, 0.02);
  EXPECT_EQ(result.runner_up_support, 0);
}

TEST(ConstellationMatch, LeavesOutAnObjectTheMapDoesNotHave) {
  const std::vector<MapObjectEstimate> map = Room();
  std::vector<MapObjectEstimate> local = LocalRoom(map);
  // A third chair 2 m from where any chair is.
  local.push_back(Moved(
      Asymmetric(0, "chair", Vector3d(2.5, 2.5, 0.0), 1.0), kTLocalMap, 200));
  const ConstellationMatchResult result = MatchConstellation(local, map);
  ASSERT_EQ(result.outcome, ConstellationMatchResult::Outcome::kMatched);
  EXPECT_EQ(result.match->correspondences.size(), 5u);
  for (const ObjectCorrespondence& c : result.match->correspondences) {
    EXPECT_NE(c.local, 200);
  }
}

TEST(ConstellationMatch, ADiscreteObjectMatchesWhicheverOfItsPosesItShows) {
  // Table and two round tables only: the table's yaw, known modulo pi,
  // plus the round tables' positions fix the transform.
  const std::vector<MapObjectEstimate> map = {
      Discrete(1, "table", Vector3d(0.0, 0.0, 0.0), 0.2, 2),
      Continuous(2, "round_table", Vector3d(2.0, 0.0, 0.0)),
      Continuous(3, "round_table", Vector3d(0.5, 1.5, 0.0))};
  std::vector<MapObjectEstimate> local;
  for (const MapObjectEstimate& object : map) {
    local.push_back(Moved(object, kTLocalMap, object.id + 10));
  }
  // The local table's poses listed from its other angle.
  std::swap(local[0].poses[0], local[0].poses[1]);
  ConstellationMatchOptions options;
  options.symmetry_orders = {{"table", 2}};
  const ConstellationMatchResult result =
      MatchConstellation(local, map, options);
  ASSERT_EQ(result.outcome, ConstellationMatchResult::Outcome::kMatched);
  ExpectTransform(*result.match, kTLocalMap.Inverse(), 1e-6, 1e-6);
}

TEST(ConstellationMatch, AxesAreLinesWhoseSignNoRunAgreesOn) {
  // Four round tables, every local axis pointing down: the same place.
  // (The first three make a triangle whose sides differ by more than the
  // gates: turned over, it could not be told apart from its mirror image.)
  std::vector<MapObjectEstimate> map = {
      Continuous(1, "round_table", Vector3d(0.0, 0.0, 0.0)),
      Continuous(2, "round_table", Vector3d(4.0, 0.0, 0.0)),
      Continuous(3, "round_table", Vector3d(1.0, 2.0, 0.0)),
      Continuous(4, "round_table", Vector3d(-1.0, 3.0, 0.0))};
  std::vector<MapObjectEstimate> local;
  for (const MapObjectEstimate& object : map) {
    local.push_back(Moved(object, kTLocalMap, object.id + 10));
    local.back().axis_w = -local.back().axis_w;
  }
  ConstellationMatchResult result = MatchConstellation(local, map);
  ASSERT_EQ(result.outcome, ConstellationMatchResult::Outcome::kMatched)
      << ToString(result.outcome);
  ExpectTransform(*result.match, kTLocalMap.Inverse(), 1e-6, 1e-6);
  // One flipped among three.
  local.resize(3);
  local[0].axis_w = -local[0].axis_w;
  map.resize(3);
  result = MatchConstellation(local, map);
  ASSERT_EQ(result.outcome, ConstellationMatchResult::Outcome::kMatched);
  ExpectTransform(*result.match, kTLocalMap.Inverse(), 1e-6, 1e-6);
}

TEST(ConstellationMatch, AKnownOrderMakesOnePoseStandForTheWholeGroup) {
  // Three four-fold tables, each with the one pose its run anchored it at
  // (a class prior folds every view onto it); the local ones anchored a
  // quarter turn, a half turn and no turn away from the map's.
  std::vector<MapObjectEstimate> map;
  std::vector<MapObjectEstimate> local;
  const std::vector<Vector3d> at = {Vector3d(0.0, 0.0, 0.0),
                                    Vector3d(2.0, 0.5, 0.0),
                                    Vector3d(0.5, 2.0, 0.0)};
  for (int i = 0; i < 3; ++i) {
    map.push_back(
        Discrete(i, "square_table", at[static_cast<size_t>(i)], 0.3 * i, 1));
    MapObjectEstimate seen = Discrete(10 + i,
                                      "square_table",
                                      at[static_cast<size_t>(i)],
                                      0.3 * i + 0.5 * kPi * i,
                                      1);
    local.push_back(Moved(seen, kTLocalMap, 10 + i));
  }
  ConstellationMatchOptions options;
  options.symmetry_orders = {{"square_table", 4}};
  const ConstellationMatchResult result =
      MatchConstellation(local, map, options);
  ASSERT_EQ(result.outcome, ConstellationMatchResult::Outcome::kMatched)
      << ToString(result.outcome);
  EXPECT_EQ(result.match->correspondences.size(), 3u);
  ExpectTransform(*result.match, kTLocalMap.Inverse(), 1e-6, 1e-6);
}

TEST(ConstellationMatch, ObjectsInALineWithAxesAcrossItDetermineTheRotation) {
  // Round tables along a corridor, 0, 8 and 20 m: the positions fix all
  // but the rotation about the corridor, the vertical axes fix that.
  const std::vector<MapObjectEstimate> map = {
      Continuous(1, "round_table", Vector3d(0.0, 0.0, 0.0)),
      Continuous(2, "round_table", Vector3d(8.0, 0.0, 0.0)),
      Continuous(3, "round_table", Vector3d(20.0, 0.0, 0.0))};
  std::vector<MapObjectEstimate> local;
  for (const MapObjectEstimate& object : map) {
    local.push_back(Moved(object, kTLocalMap, object.id + 10));
  }
  const ConstellationMatchResult result = MatchConstellation(local, map);
  ASSERT_EQ(result.outcome, ConstellationMatchResult::Outcome::kMatched)
      << ToString(result.outcome);
  ExpectTransform(*result.match, kTLocalMap.Inverse(), 1e-6, 1e-6);
}

TEST(ConstellationMatch, ATruncatedSearchMatchesNothing) {
  const std::vector<MapObjectEstimate> map = Room();
  ConstellationMatchOptions options;
  options.min_support = 1;
  options.max_cliques = 1;
  const ConstellationMatchResult result =
      MatchConstellation(LocalRoom(map), map, options);
  EXPECT_EQ(result.outcome, ConstellationMatchResult::Outcome::kTooManyCliques);
  EXPECT_FALSE(result.match.has_value());
}

TEST(ConstellationMatch, ARoundTableGivesNoYaw) {
  // One round table and one mug above it on its axis: the rotation about
  // that axis is free, so there is no match whatever the support rule.
  const std::vector<MapObjectEstimate> map = {
      Continuous(1, "round_table", Vector3d(0.0, 0.0, 0.0)),
      Continuous(2, "bowl", Vector3d(0.0, 0.0, 0.8))};
  std::vector<MapObjectEstimate> local;
  for (const MapObjectEstimate& object : map) {
    local.push_back(Moved(object, kTLocalMap, object.id + 10));
  }
  ConstellationMatchOptions options;
  options.min_support = 2;
  EXPECT_EQ(MatchConstellation(local, map, options).outcome,
            ConstellationMatchResult::Outcome::kNoConsistentSet);
}

TEST(ConstellationMatch, ATwoFoldArrangementGivesTwoYawsUntilAChairBreaksIt) {
  // A two-fold table between two round tables: turning the place by pi
  // about the table maps it onto itself, so two transforms explain all
  // three objects.
  std::vector<MapObjectEstimate> map = {
      Discrete(1, "table", Vector3d(0.0, 0.0, 0.0), 0.0, 2),
      Continuous(2, "round_table", Vector3d(1.5, 0.0, 0.0)),
      Continuous(3, "round_table", Vector3d(-1.5, 0.0, 0.0))};
  std::vector<MapObjectEstimate> local;
  for (const MapObjectEstimate& object : map) {
    local.push_back(Moved(object, kTLocalMap, object.id + 10));
  }
  const ConstellationMatchResult symmetric = MatchConstellation(local, map);
  EXPECT_EQ(symmetric.outcome, ConstellationMatchResult::Outcome::kAmbiguous);
  EXPECT_EQ(symmetric.runner_up_support, 3);
  // A chair beside the table tells the two apart.
  map.push_back(Asymmetric(4, "chair", Vector3d(0.0, 1.0, 0.0), 0.5));
  local.push_back(Moved(map.back(), kTLocalMap, 14));
  const ConstellationMatchResult broken = MatchConstellation(local, map);
  ASSERT_EQ(broken.outcome, ConstellationMatchResult::Outcome::kMatched);
  ExpectTransform(*broken.match, kTLocalMap.Inverse(), 1e-6, 1e-6);
  EXPECT_EQ(broken.match->correspondences.size(), 4u);
}

TEST(ConstellationMatch, TwoPlacesWithTheSameArrangementAreNotMatched) {
  // The same room twice, 10 m apart and turned: seen once, it could be
  // either.
  std::vector<MapObjectEstimate> map = Room();
  const Rigid3d T_second(Quaterniond(AngleAxisd(1.0, Vector3d::UnitZ())),
                         Vector3d(10.0, 0.0, 0.0));
  for (const MapObjectEstimate& object : Room()) {
    map.push_back(Moved(object, T_second, object.id + 20));
  }
  const std::vector<MapObjectEstimate> local = LocalRoom(Room());
  const ConstellationMatchResult aliased = MatchConstellation(local, map);
  EXPECT_EQ(aliased.outcome, ConstellationMatchResult::Outcome::kAmbiguous);
  EXPECT_EQ(aliased.runner_up_support, 5);
  // A lamp only the first room has settles it.
  map.push_back(Asymmetric(50, "lamp", Vector3d(2.0, -1.0, 0.0), 0.0));
  std::vector<MapObjectEstimate> local_with_lamp = local;
  local_with_lamp.push_back(Moved(map.back(), kTLocalMap, 150));
  const ConstellationMatchResult settled =
      MatchConstellation(local_with_lamp, map);
  ASSERT_EQ(settled.outcome, ConstellationMatchResult::Outcome::kMatched);
  ExpectTransform(*settled.match, kTLocalMap.Inverse(), 0.02, 0.01);
  EXPECT_EQ(settled.runner_up_support, 5);
}

TEST(ConstellationMatch, WrongArrangementsAndClassesAreNotMatched) {
  const std::vector<MapObjectEstimate> map = Room();
  std::vector<MapObjectEstimate> stretched = LocalRoom(map);
  for (MapObjectEstimate& object : stretched) object.t_wo *= 1.6;
  EXPECT_NE(MatchConstellation(stretched, map).outcome,
            ConstellationMatchResult::Outcome::kMatched);
  std::vector<MapObjectEstimate> renamed = LocalRoom(map);
  for (MapObjectEstimate& object : renamed) object.class_name += "_other";
  EXPECT_EQ(MatchConstellation(renamed, map).outcome,
            ConstellationMatchResult::Outcome::kTooFewCandidates);
}

TEST(ConstellationMatch, CovariancesWidenTheGates) {
  const std::vector<MapObjectEstimate> map = Room();
  std::vector<MapObjectEstimate> local = LocalRoom(map);
  local[2].t_wo += Vector3d(0.4, 0.0, 0.0);  // the round table, 40 cm off
  ConstellationMatchResult result = MatchConstellation(local, map);
  ASSERT_EQ(result.outcome, ConstellationMatchResult::Outcome::kMatched);
  EXPECT_EQ(result.match->correspondences.size(), 4u);
  MapObjectCovariance uncertain;
  uncertain.position = Eigen::Matrix3d::Identity() * 0.2 * 0.2;
  local[2].covariance = uncertain;
  result = MatchConstellation(local, map);
  ASSERT_EQ(result.outcome, ConstellationMatchResult::Outcome::kMatched);
  EXPECT_EQ(result.match->correspondences.size(), 5u);
}

}  // namespace
}  // namespace symba
