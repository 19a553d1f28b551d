// The depth pass of the 3-D outlines: a triangle mesh seen through a camera matrix, rendered
// through the process's EGL context into a float depth image (visibility of feature lines).
#pragma once

#include <cstdint>

namespace brushwork {

// Render `n_faces` triangles (`faces`, (m, 3) vertex indices) over `n_vertices` points
// (`vertices`, (n, 3), any unit, in double precision) through the row-major 4x4 `matrix` M of the camera convention
// p = M [v, 1]: pixel (p0/p3, p1/p3) with x right, y down, origin at the top-left corner of a
// `width` x `height` image, and depth p2/p3 in [-1, 1], growing away from the camera.
// `out` receives (height, width) floats, row 0 at the top: the depth p2/p3 of the nearest
// surface at each pixel centre, +inf where no triangle covers it.  Both faces of every
// triangle are drawn (open meshes have no inside).  Throws std::invalid_argument on bad sizes
// or indices, std::runtime_error when rendering fails.
void render_depth(const double* vertices, int n_vertices, const std::int64_t* faces, int n_faces,
                  const double* matrix, int width, int height, float* out);

}  // namespace brushwork
