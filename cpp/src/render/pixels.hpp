// Premultiplied float RGBA to 8- or 16-bit image pixels, shared by every kind of paper.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

namespace brushwork {

constexpr float kMinAlpha = 1e-6f;  // coverage below which an image on transparency is left black

// float -> the nearest integer, ties to even: what np.round (and std::nearbyint in the default
// rounding mode) gives; on x86-64 one cvtss2si instead of a call into libm
inline int round_even(float v) {
#if defined(__SSE2__)
  return _mm_cvt_ss2si(_mm_set_ss(v));
#else
  return static_cast<int>(std::nearbyint(v));
#endif
}

// one row of n RGBA float texels (premultiplied, GL's order) into n pixels of C = 3 (over white)
// or 4 (on transparency) channels of T; kBgr swaps red and blue (OpenCV's order)
template <typename T, bool kWhite, bool kBgr>
void image_row(const float* src, T* dst, int n, float top) {
  constexpr int C = kWhite ? 3 : 4;
  for (int i = 0; i < n; ++i, src += 4, dst += C) {
    float p[4];
    for (int c = 0; c < 4; ++c) p[c] = std::clamp(src[c], 0.0f, 1.0f);
    float v[4];
    for (int c = 0; c < 3; ++c) v[c] = kWhite ? (p[c] - p[3]) + 1.0f : (p[3] > kMinAlpha ? p[c] / p[3] : 0.0f);
    v[3] = p[3];
    for (int c = 0; c < C; ++c) {
      // (the product is rounded to float first, as numpy does, then to an integer)
      const float scaled = std::clamp(v[c], 0.0f, 1.0f) * top;
      dst[(kBgr && c < 3) ? 2 - c : c] = static_cast<T>(round_even(scaled));
    }
  }
}

// dispatch one row to image_row by bits (8, 16), background and channel order
inline void image_row_any(const float* src, void* dst, int n, int bits, bool white, bool bgr) {
  const float top = bits == 8 ? 255.0f : 65535.0f;
  auto* o8 = static_cast<std::uint8_t*>(dst);
  auto* o16 = static_cast<std::uint16_t*>(dst);
  switch ((bits == 8 ? 0 : 4) + (white ? 0 : 2) + (bgr ? 1 : 0)) {
    case 0: image_row<std::uint8_t, true, false>(src, o8, n, top); break;
    case 1: image_row<std::uint8_t, true, true>(src, o8, n, top); break;
    case 2: image_row<std::uint8_t, false, false>(src, o8, n, top); break;
    case 3: image_row<std::uint8_t, false, true>(src, o8, n, top); break;
    case 4: image_row<std::uint16_t, true, false>(src, o16, n, top); break;
    case 5: image_row<std::uint16_t, true, true>(src, o16, n, top); break;
    case 6: image_row<std::uint16_t, false, false>(src, o16, n, top); break;
    default: image_row<std::uint16_t, false, true>(src, o16, n, top); break;
  }
}

}  // namespace brushwork
