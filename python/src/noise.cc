// What the backend believed of the noise: each class's detection noise
// (ClassNoise, with its NoiseSamples, HypothesisScatter, NoiseClaims and
// EdgeWeights) and
// the camera's motion noise (MotionNoise, with a MotionClaimGroup per group
// of steps the front end stated alike). The attributes carry the C++ names
// of symba/backend/estimates.h; summary.json's "noise" and "motion" hold
// the same numbers (docs/replay.md).
#include "bindings.h"
#include "repr.h"
#include "symba/backend/covariance_noise.h"
#include "symba/backend/estimates.h"

namespace symba::python {

namespace {

void BindClassNoise(py::module_& m) {
  using Samples = ClassNoiseEstimate::Samples;
  py::class_<Samples>(m,
                      "NoiseSamples",
                      "The samples behind one part (translation m, rotation "
                      "rad) of a class's noise estimate.")
      .def_readonly("levels", &Samples::levels)
      .def_readonly("increments", &Samples::increments)
      .def_readonly(
          "sigma_level", &Samples::sigma_level, "None below noise_min_samples.")
      .def_readonly("sigma_increment",
                    &Samples::sigma_increment,
                    "None below noise_min_samples.")
      .def_readonly("correlation",
                    &Samples::correlation,
                    "rho: the correlation of consecutive errors.")
      .def_readonly(
          "inflation", &Samples::inflation, "sqrt((1 + rho) / (1 - rho)).")
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(self,
                             "NoiseSamples",
                             {"levels",
                              "increments",
                              "sigma_level",
                              "sigma_increment",
                              "correlation",
                              "inflation"});
      });

  using Scatter = ClassNoiseEstimate::Scatter;
  py::class_<Scatter>(m,
                      "HypothesisScatter",
                      "The class's detections weighed by their hypotheses' "
                      "scatter: how many, and the medians of their sigmas.")
      .def_readonly("detections", &Scatter::detections)
      .def_readonly("sigma_t", &Scatter::sigma_t, "m, or None.")
      .def_readonly("sigma_r", &Scatter::sigma_r, "rad, or None.")
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(
            self, "HypothesisScatter", {"detections", "sigma_t", "sigma_r"});
      });

  using Claims = ClassNoiseEstimate::Claims;
  py::class_<Claims>(m,
                     "NoiseClaims",
                     "The test of the sigmas the class's detections declare: "
                     "the pairs behind it, the scales (None below "
                     "noise_min_samples) and the factors the claims were last "
                     "weighed with (1: as claimed).")
      .def_readonly("translation_samples", &Claims::translation_samples)
      .def_readonly("rotation_samples", &Claims::rotation_samples)
      .def_readonly("scale_t", &Claims::scale_t)
      .def_readonly("scale_r", &Claims::scale_r)
      .def_readonly("factor_t", &Claims::factor_t)
      .def_readonly("factor_r", &Claims::factor_r)
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(self,
                             "NoiseClaims",
                             {"translation_samples",
                              "rotation_samples",
                              "scale_t",
                              "scale_r",
                              "factor_t",
                              "factor_r"});
      });

  using Weights = ClassNoiseEstimate::Weights;
  py::class_<Weights>(m,
                      "EdgeWeights",
                      "What the edges of the class's confirmed objects "
                      "weighed its detections with, each as last built: how "
                      "many are of detections that declare a sigma, are "
                      "weighed by their hypotheses' scatter or state "
                      "neither, and the medians of their sigmas.")
      .def_readonly("declared", &Weights::declared)
      .def_readonly("scatter", &Weights::scatter)
      .def_readonly("unstated", &Weights::unstated)
      .def_readonly("sigma_t", &Weights::sigma_t, "m, or None.")
      .def_readonly("sigma_r", &Weights::sigma_r, "rad, or None.")
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(
            self,
            "EdgeWeights",
            {"declared", "scatter", "unstated", "sigma_t", "sigma_r"});
      });

  using C = ClassNoiseEstimate;
  py::class_<C>(m,
                "ClassNoise",
                "One class's detection noise as the backend estimated it and "
                "what it weighs the class's detections without a sigma with "
                "(docs/backend.md, Real detectors).")
      .def_readonly("class_name", &C::class_name)
      .def_readonly("sigma_t",
                    &C::sigma_t,
                    "The estimate (m), or None until there are "
                    "noise_min_samples levels.")
      .def_readonly("sigma_r", &C::sigma_r, "The estimate (rad), or None.")
      .def_readonly("weight_sigma_t",
                    &C::weight_sigma_t,
                    "m: what a detection of the class without a sigma is "
                    "weighed with.")
      .def_readonly("weight_sigma_r", &C::weight_sigma_r, "rad: likewise.")
      .def_readonly("translation", &C::translation, "NoiseSamples (m).")
      .def_readonly("rotation", &C::rotation, "NoiseSamples (rad).")
      .def_readonly("scatter", &C::scatter, "HypothesisScatter.")
      .def_readonly("claims", &C::claims, "NoiseClaims.")
      .def_readonly("track_ratio",
                    &C::track_ratio,
                    "The median step ratio of the class's confirmed objects "
                    "that a tentative object's track is compared with "
                    "(options.track_tolerance), or None.")
      .def_readonly("weights",
                    &C::weights,
                    "EdgeWeights: what the class's edges were last built with.")
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(self,
                             "ClassNoise",
                             {"class_name",
                              "sigma_t",
                              "sigma_r",
                              "weight_sigma_t",
                              "weight_sigma_r",
                              "track_ratio",
                              "weights"});
      });
}

void BindMotionNoise(py::module_& m) {
  using G = MotionNoiseReport::Group;
  py::class_<G>(m,
                "MotionClaimGroup",
                "The camera steps the front end stated alike, tested by the "
                "objects: the stated sigmas, the pairs that tested them, the "
                "scale (None below noise_min_samples) and the factor the "
                "steps' sigmas were last multiplied by (1: as stated).")
      .def_readonly("stated_sigma_t", &G::stated_sigma_t, "m.")
      .def_readonly("stated_sigma_r", &G::stated_sigma_r, "rad.")
      .def_readonly("pairs", &G::pairs)
      .def_readonly("scale", &G::scale)
      .def_readonly("factor", &G::factor)
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(
            self,
            "MotionClaimGroup",
            {"stated_sigma_t", "stated_sigma_r", "pairs", "scale", "factor"});
      });

  using R = MotionNoiseReport;
  py::class_<R>(m,
                "MotionNoise",
                "What the backend weighs the camera's motion with: the steps "
                "tied by odometry and by the front end's poses, the medians "
                "of their stated sigmas (None without such steps), and the "
                "objects' test of the statements (claims: MotionClaimGroup "
                "per group).")
      .def_readonly("odometry_steps", &R::odometry_steps)
      .def_readonly("odometry_sigma_t", &R::odometry_sigma_t, "m, or None.")
      .def_readonly("odometry_sigma_r", &R::odometry_sigma_r, "rad, or None.")
      .def_readonly("frontend_steps", &R::frontend_steps)
      .def_readonly("frontend_sigma_t", &R::frontend_sigma_t, "m, or None.")
      .def_readonly("frontend_sigma_r", &R::frontend_sigma_r, "rad, or None.")
      .def_readonly("claims", &R::claims)
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(self,
                             "MotionNoise",
                             {"odometry_steps",
                              "odometry_sigma_t",
                              "odometry_sigma_r",
                              "frontend_steps",
                              "frontend_sigma_t",
                              "frontend_sigma_r",
                              "claims"});
      });
}

void BindCovarianceNoise(py::module_& m) {
  using G = CovarianceNoiseGroup;
  py::class_<G>(m,
                "CovarianceNoiseGroup",
                "A group of the keyframe graph's edges as the covariances "
                "took its noise (docs/backend.md, Covariances): the mean "
                "squared whitened residual per degree of freedom and the "
                "correlation of consecutive residuals (translation, "
                "rotation), whether something else held the estimate, and "
                "the variance factors applied (1: as stated).")
      .def_readonly("name", &G::name)
      .def_readonly("edges", &G::edges)
      .def_readonly("residuals", &G::residuals)
      .def_readonly("held_by_others", &G::held_by_others)
      .def_readonly("residual_t", &G::residual_t)
      .def_readonly("residual_r", &G::residual_r)
      .def_readonly("correlation_t", &G::correlation_t)
      .def_readonly("correlation_r", &G::correlation_r)
      .def_readonly("factor_t", &G::factor_t)
      .def_readonly("factor_r", &G::factor_r)
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(self,
                             "CovarianceNoiseGroup",
                             {"name",
                              "edges",
                              "residuals",
                              "held_by_others",
                              "residual_t",
                              "residual_r",
                              "correlation_t",
                              "correlation_r",
                              "factor_t",
                              "factor_r"});
      });
}

}  // namespace

void BindNoise(py::module_& m) {
  BindClassNoise(m);
  BindMotionNoise(m);
  BindCovarianceNoise(m);
}

}  // namespace symba::python
