// Procedural grey-scale maps for the footprint pass (seed "Fine bristle effect", "Dry brush",
// "Grain texture"), generated on the CPU once per paper from a seed, bit-identical on every
// machine (a hash, not std:: distributions whose output the standard does not fix).
#pragma once

#include <cstdint>
#include <vector>

namespace brushwork::maps {

// Split map: alpha on the tuft surface, (rows, cols) = (along the spine root->tip, around),
// row-major float in [0, 1].  Opaque except for streaks ("mask primitives", seed Figure 4) that
// open from a random point toward the tip and widen there.
std::vector<float> split_map(int rows, int cols, std::uint32_t seed);

// Dry map: bristle-clump grey levels on the tuft surface, (rows, cols) as above, equalised so
// that thresholding at t leaves exactly the fraction 1 - t of texels above it.
std::vector<float> dry_map(int rows, int cols, std::uint32_t seed);

// Paper grain: a tileable height field (size, size) in [0, 1], equalised like the dry map.
std::vector<float> grain_map(int size, std::uint32_t seed);

// `make(rows, cols, seed)` once per (kind, rows, cols, seed) per process, then the same vector
const std::vector<float>& cached(char kind, int rows, int cols, std::uint32_t seed,
                                 std::vector<float> (*make)(int, int, std::uint32_t));

}  // namespace brushwork::maps
