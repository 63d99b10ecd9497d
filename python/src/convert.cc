#include "convert.h"

#include <cmath>
#include <cstring>
#include <optional>
#include <sstream>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace symba::python {
namespace {

std::string Repr(double value) {
  return py::str(py::float_(value)).cast<std::string>();
}

template <typename Array>
py::array ConvertOrCheck(py::handle value,
                         const std::string& name,
                         const char* dtype_name) {
  if (py::isinstance<py::array>(value)) {
    if (!py::isinstance<Array>(value)) {
      const py::array array = py::reinterpret_borrow<py::array>(value);
      ThrowValueError(
          name,
          std::string("expected a ") + dtype_name + " array, got dtype " +
              py::str(array.dtype()).cast<std::string>() +
              " (convert it with .astype(numpy." + dtype_name + "))");
    }
    return py::reinterpret_borrow<py::array>(value);
  }
  try {
    return py::module_::import("numpy").attr("asarray")(value, dtype_name);
  } catch (py::error_already_set& error) {
    if (!error.matches(PyExc_ValueError) && !error.matches(PyExc_TypeError)) {
      throw;
    }
    ThrowValueError(name,
                    std::string("expected ") + dtype_name + " numbers, got " +
                        py::repr(value).cast<std::string>() + " (" +
                        error.what() + ")");
  }
}

// Calls f(index, value) for every element in C order, following strides.
template <typename F>
void ForEachDouble(const py::array& array, F f) {
  const py::ssize_t ndim = array.ndim();
  const py::ssize_t size = array.size();
  std::vector<py::ssize_t> index(ndim, 0);
  const char* base = static_cast<const char*>(array.data());
  for (py::ssize_t n = 0; n < size; ++n) {
    py::ssize_t offset = 0;
    for (py::ssize_t d = 0; d < ndim; ++d)
      offset += index[d] * array.strides(d);
    double value;
    std::memcpy(&value, base + offset, sizeof(double));
    if (!f(index, value)) return;
    for (py::ssize_t d = ndim - 1; d >= 0; --d) {
      if (++index[d] < array.shape(d)) break;
      index[d] = 0;
    }
  }
}

std::string IndexString(const std::vector<py::ssize_t>& index) {
  std::ostringstream out;
  out << "[";
  for (size_t i = 0; i < index.size(); ++i) {
    if (i > 0) out << ", ";
    out << index[i];
  }
  out << "]";
  return out.str();
}

// The pose at `a`'s first axis entry `i` (or the whole array when i < 0).
// Errors name `array_name` (and the entry): the name is built only then.
Rigid3d ReadPose(const py::array& a,
                 py::ssize_t i,
                 const std::string& array_name) {
  const auto name = [&] {
    return i < 0 ? array_name : array_name + "[" + std::to_string(i) + "]";
  };
  const char* base = static_cast<const char*>(a.data());
  const int lead = i < 0 ? 0 : 1;
  const py::ssize_t offset0 = i < 0 ? 0 : i * a.strides(0);
  auto at = [&](py::ssize_t r, py::ssize_t c) {
    py::ssize_t offset = offset0 + r * a.strides(lead);
    if (c >= 0) offset += c * a.strides(lead + 1);
    double value;
    std::memcpy(&value, base + offset, sizeof(double));
    return value;
  };
  Rigid3d pose;
  if (a.ndim() == 1 + lead) {
    pose.t = Eigen::Vector3d(at(0, -1), at(1, -1), at(2, -1));
    // Eigen's constructor takes (w, x, y, z); the array holds x, y, z, w.
    pose.q = Eigen::Quaterniond(at(6, -1), at(3, -1), at(4, -1), at(5, -1));
    return pose;
  }
  Eigen::Matrix3d R;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) R(r, c) = at(r, c);
  }
  if (at(3, 0) != 0.0 || at(3, 1) != 0.0 || at(3, 2) != 0.0 ||
      at(3, 3) != 1.0) {
    ThrowValueError(name(),
                    "the last row of a 4 x 4 pose must be [0, 0, 0, 1]");
  }
  const double error =
      (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (error > 1e-3) {
    ThrowValueError(name(),
                    "not a rotation: R^T R differs from the identity by " +
                        Repr(error) + " (more than 1e-3)");
  }
  const double det = R.determinant();
  if (!(det > 0.0)) {
    ThrowValueError(
        name(), "not a rotation: det(R) = " + Repr(det) + " is not positive");
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  pose.q = Eigen::Quaterniond(svd.matrixU() * svd.matrixV().transpose());
  pose.t = Eigen::Vector3d(at(0, 3), at(1, 3), at(2, 3));
  return pose;
}

}  // namespace

std::string ShapeString(const py::array& array) {
  std::ostringstream out;
  out << "(";
  for (py::ssize_t i = 0; i < array.ndim(); ++i) {
    if (i > 0) out << ", ";
    out << array.shape(i);
  }
  if (array.ndim() == 1) out << ",";
  out << ")";
  return out.str();
}

void ThrowIfError(const Status& status) {
  if (!status.ok()) throw StatusError(status.message());
}

void ThrowValueError(const std::string& name, const std::string& message) {
  throw py::value_error(name + ": " + message);
}

py::array Float64Array(py::handle value, const std::string& name) {
  return ConvertOrCheck<py::array_t<double>>(value, name, "float64");
}

py::array Int64Array(py::handle value, const std::string& name) {
  return ConvertOrCheck<py::array_t<std::int64_t>>(value, name, "int64");
}

void CheckFinite(const py::array& array, const std::string& name) {
  // Fast path: a C-contiguous array is one run of doubles; the slow path
  // below finds the bad element's index.
  if (array.flags() & py::array::c_style) {
    const double* data = static_cast<const double*>(array.data());
    const py::ssize_t size = array.size();
    bool finite = true;
    for (py::ssize_t n = 0; n < size; ++n) finite &= std::isfinite(data[n]);
    if (finite) return;
  }
  ForEachDouble(
      array, [&](const std::vector<py::ssize_t>& index, double value) {
        if (std::isfinite(value)) return true;
        ThrowValueError(name + IndexString(index),
                        "expected a finite number, got " + Repr(value));
      });
}

Rigid3d PoseFromPython(py::handle value, const std::string& name) {
  const py::array array = Float64Array(value, name);
  const bool vector = array.ndim() == 1 && array.shape(0) == 7;
  const bool matrix =
      array.ndim() == 2 && array.shape(0) == 4 && array.shape(1) == 4;
  if (!vector && !matrix) {
    ThrowValueError(name,
                    "expected a pose of shape (7,) [tx, ty, tz, qx, qy, qz, "
                    "qw] or (4, 4), got shape " +
                        ShapeString(array));
  }
  CheckFinite(array, name);
  return ReadPose(array, -1, name);
}

Eigen::Vector3d Vector3FromPython(py::handle value, const std::string& name) {
  const py::array array = Float64Array(value, name);
  if (array.ndim() != 1 || array.shape(0) != 3) {
    ThrowValueError(name,
                    "expected shape (3,), got shape " + ShapeString(array));
  }
  CheckFinite(array, name);
  const auto v = array.unchecked<double, 1>();
  return Eigen::Vector3d(v(0), v(1), v(2));
}

std::vector<Rigid3d> PosesFromPython(py::handle value,
                                     const std::string& name) {
  const py::array array = Float64Array(value, name);
  const bool vectors = array.ndim() == 2 && array.shape(1) == 7;
  const bool matrices =
      array.ndim() == 3 && array.shape(1) == 4 && array.shape(2) == 4;
  if (!vectors && !matrices) {
    ThrowValueError(name,
                    "expected poses of shape (N, 7) [tx, ty, tz, qx, qy, qz, "
                    "qw] or (N, 4, 4), got shape " +
                        ShapeString(array));
  }
  CheckFinite(array, name);
  std::vector<Rigid3d> poses;
  poses.reserve(array.shape(0));
  for (py::ssize_t i = 0; i < array.shape(0); ++i) {
    poses.push_back(ReadPose(array, i, name));
  }
  return poses;
}

py::array_t<double> OwnedArray(std::vector<double>&& values,
                               std::vector<py::ssize_t> shape) {
  // numpy allocates an empty array itself (it would not keep the owner).
  if (values.empty()) return py::array_t<double>(std::move(shape));
  auto* owned = new std::vector<double>(std::move(values));
  const py::capsule owner(owned, [](void* pointer) {
    delete static_cast<std::vector<double>*>(pointer);
  });
  return py::array_t<double>(std::move(shape), owned->data(), owner);
}

py::array_t<std::int64_t> OwnedArray(std::vector<std::int64_t>&& values) {
  if (values.empty()) return py::array_t<std::int64_t>(py::ssize_t{0});
  auto* owned = new std::vector<std::int64_t>(std::move(values));
  const py::capsule owner(owned, [](void* pointer) {
    delete static_cast<std::vector<std::int64_t>*>(pointer);
  });
  const py::ssize_t n = static_cast<py::ssize_t>(owned->size());
  return py::array_t<std::int64_t>({n}, owned->data(), owner);
}

py::array_t<double> PoseToPython(const Rigid3d& T) {
  return OwnedArray(
      {T.t.x(), T.t.y(), T.t.z(), T.q.x(), T.q.y(), T.q.z(), T.q.w()}, {7});
}

py::array_t<double> VectorToPython(const Eigen::Vector3d& v) {
  return OwnedArray({v.x(), v.y(), v.z()}, {3});
}

}  // namespace symba::python

namespace symba::python {

py::array_t<double> DoublesToPython(std::vector<double> values) {
  const py::ssize_t n = static_cast<py::ssize_t>(values.size());
  return OwnedArray(std::move(values), {n});
}

SymmetryType SymmetryFromPython(const std::string& value,
                                const std::string& name) {
  const std::optional<SymmetryType> type = ParseSymmetryType(value);
  if (!type) {
    ThrowValueError(name,
                    "unknown symmetry \"" + value +
                        "\" (expected \"asymmetric\", \"discrete\" or "
                        "\"continuous\")");
  }
  return *type;
}

}  // namespace symba::python
