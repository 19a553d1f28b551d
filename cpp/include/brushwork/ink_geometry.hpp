// Ink as geometry (seed "Ink depositing" for an opaque scene): what the brush leaves is a region
// of the paper, the union of each tuft's footprint (the part of its swept surface below the
// paper, orthographically projected) over the continuous motion between frames.  Kept as closed
// contours in paper millimetres, unioned stroke by stroke with Clipper, and rasterised with
// exact area coverage at any size, without a GL context.
//
// Coordinates as in render.hpp: paper millimetres, x right, y up, origin at the paper's
// bottom-left corner; images come back with row 0 at the top of the paper.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "brushwork/render.hpp"
#include "brushwork/tuft_frame.hpp"

namespace brushwork {

// How finely the sweep between two frames is followed.
struct SweepTolerance {
  double tol_mm = 0.005;  // mm: the swept edge stays this close to the continuous sweep
  int max_samples = 256;  // most blends between two frames of one tuft
};

// The region a tuft's surface covers on the paper while it moves linearly from `last` to `cur`
// (two meshes of one topology, paper at z = 0): the footprints of the blends (1 - t) last + t cur
// at the t an error estimate asks for (an interval is halved until its midpoint's footprint lies
// within tol of the band between its ends, in eight directions; never finer than each near
// vertex's move departing from a translation by 2 tol), the bands between them, each loop's
// outline simplified to within tol (the distance a stroke's clean-up drops points by).  Loops in
// mm (outer loops counter-clockwise, holes clockwise), overlapping: their union (winding > 0) is
// the region.
Loops swept_footprint(const SurfaceMesh& last, const SurfaceMesh& cur, const SweepTolerance& tol, int* samples,
                      bool with_start = true);

// The union of `loops` (winding number > 0) as closed contours: outer loops counter-clockwise,
// holes clockwise, none overlapping; coordinates rounded to 1 nm.
Loops union_loops(const Loops& loops);

// Exact area coverage of the region inside `loops` (winding number, clamped to [0, 1]: the loops
// must not overlap, as union_loops leaves them) on a grid of `width` x `height` pixels of
// 1 / px_per_mm mm, pixel (i, j) covering [i, i+1] x [j, j+1] / px_per_mm mm with row j = 0 at the
// bottom; written to out (width x height floats) row 0 at the TOP.  Bands of rows at a time.
void coverage(const Loops& loops, double px_per_mm, int width, int height, float* out);

// A paper whose ink is geometry: every stroke's region as contours (mm), its density and colour.
// Takes opaque scenes only: no split, dry or grain map, soaked tip or colour ramp (depletion is
// taken: the ink it spends is counted as on a Paper, and a stroke drawn below full density keeps
// that density).  The deposit, stroke and undo semantics are Paper's.
class VectorPaper {
 public:
  VectorPaper(double width_mm, double height_mm, double px_per_mm, const SceneFeatures& scene,
              const SweepTolerance& tol = SweepTolerance{});
  ~VectorPaper();
  VectorPaper(const VectorPaper&) = delete;
  VectorPaper& operator=(const VectorPaper&) = delete;

  DepositStats deposit(const BrushFrame& brush, const Ink* ink);
  void end_stroke();
  bool undo();
  void clear();

  int width_px() const { return W_; }
  int height_px() const { return H_; }
  double px_per_mm() const { return ppm_; }
  double width_mm() const { return width_mm_; }
  double height_mm() const { return height_mm_; }
  const SceneFeatures& scene() const { return scene_; }
  const SweepTolerance& tolerance() const { return tol_; }
  // the mesh a brush of `model` is swept with (in mm, the same at every output size)
  MeshOptions mesh_options(const BrushModel& model) const;

  // the union of every stroke's region, mm (outer loops counter-clockwise, holes clockwise)
  Loops outlines();
  // images as Paper's: (H, W) coverage, (H, W, 4) premultiplied RGBA, or an 8/16-bit image
  void read_ink(float* out);
  void read_rgba(float* out);
  void read_image(int bits, bool white, bool bgr, void* out);

  // what the last readbacks cost (s): the union of the strokes, the rasteriser
  double union_seconds() const { return union_s_; }
  double raster_seconds() const { return raster_s_; }
  double sweep_seconds() const { return sweep_s_; }

 private:
  struct Stroke;
  struct Layer;
  void check_deposit(const BrushFrame& brush, const Ink* ink) const;  // std::invalid_argument
  // a new stroke (starts) or the open one, in the ink's colour
  void open_stroke(const Ink* ink, bool starts, DepositStats& stats);
  // tuft k's region since `last` (null: it starts here) into the open stroke; its ink spent
  void deposit_tuft(const TuftFrame& tuft, const SurfaceMesh* last, const SurfaceMesh& cur, std::size_t k,
                    DepositStats& stats);
  void flush_stroke();
  std::vector<Layer> layers();  // consecutive strokes of one colour and density, unioned
  // the paper's premultiplied RGBA row by row (0 at the top); every pixel of a row outside
  // [x0, x1) is clear (0, 0, 0, 0), so a caller may take those as the background's
  void composite(const std::function<void(int row, const float* rgba, int x0, int x1)>& put);

  SceneFeatures scene_;
  SweepTolerance tol_;
  double width_mm_, height_mm_, ppm_;
  int W_ = 0, H_ = 0;
  std::vector<Stroke> strokes_;
  std::unique_ptr<Stroke> open_;           // the stroke being written
  bool stroke_open_ = false;
  std::uint64_t last_brush_ = 0;            // the brush of the last deposit (BrushFrame::brush; 0: none)
  std::vector<SurfaceMesh> last_;           // each tuft's mesh at the last deposit
  std::vector<int> last_tufts_;             // the tuft each of last_ belongs to (TuftFrame::tuft)
  std::array<float, 4> stroke_color_{{0, 0, 0, 1}};
  struct Wet;
  std::unique_ptr<Wet> wet_;
  double union_s_ = 0.0, raster_s_ = 0.0, sweep_s_ = 0.0;
};

}  // namespace brushwork
