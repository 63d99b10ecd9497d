// categorize(): one multi-hypothesis detection's symmetry type and
// unambiguous parameters (docs/categorization.md).
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "convert.h"
#include "repr.h"
#include "symba/categorization/categorize.h"

namespace symba::python {
namespace {

py::array_t<std::int64_t> Indices(const std::vector<int>& indices) {
  return OwnedArray(std::vector<std::int64_t>(indices.begin(), indices.end()));
}

}  // namespace

void BindCategorize(py::module_& m) {
  py::class_<AngleCluster>(
      m, "AngleCluster", "One mode of a discrete detection.")
      .def_readonly("theta", &AngleCluster::theta)
      .def_readonly("spread", &AngleCluster::spread)
      .def_readonly("weight", &AngleCluster::weight)
      .def_property_readonly(
          "members", [](const AngleCluster& c) { return Indices(c.members); })
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(
            self, "AngleCluster", {"theta", "spread", "weight", "members"});
      });

  using D = CategorizationDiagnostics;
  py::class_<D>(m, "CategorizationDiagnostics")
      .def_readonly("passes", &D::passes)
      .def_readonly("axis_support", &D::axis_support)
      .def_readonly("num_axis_inliers", &D::num_axis_inliers)
      .def_readonly("num_raw_clusters", &D::num_raw_clusters)
      .def_readonly("num_noise", &D::num_noise)
      .def_readonly("max_cluster_extent", &D::max_cluster_extent)
      .def_readonly("min_cluster_separation", &D::min_cluster_separation)
      .def_readonly("empty_fraction", &D::empty_fraction)
      .def_readonly("prior_axis_used", &D::prior_axis_used)
      .def_readonly("prior_order_snapped", &D::prior_order_snapped)
      .def_readonly("prior_type_used", &D::prior_type_used)
      .def("__repr__", [](const py::handle& self) {
        return AttributeRepr(self,
                             "CategorizationDiagnostics",
                             {"passes",
                              "axis_support",
                              "num_axis_inliers",
                              "num_raw_clusters",
                              "num_noise",
                              "max_cluster_extent",
                              "min_cluster_separation",
                              "empty_fraction",
                              "prior_axis_used",
                              "prior_order_snapped",
                              "prior_type_used"});
      });

  using C = CategorizedDetection;
  py::class_<C>(m,
                "Categorization",
                "The result of categorize(): type, reference index, "
                "T_co_base (7,) [tx, ty, tz, qx, qy, qz, qw], t_co, axis_o, "
                "axis_c (3,), clusters, inliers (int64), twist (N,) rad.")
      .def_property_readonly(
          "type", [](const C& c) { return std::string(ToString(c.type)); })
      .def_readonly("reference", &C::reference)
      .def_property_readonly(
          "T_co_base", [](const C& c) { return PoseToPython(c.T_co_base); })
      .def_property_readonly("t_co",
                             [](const C& c) { return VectorToPython(c.t_co); })
      .def_property_readonly(
          "axis_o", [](const C& c) { return VectorToPython(c.axis_o); })
      .def_property_readonly(
          "axis_c", [](const C& c) { return VectorToPython(c.axis_c); })
      .def_readonly("clusters", &C::clusters)
      .def_property_readonly("inliers",
                             [](const C& c) { return Indices(c.inliers); })
      .def_property_readonly(
          "twist", [](const C& c) { return DoublesToPython(c.twist); })
      .def_readonly("diagnostics", &C::diagnostics)
      .def("__repr__", [](const C& c) {
        return std::string("Categorization(type='") + ToString(c.type) + "', " +
               std::to_string(c.clusters.size()) + " clusters, " +
               std::to_string(c.inliers.size()) + " inliers)";
      });

  m.def(
      "categorize",
      [](const py::object& hypotheses,
         const py::object& weights,
         const std::optional<CategorizationOptions>& options,
         const std::optional<ClassPrior>& prior) {
        const std::vector<Rigid3d> poses =
            PosesFromPython(hypotheses, "hypotheses");
        std::vector<PoseHypothesis> input(poses.size());
        for (size_t i = 0; i < poses.size(); ++i) input[i].T_co = poses[i];
        if (!weights.is_none()) {
          const py::array w = Float64Array(weights, "weights");
          if (w.ndim() != 1 ||
              static_cast<size_t>(w.shape(0)) != poses.size()) {
            ThrowValueError("weights",
                            "expected shape (" + std::to_string(poses.size()) +
                                ",), one weight per hypothesis, got " +
                                ShapeString(w));
          }
          CheckFinite(w, "weights");
          const auto view = w.unchecked<double, 1>();
          for (size_t i = 0; i < poses.size(); ++i) input[i].weight = view(i);
        }
        CategorizedDetection out;
        Status status;
        {
          py::gil_scoped_release release;
          status = Categorize(input,
                              options.value_or(CategorizationOptions()),
                              prior ? &*prior : nullptr,
                              &out);
        }
        ThrowIfError(status);
        return out;
      },
      py::arg("hypotheses"),
      py::arg("weights") = py::none(),
      py::arg("options") = py::none(),
      py::arg("prior") = py::none(),
      "Categorises one detection: hypotheses T_co as (N, 7) [tx, ty, tz, qx, "
      "qy, qz, qw] or (N, 4, 4) float64, weights (N,) (default 1). Raises "
      "symba.Error with the library's message for invalid hypotheses.");
}

}  // namespace symba::python
