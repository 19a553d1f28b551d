// BrushModel: one Python property per row of the parameter table, each range-checked on set.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "brushwork/geometry.hpp"
#include "brushwork/model.hpp"

namespace py = pybind11;
using brushwork::BrushModel;

namespace {

// a copy with the named fields changed, each through its range-checked property, then the
// whole model validated (fields that constrain each other)
py::object replace_fields(const BrushModel& s, const py::kwargs& fields) {
  py::object out = py::cast(BrushModel(s));
  for (const auto& item : fields) {
    const std::string name = item.first.cast<std::string>();
    bool known = false;
    for (const auto& p : brushwork::param_table()) known = known || p.name == name;
    if (!known)
      throw py::type_error("BrushModel.replace: no field '" + name +
                           "' (BrushModel.parameters() lists them)");
    out.attr(name.c_str()) = item.second;
  }
  out.cast<const BrushModel&>().validate();
  return out;
}

py::list parameter_dicts() {
  py::list out;
  for (const auto& p : brushwork::param_table()) {
    py::dict d;
    d["name"] = p.name, d["unit"] = p.unit, d["kind"] = p.kind, d["doc"] = p.doc;
    d["min"] = p.lo, d["max"] = p.hi;
    out.append(d);
  }
  return out;
}

// one property for parameter p, typed as the table says
void bind_parameter(py::class_<BrushModel>& cls, const brushwork::ParamInfo& p) {
  const std::string name = p.name, kind = p.kind;
  const std::string doc = p.doc + " [" + p.unit + ", " + std::to_string(p.lo) + " .. " +
                          std::to_string(p.hi) + "]";
  py::cpp_function getter(
      [name, kind](const BrushModel& mdl) -> py::object {
        const double v = brushwork::get_param(mdl, name);
        if (kind == "int") return py::int_(static_cast<long>(v));
        if (kind == "bool") return py::bool_(v != 0.0);
        return py::float_(v);
      },
      py::is_method(cls));
  py::cpp_function setter(
      [name, kind](BrushModel& mdl, py::object value) {
        if (kind == "bool" && !py::isinstance<py::bool_>(value))
          throw std::invalid_argument("BrushModel." + name + " must be True or False, got " +
                                      py::repr(value).cast<std::string>());
        double v;
        try {
          v = value.cast<double>();
        } catch (const py::cast_error&) {
          throw std::invalid_argument("BrushModel." + name + " must be a number, got " +
                                      py::repr(value).cast<std::string>());
        }
        brushwork::set_param(mdl, name, v);
      },
      py::is_method(cls));
  cls.attr(name.c_str()) = py::reinterpret_steal<py::object>(
      PyObject_CallFunctionObjArgs((PyObject*)&PyProperty_Type, getter.ptr(), setter.ptr(),
                                   Py_None, py::str(doc).ptr(), nullptr));
}

void bind_footprint_span(py::module_& m) {
  m.def(
      "footprint_span",
      [](const std::vector<Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>& loops,
         double heading) -> py::object {
        const brushwork::FootprintSpan f = brushwork::footprint_span(loops, heading);
        if (!f.valid) return py::none();
        return py::make_tuple(f.centroid, f.width, f.behind, f.ahead);
      },
      py::arg("loops"), py::arg("heading"),
      "(centroid (2,) mm, width across `heading` mm, reach behind and ahead of the centroid along "
      "it mm) of footprint loops (Brush.footprint()), or None without a footprint. A centroid "
      "outside the points' bounds (a sliver whose loop and hole nearly cancel) is their mean.");
}

}  // namespace

void bind_model(py::module_& m) {
  auto cls = py::class_<BrushModel>(m, "BrushModel", R"doc(
Read-only parameters of one tuft (lengths in mm, forces in N, energies in N*mm, angles in deg).
Build one with BrushModel.preset(name) and change fields by keyword:
BrushModel.preset("medium").replace(exponent=3). Every field is range-checked; see
BrushModel.parameters() for the table of units, ranges and meanings.)doc");
  cls.def(py::init<>(), "The default model (the 'medium' preset).")
      .def_static("preset", &BrushModel::preset, py::arg("name"),
                  "A named preset; BrushModel.presets() lists them.")
      .def_static("presets", &BrushModel::preset_names, "Names of the presets.")
      .def("validate", &BrushModel::validate, "Raise ValueError naming any out-of-range field.")
      .def("segment_lengths", &BrushModel::segment_lengths, "(n,) mm, root first.")
      .def("node_radii", &BrushModel::node_radii, "(n+1,) mm, initial tuft radius r_i at spine node N_i.")
      .def("node_arclength", &BrushModel::node_arclength, "(n+1,) mm from the root along the unbent spine.")
      .def("bend_kappa", &BrushModel::bend_kappa, "(n,) N*mm/rad^m, bend spring constants, root first.")
      .def("split_model", &BrushModel::split_model,
           "The model of each tuft the brush splits into: an even tuft (even_tufts) or a satellite.")
      .def(
          "replace", &replace_fields,
          "A copy with the fields given by keyword changed: BrushModel.preset('small')."
          "replace(q_max=50, tolerance=1e-8). Raises TypeError for an unknown field and "
          "ValueError for a value out of range.")
      .def("__copy__", [](const BrushModel& s) { return BrushModel(s); })
      .def("copy", [](const BrushModel& s) { return BrushModel(s); }, "An independent copy.")
      .def_static(
          "parameters", &parameter_dicts,
          "The parameter table: a list of dicts with name, unit, kind, min, max, doc.");

  for (const auto& p : brushwork::param_table()) bind_parameter(cls, p);
  bind_footprint_span(m);
}
