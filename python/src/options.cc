// BackendOptions, CategorizationOptions, MixtureOptions, ClassPrior and
// PinholeIntrinsics: plain attributes with the C++ defaults; the enums are
// strings ("symba", "marginalize", ...).
#include <string>

#include "bindings.h"
#include "convert.h"
#include "symba/backend/backend_options.h"
#include "symba/categorization/categorize.h"
#include "symba/geometry/pinhole_intrinsics.h"

namespace symba::python {
namespace {

// A string property over an enum with the library's name/parse functions.
template <typename Options, typename Enum>
void EnumProperty(py::class_<Options>& cls,
                  const char* name,
                  Enum Options::*field,
                  const char* (*to_name)(Enum),
                  bool (*parse)(const std::string&, Enum*),
                  const char* expected) {
  cls.def_property(
      name,
      [field, to_name](const Options& options) {
        return std::string(to_name(options.*field));
      },
      [field, parse, name, expected](Options& options,
                                     const std::string& value) {
        Enum parsed;
        if (!parse(value, &parsed)) {
          ThrowValueError(
              name,
              "unknown value \"" + value + "\" (expected " + expected + ")");
        }
        options.*field = parsed;
      });
}

void BindCategorizationOptions(py::module_& m) {
  using O = CategorizationOptions;
  py::class_<O>(m,
                "CategorizationOptions",
                "Thresholds of the categorisation (docs/categorization.md); "
                "angles in radians, lengths in metres.")
      .def(py::init([](const py::kwargs& kwargs) {
             return FromKwargs<O>(kwargs, "CategorizationOptions");
           }),
           "Defaults, with any attribute given as a keyword.")
      .def_readwrite("min_axis_angle", &O::min_axis_angle)
      .def_readwrite("axis_vote_angle", &O::axis_vote_angle)
      .def_readwrite("swing_tolerance", &O::swing_tolerance)
      .def_readwrite("cluster_eps", &O::cluster_eps)
      .def_readwrite("min_points", &O::min_points)
      .def_readwrite("merge_close_clusters", &O::merge_close_clusters)
      .def_readwrite("rescue_min_points", &O::rescue_min_points)
      .def_readwrite("max_cluster_extent", &O::max_cluster_extent)
      .def_readwrite("min_cluster_separation", &O::min_cluster_separation)
      .def_readwrite("separation_ratio", &O::separation_ratio)
      .def_readwrite("max_noise_fraction", &O::max_noise_fraction)
      .def_readwrite("empty_gap_angle", &O::empty_gap_angle)
      .def_readwrite("min_empty_fraction", &O::min_empty_fraction)
      .def_readwrite("asymmetric_inlier_angle", &O::asymmetric_inlier_angle)
      .def_readwrite("translation_gate", &O::translation_gate)
      .def_readwrite("prior_snap_angle", &O::prior_snap_angle)
      .def_readwrite("read_one_mode_with_prior", &O::read_one_mode_with_prior)
      .def(
          "validate",
          [](const O& options) { ThrowIfError(options.Validate()); },
          "Raises symba.Error naming the option that is out of range.");
}

void BindMixtureOptions(py::module_& m) {
  using O = MixtureOptions;
  py::class_<O>(m, "MixtureOptions", "The max-mixtures' null hypothesis.")
      .def(py::init([](const py::kwargs& kwargs) {
        return FromKwargs<O>(kwargs, "MixtureOptions");
      }))
      .def_readwrite("use_null_hypothesis", &O::use_null_hypothesis)
      .def_readwrite("null_weight", &O::null_weight)
      .def_readwrite("null_sigma_scale", &O::null_sigma_scale);
}

void BindBackendOptions(py::module_& m) {
  using O = BackendOptions;
  py::class_<O> cls(m,
                    "BackendOptions",
                    "Every option of the backend with the C++ default "
                    "(docs/backend.md); metres, radians.");
  cls.def(py::init([](const py::kwargs& kwargs) {
            return FromKwargs<O>(kwargs, "BackendOptions");
          }),
          "Defaults, with any attribute given as a keyword, e.g. "
          "BackendOptions(method=\"mh\", window_size=5).");
  EnumProperty(cls,
               "method",
               &O::method,
               &MethodName,
               &ParseMethod,
               "\"symba\", \"mh\" or \"sh\"");
  cls.def_readwrite("window_size", &O::window_size);
  EnumProperty(cls,
               "window_policy",
               &O::window_policy,
               &WindowPolicyName,
               &ParseWindowPolicy,
               "\"marginalize\", \"condition\" or \"drop\"");
  cls.def_readwrite("marginalize_min_margin", &O::marginalize_min_margin)
      .def_readwrite("marginalize_rival_distance",
                     &O::marginalize_rival_distance);
  EnumProperty(cls,
               "chain_prior",
               &O::chain_prior,
               &ChainPriorName,
               &ParseChainPrior,
               "\"conditional\" or \"marginal\"");
  cls.def_readwrite("max_iterations", &O::max_iterations)
      .def_readwrite("batch_max_iterations", &O::batch_max_iterations)
      .def_readwrite("num_threads", &O::num_threads)
      .def_readwrite("hypothesis_sigma_t", &O::hypothesis_sigma_t)
      .def_readwrite("hypothesis_sigma_r", &O::hypothesis_sigma_r)
      .def_readwrite("gamma", &O::gamma)
      .def_readwrite("axis_sigma", &O::axis_sigma)
      .def_readwrite("merge_modes", &O::merge_modes);
  EnumProperty(cls,
               "object_loss",
               &O::object_loss,
               &LossName,
               &ParseLoss,
               "\"none\", \"huber\" or \"cauchy\"");
  cls.def_readwrite("object_loss_scale", &O::object_loss_scale)
      .def_readwrite("mixture", &O::mixture)
      .def_readwrite("frontend_sigma_t", &O::frontend_sigma_t)
      .def_readwrite("frontend_sigma_r", &O::frontend_sigma_r)
      .def_readwrite("point_sigma_px", &O::point_sigma_px)
      .def_readwrite("point_loss_scale", &O::point_loss_scale)
      .def_readwrite("point_depth_sigma_relative",
                     &O::point_depth_sigma_relative)
      .def_readwrite("gate_position", &O::gate_position)
      .def_readwrite("gate_axis", &O::gate_axis)
      .def_readwrite("gate_rotation", &O::gate_rotation)
      .def_readwrite("gate_angle", &O::gate_angle)
      .def_readwrite("reanchor_angle", &O::reanchor_angle)
      .def_readwrite("confirm_keyframes", &O::confirm_keyframes)
      .def_readwrite("tentative_timeout", &O::tentative_timeout)
      .def_readwrite("gate_sigmas", &O::gate_sigmas)
      .def_readwrite("estimate_noise", &O::estimate_noise)
      .def_readwrite("noise_window", &O::noise_window)
      .def_readwrite("noise_min_samples", &O::noise_min_samples)
      .def_readwrite("noise_update_ratio", &O::noise_update_ratio)
      .def_readwrite("uncalibrated_sigma_t", &O::uncalibrated_sigma_t)
      .def_readwrite("uncalibrated_sigma_r", &O::uncalibrated_sigma_r)
      .def_readwrite("min_support", &O::min_support)
      .def_readwrite("min_support_views", &O::min_support_views)
      .def_readwrite("upgrade_evidence", &O::upgrade_evidence)
      .def_readwrite("upgrade_min_fraction", &O::upgrade_min_fraction)
      .def_readwrite("max_upgrade_order", &O::max_upgrade_order)
      .def_readwrite("upgrade_angle_tolerance", &O::upgrade_angle_tolerance)
      .def_readwrite("categorization", &O::categorization)
      .def(
          "validate",
          [](const O& options) { ThrowIfError(options.Validate()); },
          "Raises symba.Error naming the option that is out of range.");
}

void BindClassPrior(py::module_& m) {
  py::class_<ClassPrior>(m,
                         "ClassPrior",
                         "What is known about a class's symmetry (the log "
                         "header's `classes`).")
      .def(py::init([](const std::string& symmetry,
                       int order,
                       const py::object& axis_o) {
             ClassPrior prior;
             prior.symmetry = SymmetryFromPython(symmetry, "symmetry");
             prior.order = order;
             if (!axis_o.is_none()) {
               prior.axis_o = Vector3FromPython(axis_o, "axis_o");
             }
             return prior;
           }),
           py::arg("symmetry") = "asymmetric",
           py::arg("order") = 0,
           py::arg("axis_o") = py::none())
      .def_property(
          "symmetry",
          [](const ClassPrior& p) { return std::string(ToString(p.symmetry)); },
          [](ClassPrior& p, const std::string& value) {
            p.symmetry = SymmetryFromPython(value, "symmetry");
          })
      .def_readwrite("order", &ClassPrior::order)
      .def_property(
          "axis_o",
          [](const ClassPrior& p) { return VectorToPython(p.axis_o); },
          [](ClassPrior& p, const py::object& value) {
            p.axis_o = Vector3FromPython(value, "axis_o");
          })
      .def("__repr__", [](const ClassPrior& p) {
        return "ClassPrior(symmetry='" + std::string(ToString(p.symmetry)) +
               "', order=" + std::to_string(p.order) + ")";
      });
}

void BindIntrinsics(py::module_& m) {
  py::class_<PinholeIntrinsics>(
      m, "PinholeIntrinsics", "Pinhole camera intrinsics in pixels.")
      .def(py::init([](double fx, double fy, double cx, double cy) {
             return PinholeIntrinsics{fx, fy, cx, cy};
           }),
           py::arg("fx"),
           py::arg("fy"),
           py::arg("cx"),
           py::arg("cy"))
      .def_readwrite("fx", &PinholeIntrinsics::fx)
      .def_readwrite("fy", &PinholeIntrinsics::fy)
      .def_readwrite("cx", &PinholeIntrinsics::cx)
      .def_readwrite("cy", &PinholeIntrinsics::cy)
      .def("__repr__", [](const PinholeIntrinsics& k) {
        return py::str("PinholeIntrinsics(fx={}, fy={}, cx={}, cy={})")
            .format(k.fx, k.fy, k.cx, k.cy);
      });
}

}  // namespace

void BindOptions(py::module_& m) {
  BindCategorizationOptions(m);
  BindMixtureOptions(m);
  BindBackendOptions(m);
  BindClassPrior(m);
  BindIntrinsics(m);
}

}  // namespace symba::python
