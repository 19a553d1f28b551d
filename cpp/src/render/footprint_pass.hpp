// The footprint pass (seed "Ink depositing"): draws a SweepPlan into the stroke layer, one tile
// at a time: the surface blended from the last deposit to this one over K sub-steps and the
// two parts below the paper slid along the move of the footprint's centre, densest ink wins.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "brushwork/render.hpp"
#include "brushwork/sweep_plan.hpp"
#include "gl_api.hpp"

namespace brushwork {

// most spine nodes the footprint shader takes (its u_wet / u_press arrays; 16 segments need 17)
constexpr int kMaxNodes = 33;

// What one deposit draws with besides its plan.
struct FootprintInputs {
  std::vector<float> wet;         // (n+1) the brush's wetness per node, [0, 1]
  std::vector<float> pressure;    // (n+1) node pressure, [0, 1] (node_pressure)
  std::array<float, 4> color{{0, 0, 0, 1}};  // straight RGBA of the ink (no ramp)
  const std::vector<std::array<float, 4>>* ramp = nullptr;  // root .. tip colours (colour ramp scenes)
  double soak = 0.0;              // soak_expand * excess moisture: the tip's growth
  double density = 1.0;           // depletion: the ink's density over this footprint, [0, 1]
  double soak_shift = 0.0;        // soak_shift * excess moisture: the split map's shift to the tip
  std::array<GLuint, 4> maps{{0, 0, 0, 0}};  // split, dry, grain images, ramp texture (0: none)
  std::array<float, 4> frame{{0, 0, 1, 0}};  // stroke frame: centre (mm), unit travel direction
  double frame_s = 0.0;           // mm: the centre's travel along the stroke
  double speed = 0.0;             // mm per deposit: the centre's move
  std::uint32_t seed = 1;         // the procedural fields' seed (the scene's, offset per tuft)
};

// The share of a footprint drawn with `in` that the dry map and the paper's grain leave inked, on
// average over its touching nodes (each field thresholded at t keeps about 1 - t of the paper,
// the shader's `spread`): what the ink a deposit spends is scaled by (Paper::wet_gain).
double texture_coverage(const SceneFeatures& scene, const FootprintInputs& in);

// A tile of the stroke layer to draw into: its framebuffer, where it lies on the paper (px, y
// up) and the part of it to touch (px, tile-relative).
struct LayerTile {
  GLuint fbo = 0;
  int x0 = 0, y0 = 0, w = 0, h = 0;
  int sx = 0, sy = 0, sw = 0, sh = 0;
};

// The footprint program of one scene (its features compiled in) and its vertex buffers.
class FootprintPass {
 public:
  // max_blend: the layer keeps the densest deposit by max blending (one ink colour); otherwise
  // by the depth test on 1 - alpha
  FootprintPass(RenderContext& ctx, const SceneFeatures& scene, bool max_blend);

  // upload the vertices of `last` and `cur`, the indices of `plan` and the uniforms; set the
  // blend, depth, cull and scissor state for draw()
  void begin(const SweepPlan& plan, const SweepFrame& last, const SweepFrame& cur, const FootprintInputs& in,
             double px_per_mm);
  void draw(const SweepPlan& plan, const LayerTile& t);
  void end();  // restore the GL state begin() changed

 private:
  void upload(const SweepPlan& plan, const SweepFrame& last, const SweepFrame& cur);
  void set_uniforms(const FootprintInputs& in);
  void set_texture_uniforms(const FootprintInputs& in);  // the split, dry and grain fields' part
  void set_state();

  SceneFeatures scene_;
  bool max_blend_ = false;
  double ppm_ = 1.0;
  GLuint prog_ = 0;  // owned by the context
  GlVertexArray vao_;
  GlBuffer vbo_, ibo_;
  // bytes allocated to vbo and ibo: a deposit that fits writes into them (glBufferSubData)
  // rather than allocating new storage each frame, which llvmpipe clears and copies (~7% of a
  // 1024 px deposit's instructions, counted under valgrind); llvmpipe flushes the last frame
  // before the buffers are written again (the same time and pixels)
  GLsizeiptr vbo_bytes_ = 0, ibo_bytes_ = 0;
  GLint u_blends_ = -1, u_slides_ = -1, u_first_ = -1, u_shift_ = -1, u_view_ = -1, u_soak_ = -1;
  GLint u_nodes_ = -1, u_wet_ = -1, u_press_ = -1, u_color_ = -1, u_soak_shift_ = -1, u_density_ = -1;
  GLint u_dry_param_ = -1, u_texture_ = -1, u_frame_ = -1, u_frame_s_ = -1, u_seed_ = -1, u_images_ = -1;
  std::array<GLint, 4> u_maps_{{-1, -1, -1, -1}};  // u_split, u_dry, u_grain, u_ramp
};

}  // namespace brushwork
