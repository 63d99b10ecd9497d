// Conversions between NumPy arrays and symba's C++ types, shared by the
// binding files. Poses are 7-vectors [tx, ty, tz, qx, qy, qz, qw]: the
// translation, then a Hamilton quaternion with the scalar last, the order of
// the log format and of TUM files. A pose argument also takes a 4 x 4
// homogeneous matrix. Every input array must be float64 (or a list of
// numbers); the wrong dtype, the wrong shape or a non-finite number raises
// ValueError naming the argument and what was expected.
#ifndef SYMBA_PYTHON_SRC_CONVERT_H_
#define SYMBA_PYTHON_SRC_CONVERT_H_

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "symba/categorization/symmetry_type.h"
#include "symba/common/status.h"
#include "symba/detection/pose_hypothesis.h"
#include "symba/geometry/rigid3.h"

namespace symba::python {

namespace py = pybind11;

// A non-OK Status from the library; the module registers it as symba.Error
// (a RuntimeError) with the Status's message unchanged.
class StatusError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws StatusError with the status's message if it is not OK.
void ThrowIfError(const Status& status);

// Throws py::value_error with "NAME: MESSAGE".
[[noreturn]] void ThrowValueError(const std::string& name,
                                  const std::string& message);

// `value` as a float64 array: an ndarray must already have dtype float64
// (no silent conversion, no copy); anything else (a list, a tuple) is
// converted with numpy.asarray(value, dtype=float64).
py::array Float64Array(py::handle value, const std::string& name);
// The same for int64 (ndarray: any signed or unsigned integer dtype that
// fits is refused unless it is int64; lists are converted).
py::array Int64Array(py::handle value, const std::string& name);

// A NumPy-style shape, e.g. "(3,)" or "(2, 7)".
std::string ShapeString(const py::array& array);

// Raises ValueError unless every element of `array` is finite; names the
// first bad element ("NAME[2, 3]: expected a finite number, got nan").
void CheckFinite(const py::array& array, const std::string& name);

// One pose from a (7,) vector or a (4, 4) matrix (its last row must be
// [0, 0, 0, 1] and its rotation within 1e-3 of orthonormal with a positive
// determinant; it is projected onto SO(3)). The quaternion of a 7-vector is
// taken as given (the library checks that it is unit).
Rigid3d PoseFromPython(py::handle value, const std::string& name);
// A (3,) vector.
Eigen::Vector3d Vector3FromPython(py::handle value, const std::string& name);
// N poses from an (N, 7) or (N, 4, 4) array.
std::vector<Rigid3d> PosesFromPython(py::handle value, const std::string& name);

// A float64 array that owns `values` (moved, not copied) with `shape`.
py::array_t<double> OwnedArray(std::vector<double>&& values,
                               std::vector<py::ssize_t> shape);
py::array_t<std::int64_t> OwnedArray(std::vector<std::int64_t>&& values);
// (7,) and (N, 7) pose arrays.
py::array_t<double> PoseToPython(const Rigid3d& pose);
template <typename Range, typename GetPose>
py::array_t<double> PosesToPython(const Range& range, GetPose get_pose) {
  std::vector<double> values;
  values.reserve(7 * range.size());
  for (const auto& item : range) {
    const Rigid3d& T = get_pose(item);
    values.insert(
        values.end(),
        {T.t.x(), T.t.y(), T.t.z(), T.q.x(), T.q.y(), T.q.z(), T.q.w()});
  }
  const py::ssize_t n = static_cast<py::ssize_t>(range.size());
  return OwnedArray(std::move(values), {n, 7});
}
py::array_t<double> VectorToPython(const Eigen::Vector3d& v);
py::array_t<double> DoublesToPython(std::vector<double> values);

// A symmetry type by its log-format name; ValueError naming `name` else.
SymmetryType SymmetryFromPython(const std::string& value,
                                const std::string& name);

// Builds a T from keyword arguments: each key must be one of T's Python
// attributes (TypeError otherwise) and is set as `object.key = value`.
template <typename T>
T FromKwargs(const py::kwargs& kwargs, const char* type_name) {
  T value;
  const py::object proxy = py::cast(&value, py::return_value_policy::reference);
  for (const auto& item : kwargs) {
    const std::string key = py::str(item.first);
    if (key.empty() || key[0] == '_' || key == "validate" ||
        !py::hasattr(proxy, key.c_str())) {
      throw py::type_error(std::string(type_name) + ": unknown option '" + key +
                           "'");
    }
    py::setattr(proxy, item.first, item.second);
  }
  return value;
}

}  // namespace symba::python

#endif  // SYMBA_PYTHON_SRC_CONVERT_H_
