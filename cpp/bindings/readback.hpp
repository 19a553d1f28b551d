// The readbacks every paper binds alike (GL's Paper and the geometry's VectorPaper): the ink,
// premultiplied RGBA and an 8- or 16-bit image as numpy arrays, filled with the GIL released.
#pragma once

#include <cstdint>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace brushwork {

template <class PaperT, class... Options>
void bind_readbacks(pybind11::class_<PaperT, Options...>& cls) {
  namespace py = pybind11;
  cls.def("ink", [](PaperT& p) {
       py::array_t<float> a({p.height_px(), p.width_px()});
       float* out = a.mutable_data();
       py::gil_scoped_release nogil;
       p.read_ink(out);
       return a;
     }, "(H, W) float32 ink coverage in [0, 1], row 0 at the top of the paper")
      .def("rgba", [](PaperT& p) {
        py::array_t<float> a({p.height_px(), p.width_px(), 4});
        float* out = a.mutable_data();
        py::gil_scoped_release nogil;
        p.read_rgba(out);
        return a;
      }, "(H, W, 4) float32 premultiplied RGBA, row 0 at the top")
      .def("_image", [](PaperT& p, int bits, bool white, bool bgr) -> py::array {
        // (read_image checks bits; a wrong value gets a uint16 array it never fills)
        const std::vector<py::ssize_t> shape{p.height_px(), p.width_px(), white ? 3 : 4};
        py::array a = bits == 8 ? py::array(py::dtype::of<std::uint8_t>(), shape)
                                : py::array(py::dtype::of<std::uint16_t>(), shape);
        void* out = a.mutable_data();
        py::gil_scoped_release nogil;
        p.read_image(bits, white, bgr, out);
        return a;
      }, py::arg("bits"), py::arg("white"), py::arg("bgr"),
      "(H, W, 3) ink over white or (H, W, 4) straight RGBA, uint8 or uint16, row 0 at the top");
}

}  // namespace brushwork
