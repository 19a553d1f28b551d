// The paper a stroke has wetted, in fixed cells of paper millimetres (see wet_area.hpp).
#include "wet_area.hpp"

#include <algorithm>
#include <cmath>

namespace brushwork {

namespace {

constexpr int kMaxCopies = 64;  // most slid copies of a footprint in one deposit

std::int64_t block_key(int bx, int by) {
  return (static_cast<std::int64_t>(bx) << 32) ^ static_cast<std::uint32_t>(by);
}

int floor_div(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

}  // namespace

void WetArea::clear() { blocks_.clear(); }

double WetArea::raise(int cx, int cy, float density) {
  const int bx = floor_div(cx, kBlock), by = floor_div(cy, kBlock);
  std::vector<float>& b = blocks_[block_key(bx, by)];
  if (b.empty()) b.assign(static_cast<std::size_t>(kBlock) * kBlock, 0.0f);
  float& d = b[static_cast<std::size_t>(cy - by * kBlock) * kBlock + (cx - bx * kBlock)];
  if (density <= d) return 0.0;
  const double gain = density - d;
  d = density;
  return gain;
}

double WetArea::fill(const Loops& loops, const Eigen::Vector2d& offset, float density) {
  double ylo = HUGE_VAL, yhi = -HUGE_VAL;
  for (const auto& l : loops)
    if (l.rows() > 0) {
      ylo = std::min(ylo, l.col(1).minCoeff() + offset.y());
      yhi = std::max(yhi, l.col(1).maxCoeff() + offset.y());
    }
  if (!(ylo < yhi)) return 0.0;
  double gain = 0.0;
  // rows of cells whose centres (cy + 1/2) cell lie within the loops' extent
  for (int cy = static_cast<int>(std::ceil(ylo / cell_ - 0.5)); (cy + 0.5) * cell_ <= yhi; ++cy) {
    const double y = (cy + 0.5) * cell_ - offset.y();
    xs_.clear();
    for (const auto& l : loops)
      for (Eigen::Index i = 0, n = l.rows(); i < n; ++i) {
        const double x0 = l(i, 0), y0 = l(i, 1), x1 = l((i + 1) % n, 0), y1 = l((i + 1) % n, 1);
        // the half-open rule: an edge counts the rows from its lower end up to, not at, its upper
        if ((y0 <= y) != (y1 <= y)) xs_.push_back(x0 + (y - y0) / (y1 - y0) * (x1 - x0) + offset.x());
      }
    std::sort(xs_.begin(), xs_.end());
    // inside between crossings 0-1, 2-3, ...: the cells whose centres lie there
    for (std::size_t k = 0; k + 1 < xs_.size(); k += 2)
      for (int cx = static_cast<int>(std::ceil(xs_[k] / cell_ - 0.5)); (cx + 0.5) * cell_ < xs_[k + 1]; ++cx)
        gain += raise(cx, cy, density);
  }
  return gain;
}

double WetArea::add(const Loops& loops, const Loops& last, const Eigen::Vector2d& shift, double density) {
  const float d = static_cast<float>(std::clamp(density, 0.0, 1.0));
  if (loops.empty() || d <= 0.0f) return 0.0;
  // copies at most a cell apart along the move, from both ends (the last deposit's own place
  // was wetted then)
  const int copies = std::clamp(static_cast<int>(std::ceil(shift.norm() / cell_)), 1, kMaxCopies);
  double gain = 0.0;
  for (int j = 0; j < copies; ++j) {
    const double t = static_cast<double>(j) / copies;
    gain += fill(loops, -shift * t, d);
    if (j > 0 && !last.empty()) gain += fill(last, shift * t, d);
  }
  return gain * cell_ * cell_;
}

}  // namespace brushwork
