// An offscreen view of the brush over the paper (seed Figure 8).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "brushwork/render/context.hpp"
#include "brushwork/render/gl_name.hpp"
#include "brushwork/render/paper.hpp"

namespace brushwork {

// How to look at the brush over the paper.
struct ViewOptions {
  std::string mode = "shaded";  // "shaded" | "outlined" | "transparent"
  bool shadow = true;
  Eigen::Vector3d eye{0.0, -60.0, 80.0};  // camera position, mm
  Eigen::Vector3d target{0.0, 0.0, 10.0}; // looked-at point, mm
  double fov_deg = 35.0;                  // vertical field of view; 0: orthographic
  double ortho_height_mm = 80.0;          // orthographic: paper height seen, mm
  Eigen::Vector3d light{-0.4, -0.5, 1.0}; // direction toward the light (normalised here)
  void validate() const;
};

// An offscreen image of the brush over the paper, multisampled (seed Figure 8).
class BrushView {
 public:
  BrushView(int width_px, int height_px);
  ~BrushView();
  BrushView(const BrushView&) = delete;
  BrushView& operator=(const BrushView&) = delete;
  int width_px() const { return W_; }
  int height_px() const { return H_; }
  // (H, W, 4) RGBA8 into `out`, row 0 at the top; paper and ink may be null.  The main tuft
  // takes the colours of `ink`, a child tuft those of its own ink (black unless both are loaded)
  void render(Paper* paper, const BrushFrame& brush, const Ink* ink, const ViewOptions& o,
              std::uint8_t* out);

 private:
  void draw_paper(const std::vector<Paper::TileRef>& tiles, double px_per_mm, const float* mvp);
  // the tuft's surface and its colours root..tip (null: black); indices of its triangles
  int upload_tuft(const TuftFrame& tuft, const std::vector<std::array<float, 4>>* ramp);
  void draw_tuft(const ViewOptions& o, bool shadow, int n_idx, float dist, const float* mvp);
  void read_back(std::uint8_t* out);  // (H, W, 4) RGBA8, row 0 at the top

  std::shared_ptr<RenderContext> ctx_;
  int W_, H_;
  GlFramebuffer fbo_ms_, fbo_;
  GlRenderbuffer color_ms_, depth_ms_;
  GlTexture color_, ramp_tex_;
  unsigned brush_prog_ = 0, paper_prog_ = 0;  // owned by the context
  GlVertexArray vao_, paper_vao_;
  GlBuffer vbo_, ibo_, paper_vbo_;
};

}  // namespace brushwork
