// Readable reprs for the result types: "Name(a=..., b=...)" built from what
// the Python attributes give, so a repr shows exactly what a user reads.
#ifndef SYMBA_PYTHON_SRC_REPR_H_
#define SYMBA_PYTHON_SRC_REPR_H_

#include <initializer_list>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace symba::python {

namespace py = pybind11;

// Arrays and lists longer than this are shown by their size only.
inline constexpr py::ssize_t kReprMaxElements = 7;

// One attribute value: small arrays as lists ([1.0, 0.0, ...]), larger ones
// as "<array (N, 7) float64>", lists longer than kReprMaxElements as
// "<list of N>", everything else as its own repr.
inline std::string ValueRepr(const py::object& value) {
  if (py::isinstance<py::array>(value)) {
    const py::array array = value.cast<py::array>();
    if (array.size() <= kReprMaxElements) {
      return py::repr(value.attr("tolist")()).cast<std::string>();
    }
    return "<array " + py::repr(value.attr("shape")).cast<std::string>() + " " +
           py::str(value.attr("dtype")).cast<std::string>() + ">";
  }
  if (py::isinstance<py::list>(value) &&
      py::len(value) > static_cast<std::size_t>(kReprMaxElements)) {
    return "<list of " + std::to_string(py::len(value)) + ">";
  }
  return py::repr(value).cast<std::string>();
}

// "Name(a=<ValueRepr of self.a>, b=...)".
inline std::string AttributeRepr(
    const py::handle& self,
    const char* name,
    std::initializer_list<const char*> attributes) {
  std::string text = std::string(name) + "(";
  bool first = true;
  for (const char* attribute : attributes) {
    if (!first) text += ", ";
    first = false;
    text += std::string(attribute) + "=" + ValueRepr(self.attr(attribute));
  }
  return text + ")";
}

}  // namespace symba::python

#endif  // SYMBA_PYTHON_SRC_REPR_H_
