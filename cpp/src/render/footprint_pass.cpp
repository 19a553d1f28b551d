// The footprint pass: a SweepPlan drawn into the stroke layer (seed "Ink depositing").
#include "footprint_pass.hpp"

#include <algorithm>
#include <cstdint>
#include <string>

#include "gl_util.hpp"
#include "shaders.hpp"

namespace brushwork {

namespace {

// the footprint shader's #defines for the features `scene` uses, and for max blending
std::vector<std::string> feature_defines(const SceneFeatures& scene, bool max_blend) {
  std::vector<std::string> defines = scene_defines(scene);
  if (max_blend) defines.push_back("USE_MAX_BLEND");
  return defines;
}

// write `bytes` of `data` into the buffer bound to `target`: into its storage when it is large
// enough (`have` bytes), else into new storage of the size asked
void upload_buffer(GLenum target, GLsizeiptr& have, GLsizeiptr bytes, const void* data) {
  if (bytes > have) {
    gl::BufferData(target, bytes, data, GL_DYNAMIC_DRAW);
    have = bytes;
  } else {
    gl::BufferSubData(target, 0, bytes, data);
  }
}

}  // namespace

FootprintPass::FootprintPass(RenderContext& ctx, const SceneFeatures& scene, bool max_blend)
    : scene_(scene), max_blend_(max_blend) {
  prog_ = ctx.program(shaders::kFootprintVertex, shaders::kFootprintFragment, feature_defines(scene, max_blend));
  const std::pair<GLint*, const char*> uniforms[] = {
      {&u_blends_, "u_blends"}, {&u_slides_, "u_slides"},   {&u_first_, "u_first"},
      {&u_shift_, "u_shift"},   {&u_view_, "u_view"},       {&u_soak_, "u_soak"},
      {&u_nodes_, "u_nodes"},   {&u_wet_, "u_wet"},         {&u_press_, "u_press"},
      {&u_color_, "u_color"},   {&u_maps_[0], "u_split"},   {&u_maps_[1], "u_dry"},
      {&u_maps_[2], "u_grain"}, {&u_maps_[3], "u_ramp"},    {&u_soak_shift_, "u_soak_shift"},
      {&u_dry_param_, "u_dry_param"}, {&u_texture_, "u_texture"}, {&u_frame_, "u_frame"},
      {&u_frame_s_, "u_frame_s"},     {&u_seed_, "u_seed"},       {&u_images_, "u_images"},
      {&u_density_, "u_density"}};
  for (const auto& [loc, name] : uniforms) *loc = glu::uniform(prog_, name);
  // interleaved: prev (3), cur (3), centre prev (3), centre cur (3), uv (2) floats
  glu::indexed_vertex_array(&ctx, vao_, vbo_, ibo_, {3, 3, 3, 3, 2});
}

void FootprintPass::upload(const SweepPlan& plan, const SweepFrame& last, const SweepFrame& cur) {
  // vertex data: prev, cur, centre prev, centre cur, uv
  const int V = cur.vertices();
  const std::vector<float> vb = glu::interleave(V, {{last.position.data(), 3}, {cur.position.data(), 3},
                                                      {last.center.data(), 3}, {cur.center.data(), 3},
                                                      {cur.uv.data(), 2}});
  gl::UseProgram(prog_);
  gl::BindVertexArray(vao_);
  gl::BindBuffer(GL_ARRAY_BUFFER, vbo_);
  upload_buffer(GL_ARRAY_BUFFER, vbo_bytes_, static_cast<GLsizeiptr>(vb.size() * sizeof(float)), vb.data());
  gl::BindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo_);
  upload_buffer(GL_ELEMENT_ARRAY_BUFFER, ibo_bytes_,
                static_cast<GLsizeiptr>(plan.indices.size() * sizeof(std::uint32_t)), plan.indices.data());
}

void FootprintPass::set_uniforms(const FootprintInputs& in) {
  const int nodes = static_cast<int>(in.wet.size());
  gl::Uniform1i(u_nodes_, nodes);
  gl::Uniform1fv(u_wet_, nodes, in.wet.data());
  gl::Uniform1fv(u_press_, nodes, in.pressure.data());
  gl::Uniform4f(u_color_, in.color[0], in.color[1], in.color[2], in.color[3]);
  gl::Uniform1f(u_soak_, static_cast<float>(in.soak));
  gl::Uniform1f(u_density_, static_cast<float>(in.density));
  gl::Uniform1f(u_soak_shift_, static_cast<float>(in.soak_shift));
  gl::Uniform4f(u_dry_param_, static_cast<float>(scene_.dry_onset), static_cast<float>(scene_.dry_pressure),
                static_cast<float>(scene_.grain_onset), static_cast<float>(scene_.grain_pressure));
  set_texture_uniforms(in);
  if (in.ramp != nullptr) {
    gl::BindTexture(GL_TEXTURE_2D, in.maps[3]);
    gl::TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, static_cast<GLsizei>(in.ramp->size()), 1, 0, GL_RGBA, GL_FLOAT,
                   in.ramp->data());
  }
  for (int u = 0; u < 4; ++u) {
    if (u_maps_[u] < 0 || in.maps[u] == 0) continue;
    gl::ActiveTexture(GL_TEXTURE0 + u);
    gl::BindTexture(GL_TEXTURE_2D, in.maps[u]);
    gl::Uniform1i(u_maps_[u], u);
  }
  gl::ActiveTexture(GL_TEXTURE0);
}

namespace {

// the shader's threshold of the dry map (onset dry_onset, dry_pressure) or the grain at node i:
// 1 - w_i / onset + dryness from speed - pressure p_i; above 0 the field opens there
double node_threshold(const SceneFeatures& scene, const FootprintInputs& in, std::size_t i, double onset,
                      double pressure) {
  return 1.0 - in.wet[i] / onset + scene.dry_speed * in.speed - pressure * in.pressure[i];
}

}  // namespace

double texture_coverage(const SceneFeatures& scene, const FootprintInputs& in) {
  if (!scene.dry_map && !scene.grain) return 1.0;
  auto kept = [&](std::size_t i, double onset, double pressure) {
    return 1.0 - std::clamp(node_threshold(scene, in, i, onset, pressure), 0.0, 1.0);
  };
  double sum = 0.0;
  int touching = 0;
  for (std::size_t i = 0; i < in.wet.size(); ++i) {
    if (in.pressure[i] <= 0.0f) continue;
    ++touching;
    sum += (scene.dry_map ? kept(i, scene.dry_onset, scene.dry_pressure) : 1.0) *
           (scene.grain ? kept(i, scene.grain_onset, scene.grain_pressure) : 1.0);
  }
  return touching > 0 ? sum / touching : 1.0;
}

void FootprintPass::set_texture_uniforms(const FootprintInputs& in) {
  // the shader's thresholds are linear in wetness and pressure, interpolated between the nodes:
  // their largest value over the surface is at a node
  const double from_speed = scene_.dry_speed * in.speed;
  auto opens = [&](double onset, double pressure) {
    for (std::size_t i = 0; i < in.wet.size(); ++i)
      if (node_threshold(scene_, in, i, onset, pressure) > 0.0) return true;
    return false;
  };
  const int dry = (scene_.dry_map && opens(scene_.dry_onset, scene_.dry_pressure)) ? 1 : 0;
  const int grain = (scene_.grain && opens(scene_.grain_onset, scene_.grain_pressure)) ? 2 : 0;
  gl::Uniform4f(u_texture_, static_cast<float>(1.0 / scene_.streak_mm), static_cast<float>(1.0 / scene_.grain_mm),
                static_cast<float>(from_speed), static_cast<float>(dry | grain));
  gl::Uniform4f(u_frame_, in.frame[0], in.frame[1], in.frame[2], in.frame[3]);
  gl::Uniform1f(u_frame_s_, static_cast<float>(in.frame_s));
  gl::Uniform1i(u_seed_, static_cast<GLint>(in.seed));
  int images = 0;  // bit u: map u (split, dry, grain) is an image
  for (int u = 0; u < 3; ++u)
    if (in.maps[u] != 0) images |= 1 << u;
  gl::Uniform1i(u_images_, images);
}

void FootprintPass::set_state() {
  // downward-facing triangles only (seen from below, a face whose outward normal points down is
  // clockwise on the paper), densest wins (max blend, or depth test on 1 - alpha with a colour
  // ramp)
  if (max_blend_) {
    gl::Disable(GL_DEPTH_TEST);
    gl::Enable(GL_BLEND);
    gl::BlendEquation(GL_MAX);
  } else {
    gl::Enable(GL_DEPTH_TEST);
    gl::DepthFunc(GL_LESS);
    gl::DepthMask(GL_TRUE);
    gl::Disable(GL_BLEND);
  }
  gl::Enable(GL_CULL_FACE);
  gl::FrontFace(GL_CCW);
  gl::CullFace(GL_FRONT);
  gl::Enable(GL_SCISSOR_TEST);
}

void FootprintPass::begin(const SweepPlan& plan, const SweepFrame& last, const SweepFrame& cur,
                          const FootprintInputs& in, double px_per_mm) {
  ppm_ = px_per_mm;
  upload(plan, last, cur);
  set_uniforms(in);
  set_state();
}

void FootprintPass::draw(const SweepPlan& plan, const LayerTile& t) {
  gl::UseProgram(prog_);
  gl::BindVertexArray(vao_);
  gl::BindFramebuffer(GL_FRAMEBUFFER, t.fbo);
  gl::Viewport(0, 0, t.w, t.h);
  gl::Scissor(t.sx, t.sy, t.sw, t.sh);
  gl::Uniform4f(u_view_, static_cast<float>(t.x0 / ppm_), static_cast<float>(t.y0 / ppm_),
                static_cast<float>(2.0 * ppm_ / t.w), static_cast<float>(2.0 * ppm_ / t.h));
  // the sweep between the last deposit and this one: the surface blended from one to the
  // other over K sub-steps (right for a tuft that turns or bends on the way), and each of
  // the two parts below the paper slid rigidly along the move of the footprint's centre
  // toward the other (so that a tuft whose shape changes a lot between frames still
  // leaves one unbroken band: the blend alone lifts off the paper halfway between a
  // pressed blob and a thin trailing tip).  The price: where the shape changes abruptly
  // the slid blob paints a little more than the brush touched.
  const int K = plan.blends;
  gl::Uniform1i(u_blends_, K);
  gl::Uniform2i(u_slides_, plan.slides_prev, plan.slides_cur);
  gl::Uniform2f(u_shift_, static_cast<float>(plan.shift_x), static_cast<float>(plan.shift_y));
  // instanced draws: the blends before t = 1 over the near faces, t = 1 over all, the last
  // part slid and this part slid over theirs; u_first numbers the instances on from the
  // draws before
  auto run = [&](std::size_t offset, std::size_t size, int first, int count) {
    if (count <= 0 || size == 0) return;
    gl::Uniform1i(u_first_, first);
    gl::DrawElementsInstanced(GL_TRIANGLES, static_cast<GLsizei>(size), GL_UNSIGNED_INT,
                              reinterpret_cast<const void*>(offset * sizeof(std::uint32_t)), count);
  };
  run(0, plan.near, 0, K - 1);
  run(0, plan.all, K - 1, 1);
  run(plan.all, plan.prev, K, plan.slides_prev);
  run(plan.all + plan.prev, plan.cur, K + plan.slides_prev, plan.slides_cur);
}

void FootprintPass::end() {
  gl::Disable(GL_SCISSOR_TEST);
  gl::Disable(GL_CULL_FACE);
  gl::Disable(GL_DEPTH_TEST);
  gl::BlendEquation(GL_FUNC_ADD);
  gl::Disable(GL_BLEND);
  gl::BindVertexArray(0);
  glu::check("footprint pass");
}

}  // namespace brushwork
