// The paper a stroke has wetted (seed "Ink loading": the ink a deposit gives the paper is taken
// from the brush), measured in cells of a fixed size in paper millimetres rather than in the
// output's pixels: the brush's ink, and through its wetness the brush's motion, are then the same
// at any output resolution (the output only samples the scene).
#pragma once

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "brushwork/tuft_frame.hpp"

namespace brushwork {

class WetArea {
 public:
  // cell_mm: side of a cell; a cell is wetted when the footprint covers its centre
  explicit WetArea(double cell_mm) : cell_(cell_mm) {}

  void clear();  // a new stroke: nothing wetted yet

  // The footprint `loops` (mm, outer loops counter-clockwise, holes clockwise) at ink `density`
  // in [0, 1], and the band swept since the tuft's last deposit: `loops` slid back along `shift`
  // (mm, the footprint's move since then) and `last` (that deposit's loops; may be empty) slid
  // forward along it.  Each cell keeps the densest ink that reached it in this stroke.  Returns
  // mm^2 of full-density ink the paper gained.
  double add(const Loops& loops, const Loops& last, const Eigen::Vector2d& shift, double density);

 private:
  static constexpr int kBlock = 64;  // cells on a side of one lazily allocated block

  // rows_ emptied and spanning the rows of cell centres from y_lo to y_hi mm
  void start_rows(double y_lo, double y_hi);
  // the runs of cells whose centres lie inside `loops` moved by `offset` (even-odd rule),
  // appended to their rows in rows_ (row cy at rows_[cy - row0_])
  void collect(const Loops& loops, const Eigen::Vector2d& offset);
  // the cells of rows_ raised to `density`, each once however many runs hold it; rows_ emptied;
  // the gain in cell units
  double raise_rows(float density);
  double raise_run(int cy, double xa, double xb, float density);  // a run of one row; its gain

  double cell_;
  std::unordered_map<std::int64_t, std::vector<float>> blocks_;  // (kBlock, kBlock) densities each
  // scratch: one loop set's crossings, x mm row by row (as rows_), and the rows that have any
  std::vector<std::vector<double>> hits_;
  std::vector<int> hit_rows_;
  // scratch: the runs [xa, xb) mm of every copy of one deposit, row by row from row row0_
  std::vector<std::vector<std::pair<double, double>>> rows_;
  int row0_ = 0;
};

// What each tuft of a brush gave the paper in a stroke: the wetted cells and each tuft's
// footprint at its last deposit (the main tuft first), shared by every kind of paper.
class WetLedger {
 public:
  explicit WetLedger(double cell_mm) : area_(cell_mm) {}
  void clear();  // a new stroke
  // tuft k's footprint now (the core's loops at the core's own mesh, whatever the paper's
  // resolution) and the band from its last one (`swept`: the tuft was there at the last deposit)
  // newly wetted at `density` (times the ink's alpha); mm^2 of full-density ink gained
  double add(const TuftFrame& tuft, bool swept, std::size_t k, double density);

 private:
  struct Footprint {
    Loops loops;                                       // mm
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // mm, the loops' area centroid
  };
  WetArea area_;
  std::vector<Footprint> last_;
};

}  // namespace brushwork
