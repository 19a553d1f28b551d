// The sweep plan of one deposit (seed "Ink depositing"): from the brush's surface now and at the
// last deposit, which faces the footprint pass draws, how many blends between the two frames,
// which parts slide and how far, and the pixels it may touch.  Pure CPU: no GL context needed.
//
// Coordinates as in render.hpp: paper millimetres, x right, y up, paper at z = 0; pixel
// rectangles are (x0, y0, x1, y1) px, x1 and y1 exclusive, y up.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "brushwork/model.hpp"
#include "brushwork/tuft_frame.hpp"

namespace brushwork {

using PixelRect = std::array<int, 4>;  // x0, y0, x1, y1 px (exclusive), y up

// One deposit's surface as the footprint pass draws it.
struct SweepFrame {
  std::vector<float> position;        // (V, 3) mm render vertices, each ring widened to its section's area
  std::vector<float> center;          // (V, 3) mm centre of each vertex's ring
  std::vector<float> uv;              // (V, 2) along the spine (0 root .. 1 tip apex), around
  std::vector<std::uint32_t> faces;   // (F, 3) outward counter-clockwise triangles
  std::vector<double> placed;         // (V, 3) mm the surface as the shader places it (soaked tip grown)
  double soak = 0.0;                  // the soaked tip's radial growth at the apex (fraction)
  int vertices() const { return static_cast<int>(position.size() / 3); }
};

// What the footprint pass draws between the last deposit and this one.
struct SweepPlan {
  bool contact = false;    // some of this deposit's surface is below the paper
  bool continues = false;  // the sweep goes on from the last deposit (false: a stroke starts)
  // (I) vertex indices, triangles in four runs: the near faces (drawn at every blend), the inner
  // faces (drawn at t = 1 only), the last deposit's part below the paper and this one's (each
  // drawn by its slid copies; empty runs when that part does not slide)
  std::vector<std::uint32_t> indices;
  std::size_t near = 0;           // indices in the first run
  std::size_t all = 0;            // indices in the first two runs
  std::size_t prev = 0, cur = 0;  // indices in the third and the fourth run
  int blends = 0;                 // K: sub-steps of the blend, t = 1/K .. 1
  int slides_prev = 0, slides_cur = 0;  // slid copies of the last and this deposit's part
  double shift_x = 0.0, shift_y = 0.0;  // mm the parts slide: the move of the footprint's centre
  double travel = 0.0;            // mm: the largest move of a vertex that can reach the paper
  PixelRect rect{{0, 0, 0, 0}};   // px the pass may touch, clipped to the paper ({0,0,0,0}: none)

  bool draws() const { return rect[2] > rect[0] && rect[3] > rect[1] && all > 0; }
};

// the render mesh of a brush of `model` on paper sampled at `px_per_mm`: as fine as `mesh_mm`
// (0: always the caps), at most `rings` rings per spine segment and `around` vertices around;
// the same on any paper of 3 px to mesh_mm or finer, coarser only below
MeshOptions mesh_options_for(const BrushModel& model, double px_per_mm, double mesh_mm, int rings, int around);
// the same for a tuft of that longest segment and belly radius (mm)
MeshOptions mesh_options_for(double segment_mm, double belly_mm, double px_per_mm, double mesh_mm, int rings,
                             int around);

// a tuft's surface (its sections swept) as the footprint pass draws it, the tip grown by `soak`
SweepFrame sweep_frame(const std::vector<Section>& sections, const MeshOptions& opt, double soak);

// the depth-weighted sum over the part of a surface below the paper: w the sum of -z (0 when
// nothing is below), (x, y) the sums of -z x and -z y (mm); the centre is (x / w, y / w)
struct PartCentre {
  double w = 0.0, x = 0.0, y = 0.0;
};
PartCentre part_centre(const std::vector<double>& placed);  // placed: (V, 3) mm

// the plan from `last` (null: a stroke starts at `cur`) to `cur`, both of one mesh, on a paper of
// `width_px` x `height_px` px sampled at `px_per_mm`; `textured`: the deposit draws the split,
// dry or grain map (its blends are spaced wider, see count_copies)
SweepPlan plan_sweep(const SweepFrame* last, const SweepFrame& cur, double px_per_mm, int width_px,
                     int height_px, bool textured = false);

}  // namespace brushwork
