#include "stroke_frame.hpp"

#include <cmath>

#include "brushwork/sweep_plan.hpp"

namespace brushwork {

namespace {
constexpr double kTurnMm = 3.0;     // mm of travel over which older moves fade from the direction by 1/e
constexpr double kJump = 1.5;       // a move of the centre counts for at most this many of the root's
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
    // the direction: the centre's recent moves, each at most kJump times the root's move (the
    // centre jumps back and sideways as the belly lifts or lands; the hand does not)
    double ux = x - last_x_, uy = y - last_y_;
    const double u = std::hypot(ux, uy), cap = kJump * std::hypot(root_x - root_x_, root_y - root_y_);
    if (u > cap) ux *= cap / u, uy *= cap / u;
    const double fade = std::exp(-std::min(u, cap) / kTurnMm);
    mx = mx * fade + ux;
    my = my * fade + uy;
    const double m = std::hypot(mx, my);
    if (m > 0.0) dx = mx / m, dy = my / m;
    // the origin follows the centre along the travel at once, across it slowly (so a jump of
    // the centre does not shift the streaks); the along coordinate of a point stays put
    const double along = (x - cx) * dx + (y - cy) * dy;
    const double across = -(x - cx) * dy + (y - cy) * dx;
    const double follow = 1.0 - std::exp(-std::fabs(along) / kFollowMm);
    cx += along * dx - follow * across * dy;
    cy += along * dy + follow * across * dx;
    s += along;
    speed = kSpeedKeep * speed + (1.0 - kSpeedKeep) * std::min(u, cap);
  } else {
    cx = x;
    cy = y;
  }
  last_x_ = x;
  last_y_ = y;
  root_x_ = root_x;
  root_y_ = root_y;
  placed_ = true;
}

}  // namespace brushwork
