#include "maps.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <map>
#include <mutex>
#include <numeric>
#include <tuple>

namespace brushwork::maps {
namespace {

// splitmix64 finaliser: a well-mixed 64-bit hash of the inputs
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// uniform in [0, 1) from (seed, a, b, c)
double hash01(std::uint32_t seed, std::int64_t a, std::int64_t b = 0, std::int64_t c = 0) {
  std::uint64_t h = mix(seed);
  h = mix(h ^ static_cast<std::uint64_t>(a));
  h = mix(h ^ static_cast<std::uint64_t>(b) * 0x632BE59BD9B4E019ull);
  h = mix(h ^ static_cast<std::uint64_t>(c) * 0x85157AF5ull);
  return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

double smooth(double t) { return t * t * (3.0 - 2.0 * t); }

// periodic 2-D value noise: lattice (px, py) cells, evaluated at (x, y) in [0, 1)^2
double value_noise(std::uint32_t seed, int px, int py, double x, double y) {
  const double fx = x * px, fy = y * py;
  const int ix = static_cast<int>(std::floor(fx)), iy = static_cast<int>(std::floor(fy));
  const double tx = smooth(fx - ix), ty = smooth(fy - iy);
  auto at = [&](int i, int j) {
    return hash01(seed, ((i % px) + px) % px, ((j % py) + py) % py);
  };
  const double a = at(ix, iy), b = at(ix + 1, iy), c = at(ix, iy + 1), d = at(ix + 1, iy + 1);
  return (a * (1 - tx) + b * tx) * (1 - ty) + (c * (1 - tx) + d * tx) * ty;
}

// replace every value by its rank / (N - 1): thresholding at t then keeps the fraction 1 - t
void equalise(std::vector<float>& v) {
  std::vector<std::uint32_t> idx(v.size());
  std::iota(idx.begin(), idx.end(), 0u);
  std::stable_sort(idx.begin(), idx.end(), [&v](std::uint32_t a, std::uint32_t b) { return v[a] < v[b]; });
  const double scale = v.size() > 1 ? 1.0 / static_cast<double>(v.size() - 1) : 0.0;
  for (std::size_t r = 0; r < idx.size(); ++r) v[idx[r]] = static_cast<float>(r * scale);
}

// one layer of periodic value noise: its seed, lattice cells across x and y, weight
struct Layer {
  std::uint32_t seed;
  int px, py;
  double weight;
};

// (rows, cols) row-major: the weighted sum of the layers at texel centres (x across the columns,
// y down the rows, both in [0, 1)), equalised
std::vector<float> layered_noise(int rows, int cols, std::initializer_list<Layer> layers) {
  std::vector<float> out(static_cast<std::size_t>(rows) * cols);
  for (int r = 0; r < rows; ++r) {
    const double y = (r + 0.5) / rows;
    for (int c = 0; c < cols; ++c) {
      const double x = (c + 0.5) / cols;
      double v = 0.0;
      for (const Layer& l : layers) v += l.weight * value_noise(l.seed, l.px, l.py, x, y);
      out[static_cast<std::size_t>(r) * cols + c] = static_cast<float>(v);
    }
  }
  equalise(out);
  return out;
}

}  // namespace

const std::vector<float>& cached(char kind, int rows, int cols, std::uint32_t seed,
                                 std::vector<float> (*make)(int, int, std::uint32_t)) {
  // the maps of a seed are made once per process (the dry map's equalising sort is the slow
  // part); entries are never removed, so references stay valid
  static std::mutex mu;
  static std::map<std::tuple<char, int, int, std::uint32_t>, std::vector<float>> cache;
  std::lock_guard<std::mutex> lock(mu);
  auto key = std::make_tuple(kind, rows, cols, seed);
  auto it = cache.find(key);
  if (it == cache.end()) it = cache.emplace(key, make(rows, cols, seed)).first;
  return it->second;
}

std::vector<float> split_map(int rows, int cols, std::uint32_t seed) {
  std::vector<float> a(static_cast<std::size_t>(rows) * cols, 1.0f);
  // streaks: centre around the tuft, opening point along the spine, half-width at the tip
  const int streaks = 16;
  for (int g = 0; g < streaks; ++g) {
    const double v0 = hash01(seed, 1, g);
    const double s0 = 0.45 + 0.45 * hash01(seed, 2, g);
    const double w_tip = 0.004 + 0.016 * hash01(seed, 3, g);
    for (int r = 0; r < rows; ++r) {
      const double s = (r + 0.5) / rows;
      if (s <= s0) continue;
      const double half = w_tip * std::pow((s - s0) / (1.0 - s0), 0.7);
      for (int c = 0; c < cols; ++c) {
        double dv = std::fabs((c + 0.5) / cols - v0);
        dv = std::min(dv, 1.0 - dv);  // around the tuft wraps
        // one texel of soft edge so the streak has no stair steps
        const double alpha = std::clamp((dv - half) * cols + 0.5, 0.0, 1.0);
        float& t = a[static_cast<std::size_t>(r) * cols + c];
        t = std::min(t, static_cast<float>(alpha));
      }
    }
  }
  return a;
}

std::vector<float> dry_map(int rows, int cols, std::uint32_t seed) {
  // bristle clumps: fine variation around the tuft (x), slow along it (y): streaks follow hairs
  return layered_noise(rows, cols, {{seed, 96, 3, 0.55}, {seed + 17u, 24, 2, 0.3}, {seed + 31u, 192, 12, 0.15}});
}

std::vector<float> grain_map(int size, std::uint32_t seed) {
  // fibres (anisotropic), pits, and a fine octave
  return layered_noise(size, size, {{seed + 5u, 48, 12, 0.45}, {seed + 7u, 24, 24, 0.35}, {seed + 11u, 64, 64, 0.2}});
}

}  // namespace brushwork::maps
