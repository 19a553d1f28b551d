#include "stroke_frame.hpp"

#include <cmath>

#include "brushwork/sweep_plan.hpp"

namespace brushwork {

namespace {
constexpr double kTurnMm = 3.0;     // mm of travel over which older moves fade from the direction by 1/e
constexpr double kSpeedKeep = 0.5;  // fraction of the last speed kept in this deposit's
}  // namespace

void StrokeFrame::start() {
  placed_ = false;
  s = speed = mx = my = 0.0;
}

void StrokeFrame::advance(const std::vector<double>& placed) {
  const PartCentre c = part_centre(placed);
  if (!(c.w > 0.0)) return;  // nothing below the paper: the frame stays
  const double x = c.x / c.w, y = c.y / c.w;
  if (placed_) {
    const double ux = x - cx, uy = y - cy, len = std::hypot(ux, uy);
    const double fade = std::exp(-len / kTurnMm);
    mx = mx * fade + ux;
    my = my * fade + uy;
    const double m = std::hypot(mx, my);
    if (m > 0.0) dx = mx / m, dy = my / m;
    // the along coordinate of a point stays put when the centre moves by (ux, uy) along d
    s += ux * dx + uy * dy;
    speed = kSpeedKeep * speed + (1.0 - kSpeedKeep) * len;
  }
  cx = x;
  cy = y;
  placed_ = true;
}

}  // namespace brushwork
