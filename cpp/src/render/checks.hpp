// Argument checks shared by the renderer's validations: each throws std::invalid_argument
// naming the field, its value and the range expected.
#pragma once

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace brushwork::checks {

inline void positive(const std::string& name, double v) {
  if (!std::isfinite(v) || v <= 0.0)
    throw std::invalid_argument(name + " = " + std::to_string(v) + ": expected a finite positive number");
}

// lo <= v <= hi (lo < v with open_low); `expected` is the range as the message writes it
inline void in_range(const std::string& name, double v, double lo, double hi, bool open_low, const char* expected) {
  if (!std::isfinite(v) || v < lo || v > hi || (open_low && v == lo))
    throw std::invalid_argument(name + " = " + std::to_string(v) + ": expected " + expected);
}

// lo <= v <= hi for a count, written as an integer in the message
inline void count_in_range(const std::string& name, int v, int lo, int hi) {
  if (v < lo || v > hi)
    throw std::invalid_argument(name + " = " + std::to_string(v) + ": expected " + std::to_string(lo) + ".." +
                                std::to_string(hi));
}

// the pixel size {W, H} of a paper of width_mm x height_mm sampled at px_per_mm (each checked
// positive): each side rounded to the nearest pixel, 1..max_px
inline std::array<int, 2> paper_pixels(double width_mm, double height_mm, double px_per_mm, int max_px) {
  positive("width_mm", width_mm);
  positive("height_mm", height_mm);
  positive("px_per_mm", px_per_mm);
  const double w = std::round(width_mm * px_per_mm), h = std::round(height_mm * px_per_mm);
  if (w < 1 || h < 1 || w > max_px || h > max_px)
    throw std::invalid_argument("paper of " + std::to_string(w) + " x " + std::to_string(h) +
                                " px: each side must be 1.." + std::to_string(max_px) + " px");
  return {static_cast<int>(w), static_cast<int>(h)};
}

}  // namespace brushwork::checks
