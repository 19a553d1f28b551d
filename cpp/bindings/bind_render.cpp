// RenderContext, Scene, Ink, DepositStats and Paper.  Images cross as numpy float32, row 0 at
// the top of the paper.  The GL context is bound to the calling thread on every call, so the
// GIL stays held: two Python threads must not render at once.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "brushwork/brush.hpp"
#include "brushwork/depth.hpp"
#include "brushwork/render.hpp"
#include "brushwork/write.hpp"
#include "readback.hpp"

namespace py = pybind11;
using namespace brushwork;

namespace {

py::dict info_dict(const RenderInfo& i) {
  py::dict d;
  d["backend"] = i.backend;
  d["device_index"] = i.device_index;
  d["device_count"] = i.device_count;
  d["vendor"] = i.vendor;
  d["renderer"] = i.renderer;
  d["version"] = i.version;
  d["max_texture_size"] = i.max_texture_size;
  return d;
}

using FloatImage = py::array_t<float, py::array::c_style | py::array::forcecast>;

// the sweep plan from `last` (None: a stroke starts) to `brush` on a paper of width_px x
// height_px at px_per_mm, as Paper.deposit would draw it with `scene`'s mesh and soaked tip
py::dict sweep_plan_dict(const Brush& brush, const Brush* last, double px_per_mm, int width_px, int height_px,
                         const SceneFeatures& scene, double excess) {
  scene.validate();
  const MeshOptions opt =
      mesh_options_for(brush.model(), px_per_mm, scene.mesh_mm, scene.mesh_rings, scene.mesh_around);
  const double soak = scene.soaked_tip ? scene.soak_expand * excess : 0.0;
  const SweepFrame cur = sweep_frame(brush.sections(), opt, soak);
  SweepFrame from;
  if (last != nullptr) from = sweep_frame(last->sections(), opt, soak);
  if (last != nullptr && from.position.size() != cur.position.size())
    throw std::invalid_argument("sweep_plan: the two brushes must be of one model");
  const SweepPlan plan = plan_sweep(last != nullptr ? &from : nullptr, cur, px_per_mm, width_px, height_px);
  py::dict d;
  d["contact"] = plan.contact;
  d["new_stroke"] = plan.contact && !plan.continues;
  d["blends"] = plan.blends;
  d["slides"] = py::make_tuple(plan.slides_prev, plan.slides_cur);
  d["near_faces"] = plan.near / 3;
  d["faces"] = plan.all / 3;
  d["shift_mm"] = py::make_tuple(plan.shift_x, plan.shift_y);
  d["travel_mm"] = plan.travel;
  d["rect"] = plan.rect;
  d["draws"] = plan.draws();
  return d;
}

// render_depth: the depth pass of the 3-D outlines
void bind_depth(py::module_& m) {
  m.def("render_depth", [](const py::array_t<double, py::array::c_style | py::array::forcecast>& vertices,
                           const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& faces,
                           const py::array_t<double, py::array::c_style | py::array::forcecast>& matrix,
                           int width, int height) {
    if (vertices.ndim() != 2 || vertices.shape(1) != 3 || faces.ndim() != 2 || faces.shape(1) != 3)
      throw std::invalid_argument("render_depth: expected vertices (n, 3) and faces (m, 3)");
    if (matrix.ndim() != 2 || matrix.shape(0) != 4 || matrix.shape(1) != 4)
      throw std::invalid_argument("render_depth: expected a 4 x 4 matrix");
    py::array_t<float> out({height > 0 ? height : 0, width > 0 ? width : 0});
    render_depth(vertices.data(), static_cast<int>(vertices.shape(0)), faces.data(), static_cast<int>(faces.shape(0)),
                 matrix.data(), width, height, out.mutable_data());
    return out;
  }, py::arg("vertices"), py::arg("faces"), py::arg("matrix"), py::arg("width"), py::arg("height"), R"doc(
(height, width) float32 depth of a triangle mesh through the camera matrix M (row-major 4 x 4, p =
M [v, 1], pixel (p0/p3, p1/p3), x right, y down from the top-left corner): p2/p3 of the nearest
surface at each pixel centre, +inf where the mesh does not cover it. vertices (n, 3), faces (m, 3).)doc");
}

// one field of SceneFeatures as a Python attribute of its row's type
void bind_scene_field(py::class_<SceneFeatures>& c, const SceneSlot& slot) {
  if (slot.flag) c.def_readwrite(slot.name, slot.flag, slot.doc);
  if (slot.real) c.def_readwrite(slot.name, slot.real, slot.doc);
  if (slot.count) c.def_readwrite(slot.name, slot.count, slot.doc);
  if (slot.seed) c.def_readwrite(slot.name, slot.seed, slot.doc);
}

py::list scene_slot_dicts() {
  py::list rows;
  for (const SceneSlot& slot : scene_slots())
    rows.append(py::dict(py::arg("name") = slot.name, py::arg("unit") = slot.unit, py::arg("kind") = slot.kind,
                         py::arg("default") = slot.value, py::arg("lo") = slot.lo, py::arg("hi") = slot.hi,
                         py::arg("expected") = slot.expected ? py::object(py::str(slot.expected)) : py::none(),
                         py::arg("define") = slot.define, py::arg("doc") = slot.doc));
  return rows;
}

void bind_context_scene(py::module_& m) {
  py::class_<RenderContext, std::shared_ptr<RenderContext>>(m, "RenderContext", R"doc(
This thread's OpenGL context through EGL (shared by every Paper and BrushView the thread makes; each
renders on the thread that made it). BRUSHWORK_RENDER = auto | gpu |
software | disable and BRUSHWORK_EGL_DEVICE = index choose it. close() may be called twice.)doc")
      .def_static("acquire", &RenderContext::acquire)
      .def_property_readonly("info", [](const RenderContext& c) { return info_dict(c.info()); })
      .def_property_readonly("closed", &RenderContext::closed)
      .def("close", &RenderContext::close)
      .def("__enter__", [](std::shared_ptr<RenderContext> c) { return c; })
      .def("__exit__", [](RenderContext& c, py::args) { c.close(); });

  py::class_<SceneFeatures> scene(m, "SceneFeatures", R"doc(
What a scene uses; what it does not use is not computed and not compiled into the shaders.
Its fields are the rows of scene_slots().)doc");
  scene.def(py::init<>()).def("validate", &SceneFeatures::validate);
  for (const SceneSlot& slot : scene_slots()) bind_scene_field(scene, slot);
  m.def("scene_slots", &scene_slot_dicts, "the scene's table: one dict per field (name, unit, kind, "
        "default, lo, hi, expected, define, doc), features first");
}

void bind_ink_stats(py::module_& m) {
  py::class_<Ink>(m, "Ink", R"doc(
Ink on one brush. ramp: (K, 4) straight RGBA root..tip; load, capacity: (n+1,) mm^2 of paper at
full density per spine node (wetness = load / capacity); excess: soaked-tip moisture 0..1;
deposited: mm^2 given to the paper so far (depletion scenes).)doc")
      .def(py::init([](const Brush& brush, double total_mm2) { return Ink::full(brush.sections(), total_mm2); }),
           py::arg("brush"), py::arg("total_mm2") = 2000.0)
      .def_property(
          "ramp", [](const Ink& k) { return k.ramp; },
          [](Ink& k, const std::vector<std::array<float, 4>>& r) {
            Ink t = k;
            t.ramp = r;
            t.validate(static_cast<int>(k.load.size()));
            k.ramp = r;
          })
      .def_readwrite("load", &Ink::load)
      .def_readwrite("capacity", &Ink::capacity)
      .def_readwrite("excess", &Ink::excess)
      .def_readwrite("deposited", &Ink::deposited)
      .def("total", &Ink::total, "mm^2 of ink left on the brush")
      .def("validate", &Ink::validate, py::arg("nodes"));

  py::class_<DepositStats>(m, "DepositStats")
      .def_readonly("contact", &DepositStats::contact)
      .def_readonly("new_stroke", &DepositStats::new_stroke)
      .def_readonly("substeps", &DepositStats::substeps)
      .def_readonly("slides", &DepositStats::slides, "copies of a footprint slid along its move (the larger of the last and this part's count)")
      .def_readonly("deposited", &DepositStats::deposited, "mm^2 (depletion scenes)")
      .def_readonly("rect", &DepositStats::rect, "px (x0, y0, x1, y1), y up, exclusive")
      .def("__repr__", [](const DepositStats& s) {
        return "DepositStats(contact=" + std::string(s.contact ? "True" : "False") +
               ", new_stroke=" + (s.new_stroke ? "True" : "False") +
               ", substeps=" + std::to_string(s.substeps) +
               ", deposited=" + std::to_string(s.deposited) + ")";
      });

  m.def("sweep_plan", &sweep_plan_dict, py::arg("brush"), py::arg("last") = nullptr, py::arg("px_per_mm") = 10.0,
        py::arg("width_px") = 1024, py::arg("height_px") = 1024, py::arg("scene") = SceneFeatures(),
        py::arg("excess") = 0.0, R"doc(
The footprint pass's plan from `last` (a brush at the last deposit; None: a stroke starts) to
`brush`, without drawing: dict of contact, new_stroke, blends (sub-steps K), slides (copies of the
last and this part), near_faces and faces (triangles drawn by the blends before t = 1 and at
t = 1), shift_mm, travel_mm, rect (px x0, y0, x1, y1, y up, exclusive) and draws.)doc");

}

void bind_paper(py::module_& m) {
  bind_readbacks(py::class_<Paper>(m, "Paper")
      .def(py::init<double, double, double, const SceneFeatures&, int>(), py::arg("width_mm"),
           py::arg("height_mm"), py::arg("px_per_mm"), py::arg("scene") = SceneFeatures(),
           py::arg("tile_px") = 0, py::keep_alive<1, 5>(), py::call_guard<py::gil_scoped_release>())
      .def("deposit", [](Paper& p, Brush& brush, Ink* ink) {
        // draw, then spend the brush's ink by what was drawn (other Python threads run meanwhile)
        py::gil_scoped_release nogil;
        return brushwork::deposit(p, brush, ink);
      }, py::arg("brush"), py::arg("ink") = nullptr)
      .def("end_stroke", &Paper::end_stroke, py::call_guard<py::gil_scoped_release>())
      .def("undo", &Paper::undo, py::call_guard<py::gil_scoped_release>())
      .def("clear", &Paper::clear, py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("width_px", &Paper::width_px)
      .def_property_readonly("height_px", &Paper::height_px)
      .def_property_readonly("px_per_mm", &Paper::px_per_mm)
      .def_property_readonly("width_mm", &Paper::width_mm)
      .def_property_readonly("height_mm", &Paper::height_mm)
      .def_property_readonly("tile_px", &Paper::tile_px)
      .def_property_readonly("tiles", &Paper::tiles)
      .def_property_readonly("samples", &Paper::samples, "multisampling of the stroke layer")
      .def_property_readonly("scene", &Paper::scene)
      .def("mesh_options", &Paper::mesh_options, py::arg("model"),
           "the render mesh (rings per segment, around) a brush of this model gets on this paper")
      .def("set_rgba", [](Paper& p, const FloatImage& a) {
        if (a.ndim() != 3 || a.shape(0) != p.height_px() || a.shape(1) != p.width_px() || a.shape(2) != 4)
          throw std::invalid_argument("set_rgba: expected a (" + std::to_string(p.height_px()) + ", " +
                                      std::to_string(p.width_px()) + ", 4) array");
        const float* in = a.data();
        py::gil_scoped_release nogil;
        p.write_rgba(in);
      }, py::arg("rgba"))
      .def("set_map", [](Paper& p, const std::string& which, const FloatImage& a) {
        if (a.ndim() != 2) throw std::invalid_argument("set_map: expected a 2-D grey-scale array");
        p.set_map(which, a.data(), static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)));
      }, py::arg("which"), py::arg("image")));
}

void bind_view(py::module_& m) {
  py::class_<ViewOptions>(m, "ViewOptions", R"doc(
Brush view camera and style. mode: shaded | outlined | transparent; eye, target: mm; fov_deg: 0
for orthographic (then ortho_height_mm is the height seen); light: direction toward the light.)doc")
      .def(py::init<>())
      .def_readwrite("mode", &ViewOptions::mode)
      .def_readwrite("shadow", &ViewOptions::shadow)
      .def_readwrite("eye", &ViewOptions::eye)
      .def_readwrite("target", &ViewOptions::target)
      .def_readwrite("fov_deg", &ViewOptions::fov_deg)
      .def_readwrite("ortho_height_mm", &ViewOptions::ortho_height_mm)
      .def_readwrite("light", &ViewOptions::light)
      .def("validate", &ViewOptions::validate);

  py::class_<BrushView>(m, "BrushView", "An offscreen image of the brush over the paper.")
      .def(py::init<int, int>(), py::arg("width_px"), py::arg("height_px"), py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("width_px", &BrushView::width_px)
      .def_property_readonly("height_px", &BrushView::height_px)
      .def("render", [](BrushView& v, Paper* paper, const Brush& brush, const Ink* ink, const ViewOptions& o) {
        py::array_t<std::uint8_t> a({v.height_px(), v.width_px(), 4});
        std::uint8_t* out = a.mutable_data();
        py::gil_scoped_release nogil;
        v.render(paper, brush.frame(), ink, o, out);
        return a;
      }, py::arg("paper"), py::arg("brush"), py::arg("ink") = nullptr, py::arg("options") = ViewOptions(),
      "(H, W, 4) uint8 RGBA, row 0 at the top");
}

}  // namespace

void bind_render(py::module_& m) {
  bind_context_scene(m);
  bind_ink_stats(m);
  bind_paper(m);
  bind_view(m);
  bind_depth(m);
}
