// BackendOptions, CategorizationOptions, MixtureOptions, ClassPrior and
// PinholeIntrinsics: plain attributes with the C++ defaults; the enums are
// strings ("symba", "marginalize", ...).
#include <string>
#include <variant>
#include <vector>

#include "bindings.h"
#include "convert.h"
#include "symba/backend/backend_option_table.h"
#include "symba/backend/backend_options.h"
#include "symba/categorization/categorize.h"
#include "symba/geometry/pinhole_intrinsics.h"

namespace symba::python {
namespace {

// "\"symba\", \"mh\" or \"sh\"".
std::string QuotedChoices(const std::vector<std::string>& choices) {
  std::string text;
  for (size_t i = 0; i < choices.size(); ++i) {
    if (i > 0) text += i + 1 == choices.size() ? " or " : ", ";
    text += "\"" + choices[i] + "\"";
  }
  return text;
}

// A property of the field's Python type (bool, int, float; an enum is its
// name as a str), documented with the table's line.
template <typename Options>
void AddProperty(py::class_<Options>& cls,
                 const OptionField<Options>& table_field) {
  const OptionField<Options>* field = &table_field;
  auto get = [field](const Options& o) {
    return std::visit([](const auto& v) { return py::cast(v); }, field->get(o));
  };
  const char* name = field->name.c_str();
  const char* doc = field->doc.c_str();
  switch (field->type) {
    case OptionType::kBool:
      cls.def_property(
          name, get, [field](Options& o, bool v) { field->set(v, &o); }, doc);
      break;
    case OptionType::kInt:
      cls.def_property(
          name, get, [field](Options& o, int v) { field->set(v, &o); }, doc);
      break;
    case OptionType::kDouble:
      cls.def_property(
          name, get, [field](Options& o, double v) { field->set(v, &o); }, doc);
      break;
    case OptionType::kEnum:
      cls.def_property(
          name,
          get,
          [field](Options& o, const std::string& v) {
            if (!field->set(v, &o)) {
              ThrowValueError(field->name,
                              "unknown value \"" + v + "\" (expected " +
                                  QuotedChoices(field->choices) + ")");
            }
          },
          doc);
      break;
  }
}

// Every field of the table that is not in a nested struct (those are the
// nested struct's own class).
template <typename Options>
void AddProperties(py::class_<Options>& cls,
                   const OptionTable<Options>& table) {
  for (const OptionField<Options>& field : table) {
    if (!IsNested(field)) AddProperty(cls, field);
  }
}

// Defaults, with any attribute as a keyword, and validate().
template <typename Options>
py::class_<Options> BindOptionsClass(py::module_& m,
                                     const char* name,
                                     const char* doc,
                                     const char* init_doc,
                                     const OptionTable<Options>& table) {
  py::class_<Options> cls(m, name, doc);
  cls.def(py::init([name](const py::kwargs& kwargs) {
            return FromKwargs<Options>(kwargs, name);
          }),
          init_doc);
  AddProperties(cls, table);
  return cls;
}

template <typename Options>
void AddValidate(py::class_<Options>& cls) {
  cls.def(
      "validate",
      [](const Options& options) { ThrowIfError(options.Validate()); },
      "Raises symba.Error naming the option that is out of range.");
}

void BindCategorizationOptions(py::module_& m) {
  auto cls = BindOptionsClass<CategorizationOptions>(
      m,
      "CategorizationOptions",
      "Thresholds of the categorisation (docs/categorization.md); angles in "
      "radians, lengths in metres.",
      "Defaults, with any attribute given as a keyword.",
      CategorizationOptionTable());
  AddValidate(cls);
}

void BindMixtureOptions(py::module_& m) {
  BindOptionsClass<MixtureOptions>(m,
                                   "MixtureOptions",
                                   "The max-mixtures' null hypothesis.",
                                   "Defaults, with any attribute given as a "
                                   "keyword.",
                                   MixtureOptionTable());
}

void BindBackendOptions(py::module_& m) {
  using O = BackendOptions;
  auto cls = BindOptionsClass<O>(
      m,
      "BackendOptions",
      "Every option of the backend with the C++ default (docs/backend.md); "
      "metres, radians.",
      "Defaults, with any attribute given as a keyword, e.g. "
      "BackendOptions(method=\"mh\", window_size=5).",
      BackendOptionTable());
  cls.def_readwrite("mixture", &O::mixture)
      .def_readwrite("categorization", &O::categorization);
  AddValidate(cls);
}

// The table as dicts, for the tests: name, type, unit, default, range
// (text, low, high, open ends, infinity), choices and doc.
py::list OptionTableForPython() {
  py::list rows;
  const BackendOptions defaults;
  for (const OptionField<BackendOptions>& field : BackendOptionTable()) {
    static const char* const kTypes[] = {"bool", "int", "float", "enum"};
    py::dict row;
    row["name"] = field.name;
    row["type"] = kTypes[static_cast<int>(field.type)];
    row["unit"] = field.unit;
    row["default"] = std::visit([](const auto& v) { return py::cast(v); },
                                field.get(defaults));
    row["default_text"] = FormatOptionValue(field.get(defaults));
    row["range"] = field.IsNumeric() ? field.range.Text() : "";
    row["low"] = field.range.low;
    row["high"] = field.range.high;
    row["low_open"] = field.range.low_open;
    row["high_open"] = field.range.high_open;
    row["allow_infinity"] = field.range.allow_infinity;
    row["choices"] = field.choices;
    row["doc"] = field.doc;
    rows.append(row);
  }
  return rows;
}

void BindOptionTable(py::module_& m) {
  m.def("_option_table",
        &OptionTableForPython,
        "Every option of BackendOptions and its nested structs, as the "
        "C++ table has it (for the tests; not part of the API).");
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
  BindOptionTable(m);
}

}  // namespace symba::python
