// A paper canvas of float ink in tiles (seed "Ink depositing"), the footprint pass depositing
// what the brush leaves on it.
//
// Coordinates: paper millimetres, x right, y up, origin at the paper's bottom-left corner, paper at
// z = 0 and z up (the brush core's frame).  Pixel (i, j) of the paper covers
// [i, i+1] x [j, j+1] / px_per_mm mm, row j = 0 at the bottom; readback flips rows once so that
// numpy row 0 is the top of the paper.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "brushwork/model.hpp"
#include "brushwork/render/context.hpp"
#include "brushwork/render/deposit.hpp"
#include "brushwork/render/gl_name.hpp"
#include "brushwork/scene.hpp"
#include "brushwork/sweep_plan.hpp"

namespace brushwork {

class FootprintPass;  // internal
class StrokeFrame;    // internal
class WetLedger;      // internal
struct PaperTile;        // internal

// A canvas of float ink: premultiplied RGBA, alpha = ink coverage.  Strokes go first into a
// stroke layer where the densest deposit wins (a bristle passing twice does not double the ink);
// the layer is composited over the paper (alpha blending of transparent colours) when the
// stroke ends, and can be undone until then or after (one level).
class Paper {
 public:
  Paper(double width_mm, double height_mm, double px_per_mm, const SceneFeatures& scene,
        int tile_px = 0);  // tile_px 0: the largest the GL allows, at most 4096
  ~Paper();
  Paper(const Paper&) = delete;
  Paper& operator=(const Paper&) = delete;

  // draw the brush's footprint swept from its last deposit; ink may be null: black, constant
  // level.  The ink and the brush are left as they are: spend_ink() applies the stats to them.
  // A split brush deposits every tuft of the frame, each swept from its own last deposit,
  // through its own stroke frame and its own seed of the split and dry fields
  DepositStats deposit(const BrushFrame& brush, const Ink* ink);
  void end_stroke();   // composite the stroke layer (also on lift, readback and save)
  bool undo();         // remove the last stroke; false when there is none
  void clear();

  int width_px() const { return W_; }
  int height_px() const { return H_; }
  double px_per_mm() const { return ppm_; }
  double width_mm() const { return width_mm_; }
  double height_mm() const { return height_mm_; }
  int tile_px() const { return T_; }
  int tiles() const { return static_cast<int>(tiles_.size()); }
  int samples() const { return samples_; }  // multisampling of the stroke layer
  const SceneFeatures& scene() const { return scene_; }
  // the render mesh a brush of `model` gets on this paper (see SceneFeatures::mesh_mm)
  MeshOptions mesh_options(const BrushModel& model) const;

  // (H, W, 4) premultiplied RGBA float32, row 0 at the top of the paper
  void read_rgba(float* out);
  // (H, W) ink coverage float32, row 0 at the top
  void read_ink(float* out);
  // the paper as an image, row 0 at the top: (H, W, 3) ink over white (white = true) or (H, W, 4)
  // straight RGBA (ink on transparency), channels in RGB(A) order or, with bgr, OpenCV's BGR(A);
  // `out` holds uint8 (bits = 8) or uint16 (bits = 16) values, rounded to nearest (ties to even)
  void read_image(int bits, bool white, bool bgr, void* out);
  // replace the paper by (H, W, 4) premultiplied RGBA, row 0 at the top (undo forgets)
  void write_rgba(const float* in);

  // replace a procedural field by an image, values in [0, 1]: "split" (rows along the spine
  // root->tip, cols streak widths across the stroke: the alpha, repeating across), "dry" (the
  // lattice values of the bristle-clump field, rows across the stroke, cols along it) or
  // "grain" (the lattice values of the paper's height field, one per grain size); the image
  // repeats on the paper
  void set_map(const std::string& which, const float* data, int rows, int cols);

  // for the brush view: the paper tile textures and, while a stroke is pending, its layer
  // layer_ink: (r, g, b, 1) when the layer holds alpha alone (the stroke's straight ink colour),
  // (0, 0, 0, 0) when it holds premultiplied RGBA
  struct TileRef { unsigned paper, layer; int x0, y0, w, h; std::array<float, 4> layer_ink; };
  std::vector<TileRef> tile_textures();

 private:
  void flush_stroke();
  void check_deposit(const BrushFrame& brush, const Ink* ink) const;  // std::invalid_argument
  // a stroke frame for each tuft; those not swept from the last deposit start theirs
  void start_frames(const std::vector<bool>& swept);
  // tuft k of the brush: its stroke frame frames_[k], its fields' seed
  // ... returns the share of the footprint the dry map and the grain leave inked (texture_coverage)
  double draw_plan(const SweepPlan& plan, const SweepFrame& last, const SweepFrame& cur, const TuftFrame& tuft,
                 const Ink* ink, double excess, double density, std::size_t k, DepositStats& stats);
  void set_stroke_color(const Ink* ink);  // the stroke's ink colour (a new one composites the layer)
  // tuft k's deposit: drawn, and with depletion the ink it gave the paper counted in stats
  void deposit_tuft(const SweepPlan& plan, const SweepFrame& last, const SweepFrame& cur, bool swept,
                    const TuftFrame& tuft, const Ink* ink, double excess, std::size_t k, DepositStats& stats);
  // depletion: the mm^2 of full-density ink tuft k gave the paper in this deposit at that density
  double wet_gain(const TuftFrame& tuft, bool swept, std::size_t k, double density);
  void read_tiles(const std::function<void(const PaperTile&, const float*)>& f);
  void for_tiles(const std::array<int, 4>& rect, bool stroke_layer,
                 const std::function<void(PaperTile&, int, int, int, int)>& f);
  void resolve_layer(const std::array<int, 4>& rect);
  std::array<float, 4> layer_ink() const;  // see TileRef

  std::shared_ptr<RenderContext> ctx_;
  SceneFeatures scene_;
  double width_mm_, height_mm_, ppm_;
  int W_ = 0, H_ = 0, T_ = 0, samples_ = 1;
  bool max_blend_ = false;  // the layer keeps the densest deposit by max blending (no colour ramp)
  std::vector<std::unique_ptr<PaperTile>> tiles_;
  std::unique_ptr<FootprintPass> program_;
  unsigned composite_program_ = 0;  // owned by the context
  GlVertexArray quad_vao_;
  GlBuffer quad_vbo_;
  GlTexture split_tex_, dry_tex_, grain_tex_, ramp_tex_;

  // stroke state: the last deposit's surface (for the sweep), the stroke's pixel rectangle
  bool stroke_open_ = false, stroke_pending_ = false;
  std::uint64_t last_brush_ = 0;  // the brush of the last deposit (BrushFrame::brush; 0: none)
  std::vector<SweepFrame> last_;  // each tuft's surface at the last deposit, the main tuft first
  std::vector<int> last_tufts_;   // the tuft each of last_ belongs to (TuftFrame::tuft)
  std::vector<std::unique_ptr<StrokeFrame>> frames_;  // each tuft's stroke frame of the split and dry fields
  std::array<int, 4> stroke_rect_{{0, 0, 0, 0}};
  std::array<float, 4> stroke_color_{{0, 0, 0, 1}};  // straight RGBA of the stroke's ink
  // undo: the paper under the last composited stroke, premultiplied RGBA, row 0 at the bottom
  std::array<int, 4> undo_rect_{{0, 0, 0, 0}};
  std::vector<float> undo_pixels_;
  // depletion: the paper this stroke has wetted, and each tuft's footprint at its last deposit
  std::unique_ptr<WetLedger> wet_;
  bool undo_available_ = false;
};

}  // namespace brushwork
