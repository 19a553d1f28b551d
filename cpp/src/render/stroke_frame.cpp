#include "stroke_frame.hpp"

#include <cmath>

#include "brushwork/sweep_plan.hpp"

namespace brushwork {

namespace {
constexpr double kTurnMm = 3.0;     // mm of the root's travel over which older moves fade from the direction by 1/e
constexpr double kFollowMm = 10.0;  // mm of travel over which the origin closes 1/e of its offset across
                                    // from the footprint's centre
constexpr double kSpeedKeep = 0.5;  // fraction of the last speed kept in this deposit's
}  // namespace

void StrokeFrame::start() {
  placed_ = false;
  s = speed = mx = my = 0.0;
}

void StrokeFrame::advance(const std::vector<double>& placed, double root_x, double root_y) {
  const PartCentre c = part_centre(placed);
  if (!(c.w > 0.0)) return;  // nothing below the paper: the frame stays
  const double x = c.x / c.w, y = c.y / c.w;
  if (placed_) {
    // the direction: the hand's (the root's) recent moves; the footprint's centre jumps back
    // and sideways as the belly lifts or lands, the root does not
    const double rx = root_x - root_x_, ry = root_y - root_y_;
    const double fade = std::exp(-std::hypot(rx, ry) / kTurnMm);
    mx = mx * fade + rx;
    my = my * fade + ry;
    const double m = std::hypot(mx, my);
    if (m > 0.0) dx = mx / m, dy = my / m;
    // the origin follows the centre along the travel at once, across it slowly (so a jump of
    // the centre does not shift the streaks); the along coordinate of a point stays put
    const double along = (x - cx) * dx + (y - cy) * dy;
    const double across = -(x - cx) * dy + (y - cy) * dx;
    const double len = std::hypot(x - cx, y - cy);
    const double follow = 1.0 - std::exp(-std::fabs(along) / kFollowMm);
    cx += along * dx - follow * across * dy;
    cy += along * dy + follow * across * dx;
    s += along;
    speed = kSpeedKeep * speed + (1.0 - kSpeedKeep) * len;
  } else {
    cx = x;
    cy = y;
  }
  root_x_ = root_x;
  root_y_ = root_y;
  placed_ = true;
}

}  // namespace brushwork
