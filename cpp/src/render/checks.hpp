// Argument checks shared by the renderer's validations: each throws std::invalid_argument
// naming the field, its value and the range expected.
#pragma once

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

}  // namespace brushwork::checks
