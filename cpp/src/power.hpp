// The spring law |e|^m of the seed's energies (m = 2 or 3, BrushModel::exponent) and its
// derivatives, shared by the energy (brush.cpp) and the start Hessian (sqp.cpp).  The two
// exponents the model allows are written out as products: std::pow was a fifth of a frame's
// time; any other m still goes through std::pow.
#pragma once

#include <cmath>

namespace brushwork {
namespace power {

// |e|^m
inline double powm(double e, double m) {
  if (m == 2.0) return e * e;
  const double a = std::abs(e);
  if (m == 3.0) return a * a * a;
  return std::pow(a, m);
}
// d/de |e|^m = m |e|^(m-1) sgn(e)
inline double dpowm(double e, double m) {
  if (m == 2.0) return 2.0 * e;
  const double a = std::abs(e);
  if (m == 3.0) return 3.0 * e * a;
  return m * std::pow(a, m - 1.0) * (e < 0 ? -1.0 : 1.0);
}
// d2/de2 |e|^m = m (m-1) |e|^(m-2)
inline double d2powm(double e, double m) {
  if (m == 2.0) return 2.0;
  const double a = std::abs(e);
  if (m == 3.0) return 6.0 * a;
  return m * (m - 1.0) * std::pow(a, m - 2.0);
}
// |v|^m from vv = |v|^2 >= 0, and its derivative with respect to v divided by v,
// m |v|^(m-2) (the gradient is that times v)
inline double pow_half(double vv, double m) {
  if (m == 2.0) return vv;
  if (m == 3.0) return vv * std::sqrt(vv);
  return std::pow(vv, 0.5 * m);
}
inline double dpow_half(double vv, double m) {
  if (m == 2.0) return 2.0;
  if (m == 3.0) return 3.0 * std::sqrt(vv);
  return m * std::pow(vv, 0.5 * m - 1.0);
}

}  // namespace power
}  // namespace brushwork
