// The brushwork._core module: one thin bind_<area>.cpp per area (Dr.Jit's layout).
// C++ std::invalid_argument becomes Python ValueError (pybind11's built-in translation), so bad
// input never aborts the process.
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_model(py::module_& m);
void bind_brush(py::module_& m);
void bind_render(py::module_& m);
void bind_ink(py::module_& m);

PYBIND11_MODULE(_core, m) {
  m.doc() = "brushwork C++ core: the Chu-Tai brush tuft, its SQP dynamics and geometry, and its EGL renderer";
  bind_model(m);
  bind_brush(m);
  bind_render(m);
  bind_ink(m);
}
