// Microbenchmarks of the object cost functions (docs/performance.md, "Object
// cost functions").
//
// For each edge type (asymmetric, discrete, continuous) and N hypotheses:
//   BM_<Type>Edge/N              Evaluate with residuals and every Jacobian
//                                (what Ceres calls once per iteration)
//   BM_<Type>EdgeResidualOnly/N  Evaluate with jacobians == nullptr
//   BM_<Type>EdgeSelect/N        choosing the winner alone (doubles)
//   BM_<Type>EdgeWinnerOnly      the winner's cost function alone
//   BM_<Type>EdgeAutoDiffAll/N   reference: every component's residual in
//                                Jets, the minimum picked inside the functor
//   BM_<Type>EdgeRatios          the edge at N = 1, 30, 100 and the reference
//                                at N = 30 interleaved in one loop, timed in
//                                thread CPU time; counters give the medians
//                                and their ratios (robust to other processes)
//
// The states are realistic: a camera 2-3 m from the object looking at it,
// hypotheses a few degrees and centimetres around the true T_co, and an
// estimate slightly off the truth. All seeds are fixed.
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>
#include <ceres/autodiff_cost_function.h>
#include <ceres/cost_function.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/factors/asymmetric_object_edge.h"
#include "symba/factors/continuous_object_edge.h"
#include "symba/factors/discrete_object_edge.h"
#include "symba/factors/max_mixture.h"
#include "symba/factors/pose_component.h"
#include "symba/factors/pose_mixture.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/rigid3.h"
#include "symba/geometry/se3.h"
#include "symba/geometry/sphere_log.h"
#include "symba/geometry/tangent_basis.h"
#include "test_support/random.h"

namespace symba {
namespace {

using testing::TestRandom;
using Blocks = std::vector<std::vector<double>>;

constexpr double kDegree = kPi / 180.0;
constexpr int kMaxHypotheses = 100;

// Detector noise of the hypotheses and the estimate's distance from the truth.
constexpr double kHypothesisSigmaR = 2.0 * kDegree;
constexpr double kHypothesisSigmaT = 0.02;
constexpr double kEstimateSigmaR = 1.0 * kDegree;
constexpr double kEstimateSigmaT = 0.01;
// The whitening of the components.
constexpr double kSqrtInfoSigmaR = 3.0 * kDegree;
constexpr double kSqrtInfoSigmaT = 0.03;

void HypothesisCounts(benchmark::internal::Benchmark* b) {
  b->ArgName("N");
  for (int n : {1, 5, 10, 30, 100}) b->Arg(n);
}

// ---------------------------------------------------------------------------
// Scenes.

Eigen::Quaterniond SmallRotation(TestRandom& random, double sigma) {
  const Eigen::Vector3d w = random.NormalVector(sigma);
  const double angle = w.norm();
  if (angle == 0.0) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, w / angle));
}

Rigid3d Perturb(TestRandom& random,
                const Rigid3d& T,
                double sigma_r,
                double sigma_t) {
  return Rigid3d((SmallRotation(random, sigma_r) * T.q).normalized(),
                 T.t + random.NormalVector(sigma_t));
}

std::vector<double> Block(const Eigen::Quaterniond& q) {
  return {q.x(), q.y(), q.z(), q.w()};  // Eigen order [x, y, z, w]
}
std::vector<double> Block(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

// The true object and camera poses: the camera 2-3 m from the object, its
// optical axis (z) through the object's origin, a random roll.
struct Scene {
  Rigid3d T_wo;
  Rigid3d T_wc;
};

Scene MakeScene(TestRandom& random) {
  Scene scene;
  scene.T_wo = Rigid3d(random.Rotation(), random.NormalVector(1.0));
  const Eigen::Vector3d view = random.UnitVector();  // object -> camera
  const double distance = random.Uniform(2.0, 3.0);
  const Eigen::Quaterniond look =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), -view);
  const Eigen::Quaterniond roll(
      Eigen::AngleAxisd(random.Uniform(-kPi, kPi), Eigen::Vector3d::UnitZ()));
  scene.T_wc =
      Rigid3d((look * roll).normalized(), scene.T_wo.t + distance * view);
  return scene;
}

// Whitened cost handicap k_j = -log(w_j / sum w) - log|det L_j| of a mixture.
template <typename Component>
std::vector<double> LogNormalizers(const std::vector<Component>& components) {
  double weight_sum = 0.0;
  for (const Component& c : components) weight_sum += c.weight;
  std::vector<double> k;
  k.reserve(components.size());
  for (const Component& c : components) {
    k.push_back(-std::log(c.weight / weight_sum) -
                std::log(std::abs(c.sqrt_info.determinant())));
  }
  return k;
}

template <typename Component>
std::vector<Component> FirstN(const std::vector<Component>& all, int n) {
  return std::vector<Component>(all.begin(), all.begin() + n);
}

// ---------------------------------------------------------------------------
// Asymmetric: most hypotheses are noisy copies of the true T_co; every fifth
// one (none for N = 1) is far off (random rotation, ~20 cm).

struct AsymmetricCase {
  std::vector<PoseComponent> components;  // kMaxHypotheses
  Blocks parameters;                      // q_wc, t_wc, q_wo, t_wo
};

const AsymmetricCase& Asymmetric() {
  static const AsymmetricCase* const instance = [] {
    auto* c = new AsymmetricCase;
    TestRandom random(101);
    const Scene scene = MakeScene(random);
    const Rigid3d T_co = scene.T_wc.Inverse() * scene.T_wo;
    const Matrix6d sqrt_info =
        IsotropicPoseSqrtInfo(kSqrtInfoSigmaT, kSqrtInfoSigmaR);
    for (int j = 0; j < kMaxHypotheses; ++j) {
      Rigid3d h = Perturb(random, T_co, kHypothesisSigmaR, kHypothesisSigmaT);
      if (j % 5 == 4) {
        h = Rigid3d(random.Rotation(), T_co.t + random.NormalVector(0.2));
      }
      c->components.push_back({h, sqrt_info, random.Uniform(0.5, 1.0)});
    }
    const Rigid3d T_wc =
        Perturb(random, scene.T_wc, kEstimateSigmaR, kEstimateSigmaT);
    const Rigid3d T_wo =
        Perturb(random, scene.T_wo, kEstimateSigmaR, kEstimateSigmaT);
    c->parameters = {
        Block(T_wc.q), Block(T_wc.t), Block(T_wo.q), Block(T_wo.t)};
    return c;
  }();
  return *instance;
}

std::unique_ptr<AsymmetricObjectEdge> MakeAsymmetricEdge(int n) {
  std::unique_ptr<AsymmetricObjectEdge> edge;
  if (!CreateAsymmetricObjectEdge(
           FirstN(Asymmetric().components, n), MixtureOptions(), &edge)
           .ok()) {
    return nullptr;
  }
  return edge;
}

// Reference: every component in Jets, the most likely kept inside the functor.
class AsymmetricAutoDiffAll {
 public:
  explicit AsymmetricAutoDiffAll(std::vector<PoseComponent> components)
      : components_(std::move(components)),
        log_normalizers_(LogNormalizers(components_)) {}

  template <typename T>
  bool operator()(const T* q_wc,
                  const T* t_wc,
                  const T* q_wo,
                  const T* t_wo,
                  T* residual) const {
    const Rigid3<T> T_oc = CameraInObject(q_wc, t_wc, q_wo, t_wo);
    Vector6<T> best = Vector6<T>::Zero();
    T best_cost(std::numeric_limits<double>::infinity());
    for (size_t j = 0; j < components_.size(); ++j) {
      Vector6<T> r;
      PoseLogResidual(components_[j], T_oc, r.data());
      const T cost = T(0.5) * r.squaredNorm() + T(log_normalizers_[j]);
      if (cost < best_cost) {
        best_cost = cost;
        best = r;
      }
    }
    Eigen::Map<Vector6<T>> out(residual);
    out = best;
    return true;
  }

 private:
  std::vector<PoseComponent> components_;
  std::vector<double> log_normalizers_;
};

std::unique_ptr<ceres::CostFunction> MakeAsymmetricAutoDiffAll(int n) {
  return std::make_unique<
      ceres::AutoDiffCostFunction<AsymmetricAutoDiffAll, 6, 4, 3, 4, 3>>(
      new AsymmetricAutoDiffAll(FirstN(Asymmetric().components, n)));
}

// ---------------------------------------------------------------------------
// Discrete: a 2-fold symmetric object (symmetry angles 0 and pi about the
// object's z axis). The benchmarked edge is the one of theta = pi; its
// hypotheses are that cluster's members, noisy copies of T_co rotated by pi.

struct DiscreteCase {
  SymmetryAnchor anchor;
  std::vector<PoseComponent> components;  // kMaxHypotheses
  Blocks parameters;                      // q_wc, t_wc, t_wo, a_w, theta
};

const DiscreteCase& Discrete() {
  static const DiscreteCase* const instance = [] {
    auto* c = new DiscreteCase;
    TestRandom random(202);
    const Scene scene = MakeScene(random);
    const Eigen::Vector3d a_o = Eigen::Vector3d::UnitZ();
    c->anchor = SymmetryAnchor::FromObjectRotation(scene.T_wo.q, a_o);
    const Rigid3d T_wo_pi(
        scene.T_wo.q * Eigen::Quaterniond(Eigen::AngleAxisd(kPi, a_o)),
        scene.T_wo.t);
    const Rigid3d T_co_pi = scene.T_wc.Inverse() * T_wo_pi;
    const Matrix6d sqrt_info =
        IsotropicPoseSqrtInfo(kSqrtInfoSigmaT, kSqrtInfoSigmaR);
    for (int j = 0; j < kMaxHypotheses; ++j) {
      c->components.push_back(
          {Perturb(random, T_co_pi, kHypothesisSigmaR, kHypothesisSigmaT),
           sqrt_info,
           random.Uniform(0.5, 1.0)});
    }
    const Rigid3d T_wc =
        Perturb(random, scene.T_wc, kEstimateSigmaR, kEstimateSigmaT);
    const Eigen::Vector3d t_wo =
        scene.T_wo.t + random.NormalVector(kEstimateSigmaT);
    const Eigen::Vector3d a_w =
        (SmallRotation(random, kEstimateSigmaR) * c->anchor.a_w0).normalized();
    const double theta = kPi + random.Normal(kEstimateSigmaR);
    c->parameters = {
        Block(T_wc.q), Block(T_wc.t), Block(t_wo), Block(a_w), {theta}};
    return c;
  }();
  return *instance;
}

std::unique_ptr<DiscreteObjectEdge> MakeDiscreteEdge(int n) {
  std::unique_ptr<DiscreteObjectEdge> edge;
  if (!CreateDiscreteObjectEdge(FirstN(Discrete().components, n),
                                Discrete().anchor,
                                MixtureOptions(),
                                &edge)
           .ok()) {
    return nullptr;
  }
  return edge;
}

class DiscreteAutoDiffAll {
 public:
  DiscreteAutoDiffAll(std::vector<PoseComponent> components,
                      const SymmetryAnchor& anchor)
      : components_(std::move(components)),
        log_normalizers_(LogNormalizers(components_)),
        anchor_(anchor) {}

  template <typename T>
  bool operator()(const T* q_wc,
                  const T* t_wc,
                  const T* t_wo,
                  const T* a_w,
                  const T* theta,
                  T* residual) const {
    const Rigid3<T> T_oc =
        CameraInSymmetricObject(anchor_, q_wc, t_wc, t_wo, a_w, theta);
    Vector6<T> best = Vector6<T>::Zero();
    T best_cost(std::numeric_limits<double>::infinity());
    for (size_t j = 0; j < components_.size(); ++j) {
      Vector6<T> r;
      PoseLogResidual(components_[j], T_oc, r.data());
      const T cost = T(0.5) * r.squaredNorm() + T(log_normalizers_[j]);
      if (cost < best_cost) {
        best_cost = cost;
        best = r;
      }
    }
    Eigen::Map<Vector6<T>> out(residual);
    out = best;
    return true;
  }

 private:
  std::vector<PoseComponent> components_;
  std::vector<double> log_normalizers_;
  SymmetryAnchor anchor_;
};

std::unique_ptr<ceres::CostFunction> MakeDiscreteAutoDiffAll(int n) {
  return std::make_unique<
      ceres::AutoDiffCostFunction<DiscreteAutoDiffAll, 6, 4, 3, 3, 3, 1>>(
      new DiscreteAutoDiffAll(FirstN(Discrete().components, n),
                              Discrete().anchor));
}

// ---------------------------------------------------------------------------
// Continuous: a rotationally symmetric object (axis z in the object frame).
// The hypotheses' rotations spread around the axis, so only their
// translations are used: noisy copies of the true t_co, every fifth one (none
// for N = 1) with a depth error of up to 15 %. The measured axis is the true
// one seen from the camera, 2 degrees off.

struct ContinuousCase {
  std::vector<TranslationComponent> components;  // kMaxHypotheses
  AxisMeasurement axis;
  Blocks parameters;  // q_wc, t_wc, t_wo, a_w
};

const ContinuousCase& Continuous() {
  static const ContinuousCase* const instance = [] {
    auto* c = new ContinuousCase;
    TestRandom random(303);
    const Scene scene = MakeScene(random);
    const Eigen::Vector3d a_w_true = scene.T_wo.q * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d t_co = (scene.T_wc.Inverse() * scene.T_wo).t;
    const Eigen::Matrix3d sqrt_info =
        Eigen::Matrix3d::Identity() / kSqrtInfoSigmaT;
    for (int j = 0; j < kMaxHypotheses; ++j) {
      Eigen::Vector3d t = t_co + random.NormalVector(kHypothesisSigmaT);
      if (j % 5 == 4) t = t_co * (1.0 + random.Uniform(-0.15, 0.15));
      c->components.push_back({t, sqrt_info, random.Uniform(0.5, 1.0)});
    }
    c->axis.a_c = (SmallRotation(random, kHypothesisSigmaR) *
                   (scene.T_wc.q.conjugate() * a_w_true))
                      .normalized();
    c->axis.sqrt_info = Eigen::Matrix2d::Identity() / kSqrtInfoSigmaR;
    c->axis.gamma = 1.0;
    const Rigid3d T_wc =
        Perturb(random, scene.T_wc, kEstimateSigmaR, kEstimateSigmaT);
    const Eigen::Vector3d t_wo =
        scene.T_wo.t + random.NormalVector(kEstimateSigmaT);
    const Eigen::Vector3d a_w =
        (SmallRotation(random, kEstimateSigmaR) * a_w_true).normalized();
    c->parameters = {Block(T_wc.q), Block(T_wc.t), Block(t_wo), Block(a_w)};
    return c;
  }();
  return *instance;
}

std::unique_ptr<ContinuousObjectEdge> MakeContinuousEdge(int n) {
  std::unique_ptr<ContinuousObjectEdge> edge;
  if (!CreateContinuousObjectEdge(FirstN(Continuous().components, n),
                                  Continuous().axis,
                                  MixtureOptions(),
                                  &edge)
           .ok()) {
    return nullptr;
  }
  return edge;
}

class ContinuousAutoDiffAll {
 public:
  ContinuousAutoDiffAll(std::vector<TranslationComponent> components,
                        const AxisMeasurement& axis)
      : components_(std::move(components)),
        log_normalizers_(LogNormalizers(components_)),
        axis_(axis),
        basis_at_a_c_(TangentBasis(Eigen::Vector3d(axis.a_c.normalized()))) {
    axis_.a_c.normalize();
  }

  template <typename T>
  bool operator()(const T* q_wc,
                  const T* t_wc,
                  const T* t_wo,
                  const T* a_w,
                  T* residual) const {
    const Eigen::Quaternion<T> R_cw =
        Eigen::Map<const Eigen::Quaternion<T>>(q_wc).conjugate();
    const Vector3<T> t_co_pred = R_cw * (Eigen::Map<const Vector3<T>>(t_wo) -
                                         Eigen::Map<const Vector3<T>>(t_wc));
    Vector3<T> best = Vector3<T>::Zero();
    T best_cost(std::numeric_limits<double>::infinity());
    for (size_t j = 0; j < components_.size(); ++j) {
      const TranslationComponent& c = components_[j];
      const Vector3<T> r = c.sqrt_info.template cast<T>() *
                           (c.t_co.template cast<T>() - t_co_pred);
      const T cost = T(0.5) * r.squaredNorm() + T(log_normalizers_[j]);
      if (cost < best_cost) {
        best_cost = cost;
        best = r;
      }
    }
    const Vector3<T> a_c_pred = R_cw * Eigen::Map<const Vector3<T>>(a_w);
    Eigen::Map<Eigen::Matrix<T, 5, 1>> out(residual);
    out.template head<3>() = best;
    out.template tail<2>() =
        T(axis_.gamma) *
        (axis_.sqrt_info.template cast<T>() *
         SphereLog(Vector3<T>(axis_.a_c.template cast<T>()),
                   Eigen::Matrix<T, 3, 2>(basis_at_a_c_.template cast<T>()),
                   a_c_pred));
    return true;
  }

 private:
  std::vector<TranslationComponent> components_;
  std::vector<double> log_normalizers_;
  AxisMeasurement axis_;
  Eigen::Matrix<double, 3, 2> basis_at_a_c_;
};

std::unique_ptr<ceres::CostFunction> MakeContinuousAutoDiffAll(int n) {
  return std::make_unique<
      ceres::AutoDiffCostFunction<ContinuousAutoDiffAll, 5, 4, 3, 3, 3>>(
      new ContinuousAutoDiffAll(FirstN(Continuous().components, n),
                                Continuous().axis));
}

// ---------------------------------------------------------------------------
// Evaluation harness.

double ThreadCpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) +
         1e-9 * static_cast<double>(ts.tv_nsec);
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// One cost function with its parameters and output buffers, evaluated the way
// Ceres does (every parameter block variable, ambient-size Jacobians).
class Evaluator {
 public:
  Evaluator(std::unique_ptr<ceres::CostFunction> cost,
            const Blocks& parameters,
            bool with_jacobians)
      : cost_(std::move(cost)),
        parameters_(parameters),
        residuals_(cost_->num_residuals()) {
    const std::vector<int32_t>& sizes = cost_->parameter_block_sizes();
    for (const std::vector<double>& block : parameters_) {
      parameter_ptrs_.push_back(block.data());
    }
    if (with_jacobians) {
      for (int32_t size : sizes) {
        jacobians_.emplace_back(cost_->num_residuals() * size);
      }
      for (std::vector<double>& jacobian : jacobians_) {
        jacobian_ptrs_.push_back(jacobian.data());
      }
    }
  }

  bool Evaluate() {
    return cost_->Evaluate(
        parameter_ptrs_.data(),
        residuals_.data(),
        jacobian_ptrs_.empty() ? nullptr : jacobian_ptrs_.data());
  }

  // Thread CPU seconds for `count` evaluations (time when other processes
  // run on this core is not counted).
  double CpuTime(int count) {
    const double start = ThreadCpuSeconds();
    for (int i = 0; i < count; ++i) {
      benchmark::DoNotOptimize(Evaluate());
      benchmark::ClobberMemory();
    }
    return ThreadCpuSeconds() - start;
  }

 private:
  std::unique_ptr<ceres::CostFunction> cost_;
  Blocks parameters_;
  std::vector<const double*> parameter_ptrs_;
  std::vector<double> residuals_;
  std::vector<std::vector<double>> jacobians_;
  std::vector<double*> jacobian_ptrs_;
};

void RunEvaluate(benchmark::State& state,
                 std::unique_ptr<ceres::CostFunction> cost,
                 const Blocks& parameters,
                 bool with_jacobians) {
  if (cost == nullptr) {
    state.SkipWithError("could not create the cost function");
    return;
  }
  Evaluator evaluator(std::move(cost), parameters, with_jacobians);
  if (!evaluator.Evaluate()) {
    state.SkipWithError("Evaluate failed");
    return;
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(evaluator.Evaluate());
    benchmark::ClobberMemory();
  }
}

template <typename Edge>
void RunSelect(benchmark::State& state,
               std::unique_ptr<Edge> edge,
               const Blocks& parameters) {
  std::vector<const double*> ptrs;
  for (const std::vector<double>& block : parameters)
    ptrs.push_back(block.data());
  MixtureSelection selection;
  if (edge == nullptr || !edge->Select(ptrs.data(), &selection)) {
    state.SkipWithError("Select failed");
    return;
  }
  state.counters["winner"] = selection.component;
  for (auto _ : state) {
    benchmark::DoNotOptimize(edge->Select(ptrs.data(), &selection));
    benchmark::ClobberMemory();
  }
}

// The winner's own autodiff cost function, evaluated through a non-owning
// wrapper so that the Evaluator can hold it.
class Borrowed final : public ceres::CostFunction {
 public:
  explicit Borrowed(const ceres::CostFunction& cost) : cost_(cost) {
    set_num_residuals(cost.num_residuals());
    *mutable_parameter_block_sizes() = cost.parameter_block_sizes();
  }
  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    return cost_.Evaluate(parameters, residuals, jacobians);
  }

 private:
  const ceres::CostFunction& cost_;
};

template <typename Edge>
void RunWinnerOnly(benchmark::State& state,
                   std::unique_ptr<Edge> edge,
                   const Blocks& parameters) {
  std::vector<const double*> ptrs;
  for (const std::vector<double>& block : parameters)
    ptrs.push_back(block.data());
  MixtureSelection selection;
  if (edge == nullptr || !edge->Select(ptrs.data(), &selection)) {
    state.SkipWithError("Select failed");
    return;
  }
  RunEvaluate(
      state,
      std::make_unique<Borrowed>(edge->model().Component(selection.component)),
      parameters,
      true);
}

// Interleaves the edge at N = 1, 30 and 100 and the autodiff-everything
// reference at N = 30 in batches timed in thread CPU time, and reports the
// medians over batches, per evaluation (n1_ns, n30_ns, n100_ns,
// autodiff30_ns) and as ratios:
//   n30_over_n1, n100_over_n1   the real edge at N = 30, 100 over N = 1
//   autodiff30_over_n30         the reference over the real edge at N = 30
// Interleaving makes the ratios robust to load from other processes.
using Factory = std::unique_ptr<ceres::CostFunction> (*)(int);

void RunRatios(benchmark::State& state,
               Factory edge,
               Factory autodiff_all,
               const Blocks& parameters) {
  for (int n : {1, 30, 100}) {
    if (edge(n) == nullptr || autodiff_all(n) == nullptr) {
      state.SkipWithError("could not create the cost functions");
      return;
    }
  }
  Evaluator n1(edge(1), parameters, true);
  Evaluator n30(edge(30), parameters, true);
  Evaluator n100(edge(100), parameters, true);
  Evaluator autodiff30(autodiff_all(30), parameters, true);
  constexpr int kBatch = 16;
  std::vector<double> t1;
  std::vector<double> t30;
  std::vector<double> t100;
  std::vector<double> t_autodiff30;
  for (auto _ : state) {
    t1.push_back(n1.CpuTime(kBatch));
    t30.push_back(n30.CpuTime(kBatch));
    t100.push_back(n100.CpuTime(kBatch));
    t_autodiff30.push_back(autodiff30.CpuTime(kBatch));
  }
  const double m1 = Median(t1);
  const double m30 = Median(t30);
  const double m100 = Median(t100);
  const double m_autodiff30 = Median(t_autodiff30);
  constexpr double kNsPerEvaluation = 1e9 / kBatch;
  state.counters["n1_ns"] = m1 * kNsPerEvaluation;
  state.counters["n30_ns"] = m30 * kNsPerEvaluation;
  state.counters["n100_ns"] = m100 * kNsPerEvaluation;
  state.counters["autodiff30_ns"] = m_autodiff30 * kNsPerEvaluation;
  state.counters["n30_over_n1"] = m30 / m1;
  state.counters["n100_over_n1"] = m100 / m1;
  state.counters["autodiff30_over_n30"] = m_autodiff30 / m30;
}

template <typename Edge>
std::unique_ptr<ceres::CostFunction> AsCostFunction(
    std::unique_ptr<Edge> edge) {
  return edge;
}

std::unique_ptr<ceres::CostFunction> AsymmetricEdgeCost(int n) {
  return AsCostFunction(MakeAsymmetricEdge(n));
}
std::unique_ptr<ceres::CostFunction> DiscreteEdgeCost(int n) {
  return AsCostFunction(MakeDiscreteEdge(n));
}
std::unique_ptr<ceres::CostFunction> ContinuousEdgeCost(int n) {
  return AsCostFunction(MakeContinuousEdge(n));
}

// ---------------------------------------------------------------------------
// The benchmarks every object edge gets, named BM_<name>Edge<suffix>:
//   (none)        evaluation with Jacobians, N = 1 .. 100
//   ResidualOnly  evaluation without Jacobians, N = 30
//   Select        picking the winner in doubles, N = 1 .. 100
//   WinnerOnly    the winning component alone, N = 30
//   AutoDiffAll   the autodiff-everything reference, N = 1 .. 100
//   Ratios        interleaved ratios (RunRatios)

using ParametersOf = const Blocks& (*)();

template <typename Edge>
void RegisterEdgeBenchmarks(const std::string& name,
                            std::unique_ptr<Edge> (*make_edge)(int),
                            Factory edge_cost,
                            Factory autodiff_all,
                            ParametersOf parameters) {
  const std::string prefix = "BM_" + name + "Edge";
  const auto n = [](const benchmark::State& state) {
    return static_cast<int>(state.range(0));
  };
  benchmark::RegisterBenchmark(prefix.c_str(), [=](benchmark::State& state) {
    RunEvaluate(state, edge_cost(n(state)), parameters(), true);
  })->Apply(HypothesisCounts);
  benchmark::RegisterBenchmark(
      (prefix + "ResidualOnly").c_str(),
      [=](benchmark::State& state) {
        RunEvaluate(state, edge_cost(n(state)), parameters(), false);
      })
      ->ArgName("N")
      ->Arg(30);
  benchmark::RegisterBenchmark((prefix + "Select").c_str(),
                               [=](benchmark::State& state) {
                                 RunSelect(
                                     state, make_edge(n(state)), parameters());
                               })
      ->Apply(HypothesisCounts);
  benchmark::RegisterBenchmark(
      (prefix + "WinnerOnly").c_str(), [=](benchmark::State& state) {
        RunWinnerOnly(state, make_edge(30), parameters());
      });
  benchmark::RegisterBenchmark(
      (prefix + "AutoDiffAll").c_str(),
      [=](benchmark::State& state) {
        RunEvaluate(state, autodiff_all(n(state)), parameters(), true);
      })
      ->Apply(HypothesisCounts);
  benchmark::RegisterBenchmark(
      (prefix + "Ratios").c_str(), [=](benchmark::State& state) {
        RunRatios(state, edge_cost, autodiff_all, parameters());
      });
}

bool RegisterObjectEdgeBenchmarks() {
  RegisterEdgeBenchmarks(
      "Asymmetric",
      MakeAsymmetricEdge,
      AsymmetricEdgeCost,
      MakeAsymmetricAutoDiffAll,
      []() -> const Blocks& { return Asymmetric().parameters; });
  RegisterEdgeBenchmarks(
      "Discrete",
      MakeDiscreteEdge,
      DiscreteEdgeCost,
      MakeDiscreteAutoDiffAll,
      []() -> const Blocks& { return Discrete().parameters; });
  RegisterEdgeBenchmarks(
      "Continuous",
      MakeContinuousEdge,
      ContinuousEdgeCost,
      MakeContinuousAutoDiffAll,
      []() -> const Blocks& { return Continuous().parameters; });
  return true;
}

const bool kObjectEdgeBenchmarksRegistered = RegisterObjectEdgeBenchmarks();

}  // namespace
}  // namespace symba
