// Offscreen rendering through EGL (seed "Ink depositing" and "System prototype"): a shared GL
// context, a paper canvas of float ink in tiles, the footprint pass that deposits what the brush
// leaves on the paper, and a brush view for previews.
//
// Coordinates: paper millimetres, x right, y up, origin at the paper's bottom-left corner, paper at
// z = 0 and z up (the brush core's frame).  Pixel (i, j) of the paper covers
// [i, i+1] x [j, j+1] / px_per_mm mm, row j = 0 at the bottom; readback flips rows once so that
// numpy row 0 is the top of the paper.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "brushwork/brush.hpp"
#include "brushwork/render/gl_name.hpp"
#include "brushwork/sweep_plan.hpp"

namespace brushwork {

// ---------------------------------------------------------------------------------------------
// context

// Which EGL path the context took, and what the driver says about itself.
struct RenderInfo {
  std::string backend;   // "egl-device" (a GPU through EGL device enumeration),
                         // "mesa-surfaceless" (software) or "default-display"
  int device_index = -1; // index among the enumerated EGL devices, -1 when none was used
  int device_count = 0;  // EGL devices enumerated
  std::string vendor, renderer, version;  // glGetString
  int max_texture_size = 0;               // px, GL_MAX_TEXTURE_SIZE
};

// One OpenGL 3.3 core context per thread, shared by every Paper and BrushView that thread makes
// (an EGL context is current on one thread at a time: each renders on the thread that made it,
// and make_current elsewhere throws saying so).  Selection
// (Open3D's and MuJoCo's order): BRUSHWORK_RENDER = auto (default) | gpu | software | disable;
// BRUSHWORK_EGL_DEVICE = index of the EGL device to use (range-checked).  auto tries the EGL
// devices (taking the first that initialises), then Mesa's surfaceless platform, then the
// default display.  Failures throw std::runtime_error naming what is missing and what to
// install; a bad variable throws std::invalid_argument.
class RenderContext {
 public:
  static std::shared_ptr<RenderContext> acquire();
  ~RenderContext();
  RenderContext(const RenderContext&) = delete;
  RenderContext& operator=(const RenderContext&) = delete;

  const RenderInfo& info() const { return info_; }
  // a GLSL program built from `vertex` + `fragment` with "#define" lines for `defines`, compiled
  // once per context and shared (a Paper per glyph in a batch must not recompile its shaders);
  // owned by the context: callers must not delete it
  unsigned program(const char* vertex, const char* fragment, const std::vector<std::string>& defines);
  void make_current() const;  // throws if closed
  bool closed() const { return display_ == nullptr; }
  void close();               // idempotent

 private:
  RenderContext() = default;
  void open();
  void* display_ = nullptr;
  void* context_ = nullptr;
  std::thread::id owner_;  // the thread it was made on, the one it is current on
  RenderInfo info_;
  std::map<std::string, unsigned> programs_;
};

// ---------------------------------------------------------------------------------------------
// scene

// What a scene uses (DESIGN "scene.py").  Each feature off is neither computed on the CPU nor
// compiled into the footprint shader (it becomes an absent #define).
struct SceneFeatures {
  bool split_map = false;    // seed "Fine bristle effect": the tip parts into bristle groups
  bool dry_map = false;      // seed "Dry brush": bristle-clump field thresholded by moisture,
                             // speed and pressure
  bool grain = false;        // seed "Grain texture": paper height field thresholded when dry
  bool soaked_tip = false;   // seed "Soaked brush": tip expanded, split map dilated, drains
  bool color_ramp = false;   // seed "Ink loading": colour gradient along the spine
  bool depletion = false;    // ink subtracted from the brush (off: constant ink level)

  // thresholds (dimensionless, wetness and pressure in [0, 1])
  double dry_onset = 0.6;       // wetness below which the dry map starts to open streaks
  double dry_pressure = 0.5;    // how much pressure closes the streaks again
  double grain_onset = 0.4;     // wetness below which paper grain shows
  double grain_pressure = 0.5;  // how much pressure presses ink into the grain's valleys
  double grain_mm = 0.25;       // mm: the size of the paper grain's features (its lattice cell)
  double streak_mm = 0.3;       // mm: the width of a bristle streak across the stroke (split
                                // and dry fields; the dry field runs 50 of them along the stroke)
  double dry_speed = 0.0;       // dryness added per mm of the footprint's travel per deposit
  double soak_expand = 0.25;    // radial growth of the tip at full excess moisture (fraction)
  double soak_shift = 0.35;     // split map scaled toward the tip at full excess moisture
  double soak_drain_mm = 40.0;  // travel in contact over which excess moisture falls by 1/e
  double capillary = 0.2;       // depletion: fraction of the way each node's wetness moves
                                // toward the tuft's mean per frame (ink flows to the tip)
  std::uint32_t seed = 1;       // procedural fields (split, dry, grain)
  int mesh_rings = 6;           // rings per spine segment of the swept surface (at most)
  int mesh_around = 48;         // vertices around one ring (at most)
  double mesh_mm = 0.6;         // mm: the render mesh is as fine as this on the paper, no finer:
                                // rings per segment and vertices around are chosen per brush
                                // (longest segment and belly circumference over mesh_mm),
                                // capped by the two above; the same at every output size from
                                // 3 px to mesh_mm up (5 px/mm), which only samples the surface,
                                // its edges kept at 3 px below.  0: always the caps.
                                // `brushwork bench render` sweeps it (ink error against time)
  int samples = 4;              // multisampling of the stroke layer: 1 (none), 2, 4 or 8 (the
                                // device's maximum at most).  On a software rasteriser 4x is
                                // ~2.5x the time of 1x; 1x loses the faint ink of footprints
                                // thinner than a pixel (see Paper::samples)

  void validate() const;  // std::invalid_argument naming the field
};

// What one deposit did.
struct DepositStats {
  bool contact = false;        // some of the surface was below the paper
  bool new_stroke = false;     // this deposit started a stroke
  int substeps = 0;            // footprints swept between the last deposit and this one
  int slides = 0;              // copies of a footprint slid along its move, the larger of the
                               // last and this part's count (0: blend only)
  double deposited = 0.0;      // mm^2 of full-density ink given to the paper (depletion only)
  std::array<int, 4> rect{{0, 0, 0, 0}};  // px x0, y0, x1, y1 (exclusive) touched, y up
  bool drawn = false;          // the footprint pass drew (contact, and some pixel of the paper)
  std::vector<float> pressure; // (n+1) node pressure in [0, 1] the pass drew with (when drawn)
  double travel = 0.0;         // mm: the largest move of the surface in reach of the paper
};

// What a deposit did to the brush's ink (seed "Ink loading"): with depletion, the ink the pass
// gave the paper taken from the nodes (first in proportion to pressure x load), capillary flow
// toward the tuft's mean wetness, and the brush's wetness set to load / capacity; with a soaked
// tip, the excess moisture drained by the distance travelled in contact.
void spend_ink(const DepositStats& stats, const SceneFeatures& scene, Ink& ink, Brush& brush);

// depletion: the density in [0, 1] a tuft's footprint reaches the paper at, from its nodes' wetness
double ink_density(const Brush& tuft);

// ---------------------------------------------------------------------------------------------
// paper

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
  // A split brush deposits every tuft (Brush::tufts()), each swept from its own last deposit,
  // through its own stroke frame and its own seed of the split and dry fields
  DepositStats deposit(const Brush& brush, const Ink* ink);
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
  void check_deposit(const Brush& brush, const Ink* ink) const;  // std::invalid_argument
  // a stroke frame for each tuft; those not swept from the last deposit start theirs
  void start_frames(const std::vector<bool>& swept);
  // tuft k of the brush: its stroke frame frames_[k], its fields' seed
  // ... returns the share of the footprint the dry map and the grain leave inked (texture_coverage)
  double draw_plan(const SweepPlan& plan, const SweepFrame& last, const SweepFrame& cur, const Brush& brush,
                 const Ink* ink, double excess, double density, std::size_t k, DepositStats& stats);
  void set_stroke_color(const Ink* ink);  // the stroke's ink colour (a new one composites the layer)
  // tuft k's deposit: drawn, and with depletion the ink it gave the paper counted in stats
  void deposit_tuft(const SweepPlan& plan, const SweepFrame& last, const SweepFrame& cur, bool swept,
                    const Brush& tuft, const Ink* ink, double excess, std::size_t k, DepositStats& stats);
  // depletion: the mm^2 of full-density ink tuft k gave the paper in this deposit at that density
  double wet_gain(const Brush& tuft, bool swept, std::size_t k, double density);
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
  const Brush* last_brush_ = nullptr;
  std::vector<SweepFrame> last_;  // each tuft's surface at the last deposit, the main tuft first
  std::vector<const Brush*> last_tufts_;  // the tuft each of last_ belongs to
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
  // (H, W, 4) RGBA8 into `out`, row 0 at the top; paper and ink may be null
  void render(Paper* paper, const Brush& brush, const Ink* ink, const ViewOptions& o,
              std::uint8_t* out);

 private:
  void draw_paper(const std::vector<Paper::TileRef>& tiles, double px_per_mm, const float* mvp);
  int upload_tuft(const Brush& brush, const Ink* ink);  // indices of its triangles
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
