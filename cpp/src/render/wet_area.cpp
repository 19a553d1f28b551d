// The paper a stroke has wetted, in fixed cells of paper millimetres (see wet_area.hpp).
#include "wet_area.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace brushwork {

namespace {

constexpr int kMaxCopies = 64;      // most slid copies of a footprint in one deposit
constexpr double kMaxRows = 8192;  // most rows of cells one deposit's copies are gathered in (819 mm)

std::int64_t block_key(int bx, int by) {
  return (static_cast<std::int64_t>(bx) << 32) ^ static_cast<std::uint32_t>(by);
}

int floor_div(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// (lowest, highest) y of the vertices of two sets of loops (mm; inf, -inf when they have none)
std::pair<double, double> y_span(const Loops& a, const Loops& b) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Loops* set : {&a, &b})
    for (const auto& l : *set)
      if (l.rows() > 0) {
        lo = std::min(lo, l.col(1).minCoeff());
        hi = std::max(hi, l.col(1).maxCoeff());
      }
  return {lo, hi};
}

}  // namespace

void WetArea::clear() { blocks_.clear(); }

double WetArea::raise_run(int cy, double xa, double xb, float density) {
  // the cells of row cy whose centres lie in [xa, xb) mm, a block looked up once per block
  double gain = 0.0;
  const int by = floor_div(cy, kBlock);
  float* row = nullptr;
  int bx = 0;
  for (int cx = static_cast<int>(std::ceil(xa / cell_ - 0.5)); (cx + 0.5) * cell_ < xb; ++cx) {
    if (row == nullptr || floor_div(cx, kBlock) != bx) {
      bx = floor_div(cx, kBlock);
      std::vector<float>& b = blocks_[block_key(bx, by)];
      if (b.empty()) b.assign(static_cast<std::size_t>(kBlock) * kBlock, 0.0f);
      row = &b[static_cast<std::size_t>(cy - by * kBlock) * kBlock];
    }
    float& d = row[cx - bx * kBlock];
    if (density > d) {
      gain += density - d;
      d = density;
    }
  }
  return gain;
}

void WetArea::collect(const Loops& loops, const Eigen::Vector2d& offset) {
  // each edge's crossings with the rows of cell centres, y = (cy + 1/2) cell, it spans, as x mm
  // in the crossing's row
  if (hits_.size() < rows_.size()) hits_.resize(rows_.size());
  hit_rows_.clear();
  for (const auto& l : loops)
    for (Eigen::Index i = 0, n = l.rows(); i < n; ++i) {
      const Eigen::Index j = i + 1 == n ? 0 : i + 1;
      const double x0 = l(i, 0), y0 = l(i, 1), x1 = l(j, 0), y1 = l(j, 1);
      const double ya = std::min(y0, y1) + offset.y(), yb = std::max(y0, y1) + offset.y();
      for (int cy = static_cast<int>(std::floor(ya / cell_ - 0.5)); (cy - 0.5) * cell_ <= yb; ++cy) {
        const double y = (cy + 0.5) * cell_ - offset.y();
        // the half-open rule: an edge counts the rows from its lower end up to, not at, its upper
        if ((y0 <= y) == (y1 <= y)) continue;
        std::vector<double>& row = hits_[static_cast<std::size_t>(cy - row0_)];
        if (row.empty()) hit_rows_.push_back(cy - row0_);
        row.push_back(x0 + (y - y0) / (y1 - y0) * (x1 - x0) + offset.x());
      }
    }
  // row by row, inside between crossings 0-1, 2-3, ...
  for (const int r : hit_rows_) {
    std::vector<double>& xs = hits_[static_cast<std::size_t>(r)];
    std::sort(xs.begin(), xs.end());
    auto& row = rows_[static_cast<std::size_t>(r)];
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2) row.emplace_back(xs[k], xs[k + 1]);
    xs.clear();
  }
}

void WetArea::start_rows(double y_lo, double y_hi) {
  row0_ = static_cast<int>(std::floor(y_lo / cell_ - 0.5)) - 1;
  const int row1 = static_cast<int>(std::ceil(y_hi / cell_ + 0.5)) + 1;
  rows_.resize(static_cast<std::size_t>(row1 - row0_ + 1));
}

double WetArea::raise_rows(float density) {
  // runs of one row that overlap or touch hold their cells together: merged, each cell is
  // raised once (a cell's gain is the same however often the same density reaches it)
  double gain = 0.0;
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    auto& runs = rows_[k];
    std::sort(runs.begin(), runs.end());
    for (std::size_t a = 0; a < runs.size();) {
      auto [xa, xb] = runs[a];
      std::size_t b = a + 1;
      for (; b < runs.size() && runs[b].first <= xb; ++b) xb = std::max(xb, runs[b].second);
      gain += raise_run(row0_ + static_cast<int>(k), xa, xb, density);
      a = b;
    }
    runs.clear();
  }
  return gain;
}

double WetArea::add(const Loops& loops, const Loops& last, const Eigen::Vector2d& shift, double density) {
  const float d = static_cast<float>(std::clamp(density, 0.0, 1.0));
  if (loops.empty() || d <= 0.0f) return 0.0;
  // copies at most a cell apart along the move, from both ends (the last deposit's own place
  // was wetted then)
  const int copies = std::clamp(static_cast<int>(std::ceil(shift.norm() / cell_)), 1, kMaxCopies);
  // the rows the copies reach: the loops' span in y, widened by the move
  const auto [lo, hi] = y_span(loops, last);
  if (!std::isfinite(lo) || !std::isfinite(hi) || !std::isfinite(shift.y())) return 0.0;
  const double reach = std::abs(shift.y());
  // a move too long for one set of rows (a jump across the paper) is raised a copy at a time
  const bool together = (hi - lo + 2.0 * reach) / cell_ < kMaxRows;
  if (together) start_rows(lo - reach, hi + reach);
  double gain = 0.0;
  auto copy = [&](const Loops& set, const Eigen::Vector2d& offset) {
    if (!together) start_rows(lo + offset.y(), hi + offset.y());
    collect(set, offset);
    if (!together) gain += raise_rows(d);
  };
  for (int j = 0; j < copies; ++j) {
    const double t = static_cast<double>(j) / copies;
    copy(loops, -shift * t);
    if (j > 0 && !last.empty()) copy(last, shift * t);
  }
  if (together) gain += raise_rows(d);
  return gain * cell_ * cell_;
}

void WetLedger::clear() {
  area_.clear();
  last_.clear();
}

double WetLedger::add(const TuftFrame& tuft, bool swept, std::size_t k, double density) {
  const Loops loops = own_footprint(tuft);
  const FootprintSpan span = footprint_span(loops, 0.0);
  last_.resize(std::max(last_.size(), k + 1));
  Footprint& last = last_[k];
  if (!swept || !span.valid) last = Footprint{};
  const Eigen::Vector2d shift = last.loops.empty() ? Eigen::Vector2d::Zero() : Eigen::Vector2d(span.centroid - last.centre);
  const double gain = area_.add(loops, last.loops, shift, density);
  last = Footprint{loops, span.centroid};
  return gain;
}

}  // namespace brushwork
