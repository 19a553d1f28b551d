// A tuft's swept surface (its sections Omega_0..Omega_n swept) re-laid for the GPU: rings of `around + 1` vertices (the first
// column repeated at around = 1 so that textures do not wrap backwards across the seam), the
// root cap and the tip apex, with the core's outward CCW triangles re-indexed.
#pragma once

#include <cstdint>
#include <vector>

#include "brushwork/geometry.hpp"

namespace brushwork {

struct RenderMesh {
  std::vector<float> position;  // (V, 3) mm
  std::vector<float> center;    // (V, 3) mm, centre of the vertex's ring (the spine point)
  std::vector<float> uv;        // (V, 2): along the spine (node i at i / n; tip apex 1), around
  std::vector<float> normal;    // (V, 3) unit outward vertex normals
  std::vector<std::uint32_t> faces;  // (F, 3) outward counter-clockwise
  int vertices() const { return static_cast<int>(position.size() / 3); }
};

// with_normals = false leaves `normal` empty (the footprint pass needs none; they cost about
// as much as the re-layout itself)
RenderMesh build_render_mesh(const std::vector<Section>& sections, const MeshOptions& opt, bool with_normals = true);

}  // namespace brushwork
