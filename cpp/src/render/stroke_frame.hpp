// The stroke frame the streak fields live in (seed "Fine bristle effect", "Dry brush"): paper
// mm along the path of the footprint's centre and across it.  A point of the paper keeps its
// coordinates from one deposit to the next (to first order in the turn between them), so the
// split and dry fields it is inked through are the same on every deposit that reaches it and
// their streaks run along the stroke, at any resolution of the output.
#pragma once

#include <vector>

namespace brushwork {

class StrokeFrame {
 public:
  // a stroke begins: the along coordinate starts again at 0 (the direction carries over)
  void start();
  // move to the deposit whose surface as placed ((V, 3) mm) has a part below the paper, the
  // brush's root at (root_x, root_y) mm
  void advance(const std::vector<double>& placed, double root_x, double root_y);

  double cx = 0.0, cy = 0.0;  // mm: the origin, on the path of the footprint's depth-weighted centre
  double dx = 1.0, dy = 0.0;  // the unit direction of the centre's travel, smoothed over kTurnMm
  double s = 0.0;             // mm the centre has travelled along the stroke
  double speed = 0.0;         // mm per deposit: the centre's move (jumps capped), smoothed over two deposits

 private:
  bool placed_ = false;       // (cx, cy) holds a centre of this stroke
  double mx = 0.0, my = 0.0;  // mm: the centre's recent moves, the older fading (their sum gives d)
  double last_x_ = 0.0, last_y_ = 0.0;  // mm: the footprint's centre on the last deposit
  double root_x_ = 0.0, root_y_ = 0.0;  // mm: the root on the last deposit
};

}  // namespace brushwork
