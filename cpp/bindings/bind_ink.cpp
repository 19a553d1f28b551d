// Ink as geometry: VectorPaper, and the sweep, union and coverage it is made of.  Loops cross as
// lists of (k, 2) float64 arrays in mm.  Nothing here needs a GL context; the GIL is released
// around the deposit and the readbacks.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "brushwork/ink_geometry.hpp"
#include "brushwork/write.hpp"
#include "readback.hpp"

namespace py = pybind11;
using namespace brushwork;

namespace {

using Rows3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Faces = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

SurfaceMesh mesh_of(const Rows3& v, const Faces& f) {
  SurfaceMesh m;
  m.vertices = v;
  m.faces = f;
  return m;
}

void bind_functions(py::module_& m) {
  py::class_<SweepTolerance>(m, "SweepTolerance", "How finely the sweep between two frames is followed.")
      .def(py::init([](double tol_mm, int max_samples) { return SweepTolerance{tol_mm, max_samples}; }),
           py::arg("tol_mm") = 0.005, py::arg("max_samples") = 256)
      .def_readwrite("tol_mm", &SweepTolerance::tol_mm, "mm: the swept edge's distance from the continuous sweep")
      .def_readwrite("max_samples", &SweepTolerance::max_samples, "most blends between two frames");
  m.def("union_loops", &union_loops, py::arg("loops"),
        "the union (winding > 0) of loops [(k, 2) mm] as non-overlapping contours: outer ccw, holes cw");
  m.def("coverage", [](const Loops& loops, double px_per_mm, int width, int height) {
    if (width < 1 || height < 1 || width > 32768 || height > 32768)
      throw std::invalid_argument("coverage: width and height must be 1..32768 px");
    py::array_t<float> a({height, width});
    float* out = a.mutable_data();
    {
      py::gil_scoped_release nogil;
      coverage(loops, px_per_mm, width, height, out);
    }
    return a;
  }, py::arg("loops"), py::arg("px_per_mm"), py::arg("width"), py::arg("height"), R"doc(
(height, width) float32 exact area coverage of the region inside non-overlapping loops (mm, y up),
pixel (i, j) covering [i, i+1] x [j, j+1] / px_per_mm mm; row 0 at the top.)doc");
  m.def("swept_footprint", [](const Rows3& last_v, const Rows3& cur_v, const Faces& faces, const SweepTolerance& tol) {
    int samples = 0;
    Loops l = swept_footprint(mesh_of(last_v, faces), mesh_of(cur_v, faces), tol, &samples);
    return py::make_tuple(l, samples);
  }, py::arg("last_vertices"), py::arg("vertices"), py::arg("faces"), py::arg("tolerance") = SweepTolerance(), R"doc(
(loops, blends): the region a surface covers below z = 0 moving linearly from last_vertices to
vertices (V, 3) mm over faces (F, 3), as overlapping loops whose union is the region.)doc");
  m.def("footprint_projection", [](const Rows3& v, const Faces& faces) {
    return footprint_projection(mesh_of(v, faces));
  }, py::arg("vertices"), py::arg("faces"), R"doc(
The footprint as the seed defines it: loops [(k, 2) mm] around the orthogonal projection onto the
paper of the closed surface's part below z = 0 (vertices (V, 3) mm, faces (F, 3) outward); their
union (winding > 0) is the region. It holds the plane section (Brush.footprint) and reaches past it
where a section's widest points lie below the paper; its silhouette is where the vertex normals' z,
interpolated over each face, is 0.)doc");
}

}  // namespace

void bind_ink(py::module_& m) {
  bind_functions(m);
  bind_readbacks(py::class_<VectorPaper>(m, "VectorPaper", R"doc(
A paper whose ink is geometry: strokes as contours in mm, unioned, rasterised with exact coverage on
readback; no GL context. Opaque scenes only (no split, dry or grain map, soaked tip, colour ramp).)doc")
      .def(py::init<double, double, double, const SceneFeatures&, const SweepTolerance&>(), py::arg("width_mm"),
           py::arg("height_mm"), py::arg("px_per_mm"), py::arg("scene") = SceneFeatures(),
           py::arg("tolerance") = SweepTolerance())
      .def("deposit", [](VectorPaper& p, Brush& brush, Ink* ink) {
        DepositStats stats;
        {
          py::gil_scoped_release nogil;
          stats = brushwork::deposit(p, brush, ink);
        }
        return stats;
      }, py::arg("brush"), py::arg("ink") = nullptr)
      .def("end_stroke", &VectorPaper::end_stroke)
      .def("undo", &VectorPaper::undo)
      .def("clear", &VectorPaper::clear)
      .def_property_readonly("width_px", &VectorPaper::width_px)
      .def_property_readonly("height_px", &VectorPaper::height_px)
      .def_property_readonly("px_per_mm", &VectorPaper::px_per_mm)
      .def_property_readonly("width_mm", &VectorPaper::width_mm)
      .def_property_readonly("height_mm", &VectorPaper::height_mm)
      .def_property_readonly("scene", &VectorPaper::scene)
      .def_property_readonly("tolerance", &VectorPaper::tolerance)
      .def("mesh_options", &VectorPaper::mesh_options, py::arg("model"))
      .def("outlines", [](VectorPaper& p) {
        py::gil_scoped_release nogil;
        return p.outlines();
      }, "the union of every stroke's region: [(k, 2) float64 mm], outer loops ccw, holes cw")
      .def_property_readonly("timings", [](const VectorPaper& p) {
        py::dict d;
        d["sweep_s"] = p.sweep_seconds();
        d["union_s"] = p.union_seconds();
        d["raster_s"] = p.raster_seconds();
        return d;
      }, "seconds: the deposits' sweeps (all so far), the last readback's union and raster"));
}
