// Exact area coverage of closed contours on a pixel grid: signed-area accumulation (each edge
// adds, to the cells it crosses, the area it bounds to their right; a running sum along the
// row then gives every pixel's covered area), in bands of rows so that a large paper needs only
// a band's accumulator.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "brushwork/ink_geometry.hpp"

namespace brushwork {

namespace {

constexpr int kBandRows = 256;  // rows accumulated at once

// one edge in pixel units, y0 < y1, dir +1 (upward) or -1
struct Edge {
  double x0, y0, x1, y1;
  double dir;
};

// the loops' edges in pixels, split where they cross x = 0 and x = W and clamped to [0, W]:
// what lies left of the paper then runs along its left side, which keeps the winding of every
// point on the paper (the map x -> clamp(x, 0, W) is monotone and the identity on it)
void pixel_edges(const Loops& loops, double ppm, double W, std::vector<Edge>& edges) {
  auto add = [&](double xa, double ya, double xb, double yb) {
    if (ya == yb) return;
    xa = std::clamp(xa, 0.0, W), xb = std::clamp(xb, 0.0, W);
    if (ya < yb) edges.push_back({xa, ya, xb, yb, 1.0});
    else edges.push_back({xb, yb, xa, ya, -1.0});
  };
  for (const auto& L : loops) {
    const Eigen::Index k = L.rows();
    for (Eigen::Index i = 0; i < k; ++i) {
      const Eigen::Index j = i + 1 == k ? 0 : i + 1;
      const double xa = L(i, 0) * ppm, ya = L(i, 1) * ppm, xb = L(j, 0) * ppm, yb = L(j, 1) * ppm;
      // split at the paper's sides
      double ts[4] = {0.0, 1.0, 1.0, 1.0};
      int n = 1;
      for (double side : {0.0, W})
        if ((xa - side) * (xb - side) < 0.0) ts[n++] = (side - xa) / (xb - xa);
      if (n == 3 && ts[2] < ts[1]) std::swap(ts[1], ts[2]);
      ts[n] = 1.0;
      for (int s = 0; s < n; ++s)
        add(xa + ts[s] * (xb - xa), ya + ts[s] * (yb - ya), xa + ts[s + 1] * (xb - xa), ya + ts[s + 1] * (yb - ya));
    }
  }
}

// the edge's contribution to rows [r0, r1) of the accumulator acc ((r1 - r0) rows of stride
// cols), whose running sum along a row is each pixel's covered area.  Within row y the edge runs
// over x in [lo, hi], its x spread evenly over the row's height h it spans, so the area right of
// it and left of X is G(X) = h E[max(X - x, 0)]; pixel i is covered G(i + 1) - G(i), and the
// accumulator takes the differences of that from pixel to pixel
void accumulate(const Edge& e, int r0, int r1, int cols, std::vector<double>& acc) {
  const double dxdy = (e.x1 - e.x0) / (e.y1 - e.y0);
  const int ya = std::max(r0, static_cast<int>(std::floor(e.y0)));
  const int yb = std::min(r1, static_cast<int>(std::ceil(e.y1)));
  for (int y = ya; y < yb; ++y) {
    const double top = std::min(e.y1, y + 1.0), bot = std::max(e.y0, static_cast<double>(y));
    if (top <= bot) continue;
    const double d = (top - bot) * e.dir;
    const double xa = e.x0 + (bot - e.y0) * dxdy, xb = e.x0 + (top - e.y0) * dxdy;
    const double lo = std::min(xa, xb), hi = std::max(xa, xb), span = hi - lo;
    auto G = [&](double X) {
      if (X <= lo) return 0.0;
      if (X >= hi) return X - 0.5 * (lo + hi);
      return 0.5 * (X - lo) * (X - lo) / span;
    };
    double* row = &acc[static_cast<std::size_t>(y - r0) * cols];
    const int i0 = static_cast<int>(std::floor(lo)), i1 = std::min(static_cast<int>(std::floor(hi)), cols - 2);
    double prev = 0.0;
    for (int i = i0; i <= i1 + 1; ++i) {
      const double c = G(i + 1.0) - G(static_cast<double>(i));
      row[i] += d * (c - prev);
      prev = c;
    }
  }
}

}  // namespace

void coverage(const Loops& loops, double px_per_mm, int width, int height, float* out) {
  if (!(px_per_mm > 0.0) || width < 1 || height < 1) throw std::invalid_argument("coverage: empty grid");
  std::vector<Edge> edges;
  pixel_edges(loops, px_per_mm, width, edges);
  std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) { return a.y0 < b.y0; });
  const int cols = width + 2;
  std::vector<double> acc;
  std::size_t first = 0;  // edges sorted by y0; those below the band are skipped
  for (int r0 = 0; r0 < height; r0 += kBandRows) {
    const int r1 = std::min(height, r0 + kBandRows);
    acc.assign(static_cast<std::size_t>(r1 - r0) * cols, 0.0);
    for (std::size_t e = first; e < edges.size() && edges[e].y0 < r1; ++e)
      if (edges[e].y1 > r0) accumulate(edges[e], r0, r1, cols, acc);
    // running sums along each row: the winding-weighted covered area of each pixel
    for (int y = r0; y < r1; ++y) {
      const double* row = &acc[static_cast<std::size_t>(y - r0) * cols];
      float* dst = out + static_cast<std::size_t>(height - 1 - y) * width;
      double sum = 0.0;
      for (int x = 0; x < width; ++x) {
        sum += row[x];
        dst[x] = static_cast<float>(std::min(std::abs(sum), 1.0));
      }
    }
  }
}

}  // namespace brushwork
