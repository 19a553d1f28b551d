// Pose, StepStats and Brush.  Arrays cross as numpy: row-major (k, 3) float64, in mm.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <sstream>

#include "brushwork/brush.hpp"
#include "brushwork/render/deposit.hpp"

namespace py = pybind11;
using namespace brushwork;

namespace {

void bind_pose(py::module_& m) {
  py::class_<Pose>(m, "Pose", R"doc(
Where the hand holds the brush. position: the tuft root (x, y, z) in mm, z its height above the
paper (lowering z below the tuft length presses the brush); tilt_deg: handle against the paper's
normal, 0..89.9; azimuth_deg: direction on the paper toward which the handle leans; twist_deg:
rotation of the handle about its own axis. Non-finite or out-of-range values raise ValueError.)doc")
      .def(py::init([](const Eigen::Vector3d& position, double tilt, double azimuth, double twist) {
             Pose p;
             p.position = position;
             p.tilt_deg = tilt;
             p.azimuth_deg = azimuth;
             p.twist_deg = twist;
             p.validate();
             return p;
           }),
           py::arg("position"), py::arg("tilt_deg") = 0.0, py::arg("azimuth_deg") = 0.0,
           py::arg("twist_deg") = 0.0)
      .def_property_readonly("position", [](const Pose& p) { return Eigen::Vector3d(p.position); })
      .def_readonly("tilt_deg", &Pose::tilt_deg)
      .def_readonly("azimuth_deg", &Pose::azimuth_deg)
      .def_readonly("twist_deg", &Pose::twist_deg)
      .def("__repr__", [](const Pose& p) {
        std::ostringstream o;
        o << "Pose(position=(" << p.position.x() << ", " << p.position.y() << ", " << p.position.z()
          << "), tilt_deg=" << p.tilt_deg << ", azimuth_deg=" << p.azimuth_deg
          << ", twist_deg=" << p.twist_deg << ")";
        return o.str();
      });
}

void bind_stats(py::module_& m) {
  py::class_<StepStats>(m, "StepStats", "Statistics of one Brush.step().")
      .def_readonly("iterations", &StepStats::iterations, "SQP iterations this frame")
      .def_readonly("energy", &StepStats::energy, "incremental potential at the end, N*mm")
      .def_readonly("kkt_residual", &StepStats::kkt_residual, "scaled KKT residual at the end")
      .def_readonly("max_penetration", &StepStats::max_penetration,
                    "mm, deepest point of the shrunk sections below the paper")
      .def_readonly("converged", &StepStats::converged, "kkt_residual <= model.tolerance")
      .def_readonly("time", &StepStats::time, "seconds spent in step()")
      .def_readonly("line_search_failures", &StepStats::line_search_failures)
      .def_readonly("hessian_resets", &StepStats::hessian_resets)
      .def_readonly("contacts", &StepStats::contacts, "nodes in the frozen contact set")
      .def_readonly("root_clamped", &StepStats::root_clamped,
                    "the pose put the ferrule into the paper; the root was held on it")
      .def_readonly("substeps", &StepStats::substeps,
                    "sub-steps this frame was split into (a pose far from the last one)")
      .def_readonly("pore_active", &StepStats::pore_active, "the pore blocking plane was active")
      .def_readonly("penalty", &StepStats::penalty, "nu of the l1 merit function")
      .def_readonly("tufts_active", &StepStats::tufts_active, "child tufts sprouted after this frame")
      .def_readonly("tuft_iterations", &StepStats::tuft_iterations,
                    "SQP iterations of the child tufts' own minimisations this frame")
      .def_readonly("sprout_score", &StepStats::sprout_score,
                    "the main tuft's sprouting score this frame (model.sprout_spread sprouts)")
      .def_readonly("status", &StepStats::status)
      .def_readonly("merit_before", &StepStats::merit_before, "merit before each accepted step")
      .def_readonly("merit_after", &StepStats::merit_after, "merit after each accepted step")
      .def_readonly("kkt_trace", &StepStats::kkt_trace, "KKT residual after each accepted step")
      .def_readonly("step_sizes", &StepStats::step_sizes, "line-search alpha of each accepted step")
      .def("__repr__", [](const StepStats& s) {
        std::ostringstream o;
        o << "StepStats(iterations=" << s.iterations << ", energy=" << s.energy
          << ", kkt_residual=" << s.kkt_residual << ", max_penetration=" << s.max_penetration
          << ", converged=" << (s.converged ? "True" : "False") << ", status='" << s.status
          << "', time=" << s.time << ")";
        return o.str();
      });
}

void bind_state(py::module_& m) {
  py::class_<BrushState>(m, "BrushState", R"doc(
Everything that changes as a brush moves (degrees of freedom, last frame's values, plastic rest
angles, multipliers, the carried BFGS matrix, the contact set, the pore plane, the pose, the
wetness and the ink, the last step's statistics), as one opaque value.  Brush.state() returns a copy;
Brush.set_state(state) puts it back, and the brush then moves on bit for bit as it did from
that moment.)doc")
      .def("copy", [](const BrushState& s) { return BrushState(s); }, "an independent copy")
      .def("__copy__", [](const BrushState& s) { return BrushState(s); })
      .def("__deepcopy__", [](const BrushState& s, py::dict) { return BrushState(s); }, py::arg("memo"))
      .def_property_readonly("n_segments", [](const BrushState& s) { return s.x.size() / 5; })
      .def_property_readonly("tufts_active", [](const BrushState& s) { return s.tufts_active; },
                             "child tufts sprouted in this state")
      .def_property_readonly("split_node", [](const BrushState& s) { return s.split_node; },
                             "the node N_i the child tufts hang from (0: even tufts, at the root)")
      .def_property_readonly("full_state", [](const BrushState& s) { return Eigen::VectorXd(s.x); },
                             "(5n,) all variables, as Brush.full_state()")
      .def("__repr__", [](const BrushState& s) {
        std::ostringstream o;
        o << "BrushState(n_segments=" << s.x.size() / 5 << ", contacts=" << s.contacts << ")";
        return o.str();
      });
}

void bind_mesh_options(py::module_& m) {
  py::class_<MeshOptions>(m, "MeshOptions")
      .def(py::init([](int rings, int around) {
             MeshOptions o;
             o.rings_per_segment = rings;
             o.around = around;
             return o;
           }),
           py::arg("rings_per_segment") = 8, py::arg("around") = 32)
      .def_readonly("rings_per_segment", &MeshOptions::rings_per_segment)
      .def_readonly("around", &MeshOptions::around);
}

void set_wetness(Brush& b, const Eigen::VectorXd& w) {
  if (w.size() != b.wetness().size())
    throw std::invalid_argument("wetness: expected " + std::to_string(b.wetness().size()) +
                                " values (one per spine node), got " + std::to_string(w.size()));
  for (int i = 0; i < w.size(); ++i)
    if (!std::isfinite(w[i]) || w[i] < 0.0 || w[i] > 1.0)
      throw std::invalid_argument("wetness[" + std::to_string(i) + "] = " + std::to_string(w[i]) +
                                  " is outside [0, 1]");
  b.wetness() = w;
}

// (n+1, 15): center(3) u(3) w(3) n(3) a_plus a_minus c
Eigen::Matrix<double, Eigen::Dynamic, 15, Eigen::RowMajor> sections_array(const Brush& b) {
  const auto secs = b.sections();
  Eigen::Matrix<double, Eigen::Dynamic, 15, Eigen::RowMajor> a(secs.size(), 15);
  for (size_t i = 0; i < secs.size(); ++i) {
    const auto& s = secs[i];
    a.row(i) << s.center.transpose(), s.u.transpose(), s.w.transpose(), s.n.transpose(), s.a_plus,
        s.a_minus, s.c;
  }
  return a;
}

// the frame problem, for tests and other solvers
void bind_frame_problem(py::class_<Brush>& c) {
  c.def("prepare", &Brush::prepare, py::arg("pose"))
      .def_property_readonly("num_variables", &Brush::num_variables)
      .def_property_readonly("num_constraints", &Brush::num_constraints)
      .def("variables", &Brush::variables)
      .def("set_variables", &Brush::set_variables, py::arg("z"))
      .def("variable_names", &Brush::variable_names)
      .def("energy", &Brush::energy, py::arg("z"))
      .def("energy_gradient", &Brush::energy_gradient, py::arg("z"))
      .def("constraints", &Brush::constraints, py::arg("z"))
      .def("constraint_jacobian", &Brush::constraint_jacobian, py::arg("z"))
      .def("full_state", &Brush::full_state)
      .def("multipliers", &Brush::multipliers);
}

void bind_brush_class(py::module_& m) {
  py::class_<Brush> c(m, "Brush");
  c.def(py::init<const BrushModel&>(), py::arg("model"))
      .def("copy_state_from", [](Brush& self, const Brush& other) { self = other; }, py::arg("other"),
           "become an exact copy of `other`: model, state, plasticity, carried Hessian, statistics")
      .def_property_readonly("model", &Brush::model, py::return_value_policy::copy)
      .def("step", &Brush::step, py::arg("pose"), py::call_guard<py::gil_scoped_release>())
      .def("reset", &Brush::reset)
      .def_property_readonly("last_stats", &Brush::last_stats, py::return_value_policy::copy)
      .def("skeleton", py::overload_cast<>(&Brush::skeleton, py::const_))
      .def("lateral_nodes", &Brush::lateral_nodes)
      .def("section_heights", &Brush::section_heights)
      .def("clearance", &Brush::clearance,
           "mm, the lowest point of every sprouted tuft's sections Omega_i above the paper")
      .def("sections_array", &sections_array)
      .def("surface_mesh",
           [](const Brush& b, const MeshOptions& o) {
             SurfaceMesh s = b.surface_mesh(o);
             return py::make_tuple(s.vertices, s.faces, s.uv);
           },
           py::arg("options") = MeshOptions())
      .def("footprint", &Brush::footprint, py::arg("options") = MeshOptions())
      .def("footprint_area", &Brush::footprint_area, py::arg("options") = MeshOptions())
      .def("own_footprint", &Brush::own_footprint, py::arg("options") = MeshOptions(),
           "the main tuft's footprint loops alone (footprint() holds every tuft's)")
      .def_property_readonly("tufts_active", &Brush::tufts_active, "child tufts sprouted now")
      .def("_tuft_skeletons",
           [](const Brush& b) {
             std::vector<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>> all;
             for (int k : b.tufts()) all.push_back(b.skeleton(k));
             return all;
           },
           "(n_j+1, 3) mm spine of each tuft that meets the paper (Brush::tufts), the main tuft first")
      .def("state", &Brush::state, "a copy of the whole mutable state (BrushState)")
      .def("set_state", &Brush::set_state, py::arg("state"),
           "put back a state from state(); ValueError if it belongs to a brush of another shape")
      .def("_ink", py::overload_cast<>(&Brush::ink), py::return_value_policy::reference_internal,
           "the brush's own ink (a view into its state; empty until loaded)")
      .def("_set_ink", &Brush::set_ink, py::arg("ink"))
      .def("spend_ink", [](Brush& b, const DepositStats& stats, const SceneFeatures& scene,
                           Ink& ink) { b.spend_ink(stats, scene, ink); }, py::arg("stats"), py::arg("scene"), py::arg("ink"),
           "the ink's state update after a deposit (as Paper.deposit makes it): `ink` spent by what the "
           "deposit's `stats` say the paper took, in `scene`'s terms; the wetness set from it")
      .def_property(
          "wetness", [](const Brush& b) { return Eigen::VectorXd(b.wetness()); }, &set_wetness);
  bind_frame_problem(c);
}

}  // namespace

void bind_brush(py::module_& m) {
  bind_pose(m);
  bind_stats(m);
  bind_state(m);
  bind_mesh_options(m);
  bind_brush_class(m);
}
