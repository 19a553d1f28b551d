// Swept surface of one tuft through its elliptic cross sections Omega_i, and the footprint
// loops where that surface crosses the paper plane z = 0.
#include "brushwork/geometry.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace brushwork {

namespace {

constexpr double kPi = 3.14159265358979323846;

using LoopMatrix = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

// throw std::invalid_argument naming the section index and the field
[[noreturn]] void bad_section(std::size_t i, const char* field, const std::string& why) {
  std::ostringstream os;
  os << "sweep_surface: section " << i << ": field '" << field << "' " << why;
  throw std::invalid_argument(os.str());
}

// a finite vector of non-zero length, returned normalised
Vec3 checked_direction(const Vec3& v, std::size_t i, const char* field) {
  if (!v.allFinite()) bad_section(i, field, "is not finite");
  const double len = v.norm();
  if (!(len > 1e-12)) bad_section(i, field, "has zero length (must be a unit vector)");
  return v / len;
}

// a finite, strictly positive radius
double checked_radius(double r, std::size_t i, const char* field) {
  if (!std::isfinite(r)) bad_section(i, field, "is not finite");
  if (!(r > 0.0)) {
    std::ostringstream os;
    os << "must be > 0 (got " << r << ")";
    bad_section(i, field, os.str());
  }
  return r;
}

// some unit vector perpendicular to the unit vector t
Vec3 any_perpendicular(const Vec3& t) {
  const Vec3 axis = std::abs(t.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return (axis - axis.dot(t) * t).normalized();
}

// normalised linear blend (1-s) a + s b of two unit vectors; when the blend nearly vanishes
// (a and b nearly opposite, s near 1/2) fall back to the nearer endpoint instead of a NaN
Vec3 blend_unit(const Vec3& a, const Vec3& b, double s) {
  const Vec3 m = (1.0 - s) * a + s * b;
  const double len = m.norm();
  if (len > 1e-6) return m / len;
  return s <= 0.5 ? a : b;
}

// unordered mesh-edge key (smaller index in the high word)
inline std::uint64_t edge_key(int i, int j) {
  const std::uint32_t lo = static_cast<std::uint32_t>(i < j ? i : j);
  const std::uint32_t hi = static_cast<std::uint32_t>(i < j ? j : i);
  return (static_cast<std::uint64_t>(lo) << 32) | hi;
}

}  // namespace

namespace {

// -, ring vectors shorter than this count as zero (spine tangents, major axes)
constexpr double kZeroLength = 1e-14;
constexpr double kDegenerateAxis = 1e-9;  // -, a major axis this short after Gram-Schmidt is lost
constexpr long long kMaxMeshVertices = 100000000LL;
// mm^2, consecutive footprint points closer than this (squared) are one point
constexpr double kSamePoint2 = 1e-24;
// mm, start of running minima and maxima (beyond any coordinate on the paper)
constexpr double kFar = 1e300;
// mm^2, a footprint whose |area| is below this is no footprint
constexpr double kMinFootprintArea = 1e-9;

// the sections' fields, checked: centres C, unit axes U, W, N, radii a+ (AP), a- (AM), c (CC)
struct SweepInput {
  std::vector<Vec3> C, U, W, N, D;  // D: unit Catmull-Rom tangent directions at the centres
  std::vector<double> AP, AM, CC;
  std::vector<double> H;              // (S-1) mm, chord |O_i+1 - O_i| (at least kMinChord)
  std::vector<double> MAP, MAM, MCC;  // (S) slopes d(radius)/d(arc) of a+, a-, c at the centres
  double round = 0.0;                 // [0, 1]: how far the tip segment's radii are rounded (pressed_tip_round)
};

// mm, a chord between two section centres shorter than this is taken as this long (the radii's
// slopes stay finite where two centres coincide)
constexpr double kMinChord = 1e-9;

// PCHIP's one-sided slope at an end: the three-point estimate from the end's two secants d0
// (the end's own) and d1, over knots h0 and h1 apart; zero against d0's sign, at most 3 d0
// where the two secants differ in sign
double end_slope(double d0, double d1, double h0, double h1) {
  const double m = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
  if (m * d0 <= 0.0) return 0.0;
  if (d0 * d1 < 0.0 && std::abs(m) > 3.0 * std::abs(d0)) return 3.0 * d0;
  return m;
}

// slopes of a monotone piecewise-cubic Hermite interpolant of the radii r over knots h apart
// (Fritsch-Carlson, with PCHIP's weighted harmonic mean and ends): continuous slope along the
// spine, no overshoot between two sections (a radius never leaves the range of its two ends),
// flat at a local extremum. The last segment, the one nearest the tip, is the chord itself, its
// slope carried into the section above: the radii of a tuft narrowing ever faster toward its tip
// are concave there, and any C1 curve through concave radii rises above their chords, so a
// curved tip segment would leave a footprint wider than the cone's where only the tip touches
// (a club where a light stroke lifts)
std::vector<double> monotone_slopes(const std::vector<double>& r, const std::vector<double>& h) {
  const std::size_t S = r.size();
  std::vector<double> d(S - 1);  // secant slopes delta_k
  for (std::size_t k = 0; k + 1 < S; ++k) d[k] = (r[k + 1] - r[k]) / h[k];
  if (S == 2) return {d[0], d[0]};
  std::vector<double> m(S, 0.0);
  for (std::size_t k = 1; k + 1 < S; ++k) {
    if (d[k - 1] * d[k] <= 0.0) continue;  // an extremum (or a flat run): flat
    const double w1 = 2.0 * h[k] + h[k - 1], w2 = h[k] + 2.0 * h[k - 1];
    m[k] = (w1 + w2) / (w1 / d[k - 1] + w2 / d[k]);
  }
  m[0] = end_slope(d[0], d[1], h[0], h[1]);
  // the tip segment straight: both its ends at its own secant, which the segment above may take
  // as its end slope as long as it stays monotone (Fritsch-Carlson: at most 3 times its secant)
  m[S - 1] = d[S - 2];
  m[S - 2] = d[S - 2];
  if (d[S - 3] * d[S - 2] <= 0.0)
    m[S - 2] = 0.0;
  else if (std::abs(d[S - 2]) > 3.0 * std::abs(d[S - 3]))
    m[S - 2] = 3.0 * d[S - 3];
  return m;
}

void check_options(std::size_t S, const MeshOptions& opt) {
  if (S < 2) {
    std::ostringstream os;
    os << "sweep_surface: need at least 2 sections, got " << S;
    throw std::invalid_argument(os.str());
  }
  if (opt.rings_per_segment < 1) throw std::invalid_argument("sweep_surface: rings_per_segment must be >= 1");
  if (opt.around < 8) throw std::invalid_argument("sweep_surface: around must be >= 8");
  const long long rings_ll = static_cast<long long>(S - 1) * opt.rings_per_segment + 1;
  if (rings_ll * opt.around + 2 > kMaxMeshVertices) throw std::invalid_argument("sweep_surface: mesh too large");
}

// the flattening of the section above the tip (mean major radius / minor) from which its
// segment starts to round, and over which it rounds fully; a brush pressed 0.2 L flattens it
// ~1.4, 0.5 L ~6 (small brush)
constexpr double kRoundFromFlat = 1.2, kRoundSpan = 0.8;
// how much of the apex cone's length a fully rounded tip segment gives up (a blunt apex)
constexpr double kRoundedApexCut = 0.8;

// A tuft pressed onto the paper flattens its sections (mean major radius over the minor one
// well above 1) and its tip hairs fan out: the segment nearest the tip, straight while only the
// tip touches (see monotone_slopes), then closes round, a quarter ellipse from the section above
// (flat there) to the tip section, instead of a cone whose footprint is a pointed wedge (the
// arrowhead at every pressed entry).  Returns how far: 0 up to a flattening of
// kRoundFromFlat, 1 from kRoundFromFlat + kRoundSpan on
double pressed_tip_round(const SweepInput& in) {
  const std::size_t S = in.CC.size();
  if (S < 3) return 0.0;
  const std::size_t k = S - 2;
  const double flat = 0.5 * (in.AP[k] + in.AM[k]) / std::max(in.CC[k], kMinChord);
  return std::clamp((flat - kRoundFromFlat) / kRoundSpan, 0.0, 1.0);
}

SweepInput checked_sections(const std::vector<Section>& sections) {
  const std::size_t S = sections.size();
  SweepInput in;
  for (auto* v : {&in.C, &in.U, &in.W, &in.N, &in.D}) v->resize(S);
  for (auto* v : {&in.AP, &in.AM, &in.CC}) v->resize(S);
  for (std::size_t i = 0; i < S; ++i) {
    const Section& sec = sections[i];
    if (!sec.center.allFinite()) bad_section(i, "center", "is not finite");
    in.C[i] = sec.center;
    in.U[i] = checked_direction(sec.u, i, "u");
    in.W[i] = checked_direction(sec.w, i, "w");
    in.N[i] = checked_direction(sec.n, i, "n");
    in.AP[i] = checked_radius(sec.a_plus, i, "a_plus");
    in.AM[i] = checked_radius(sec.a_minus, i, "a_minus");
    in.CC[i] = checked_radius(sec.c, i, "c");
  }
  // unit Catmull-Rom tangent directions at the centres O_i (one-sided at the two ends);
  // zero where neighbouring centres coincide
  const auto& C = in.C;
  for (std::size_t i = 0; i < S; ++i) {
    const Vec3 m = (i == 0) ? Vec3(C[1] - C[0])
                   : (i == S - 1) ? Vec3(C[S - 1] - C[S - 2])
                                  : Vec3(0.5 * (C[i + 1] - C[i - 1]));
    const double len = m.norm();
    in.D[i] = len > kZeroLength ? Vec3(m / len) : Vec3::Zero();
  }
  in.H.resize(S - 1);
  for (std::size_t i = 0; i + 1 < S; ++i) in.H[i] = std::max((C[i + 1] - C[i]).norm(), kMinChord);
  in.MAP = monotone_slopes(in.AP, in.H);
  in.MAM = monotone_slopes(in.AM, in.H);
  in.MCC = monotone_slopes(in.CC, in.H);
  in.round = pressed_tip_round(in);
  return in;
}

// one ring of the sweep: its centre P, axes u (major) and w (minor), radii ap, am, cr
struct Ring {
  Vec3 P, u, w;
  double ap, am, cr;
};

// the ring at fraction s between sections i0 and i0 + 1: Hermite centre, linear radii, blended
// and re-orthogonalised frame.  prev_u: the last ring's major axis; handed: the sign of w
// relative to T x u, fixed on the first ring (0 until then)
Ring sweep_ring(const SweepInput& in, int i0, double s, bool first, Vec3& prev_u, double& handed) {
  const int i1 = i0 + 1;
  const auto& C = in.C;
  Ring ring;
  // cubic Hermite through O_i0, O_i1 with tangents scaled by the chord length
  const double L = (C[i1] - C[i0]).norm();
  const Vec3 m0 = in.D[i0] * L, m1 = in.D[i1] * L;
  const double s2 = s * s, s3 = s2 * s;
  ring.P = (2 * s3 - 3 * s2 + 1) * C[i0] + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * C[i1] + (s3 - s2) * m1;
  Vec3 T = (6 * s2 - 6 * s) * C[i0] + (3 * s2 - 4 * s + 1) * m0 + (-6 * s2 + 6 * s) * C[i1] +
           (3 * s2 - 2 * s) * m1;
  const double tlen = T.norm();
  T = tlen > kZeroLength ? Vec3(T / tlen) : blend_unit(in.N[i0], in.N[i1], s);

  // major axis: blended u made orthogonal to the spine tangent (Gram-Schmidt)
  const Vec3 ub = blend_unit(in.U[i0], in.U[i1], s);
  Vec3 u = ub - ub.dot(T) * T;
  if (u.norm() <= kDegenerateAxis && !first) u = prev_u - prev_u.dot(T) * T;
  u = u.norm() > kDegenerateAxis ? Vec3(u.normalized()) : any_perpendicular(T);
  prev_u = u;
  ring.u = u;

  // minor axis: unit, orthogonal to T and u; its sign agrees with the blended w on the
  // first ring and keeps the same handedness afterwards so no ring flips
  Vec3 w = T.cross(u);
  if (handed == 0.0) {
    const Vec3 wb = blend_unit(in.W[i0], in.W[i1], s);
    handed = w.dot(wb) >= 0.0 ? 1.0 : -1.0;
  }
  ring.w = w * handed;

  // radii (a + r_lat, b + r_lat, c): monotone cubic Hermite over the arc (continuous slope
  // through the sections, so a flattened tuft's outline has no kink at each Omega_i; straight
  // on the segment nearest the tip, see monotone_slopes); beyond the last section the cone to
  // the apex
  const double h = in.H[i0];
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  const int S = static_cast<int>(in.C.size());
  const double lam = in.round;
  auto radius = [&](const std::vector<double>& r, const std::vector<double>& m) {
    // the segment above the tip ends on the rounded tip segment's start slope (C1)
    const double m1 = (i1 == S - 2) ? (1.0 - lam) * m[i1] : m[i1];
    const double cubic = h00 * r[i0] + h10 * h * m[i0] + h01 * r[i1] + h11 * h * m1;
    if (i1 != S - 1 || lam <= 0.0 || r[i0] <= r[i1]) return cubic;
    // the tip segment: blended toward the quarter ellipse, flat at O_S-2, through r at O_S-1
    const double ell = std::sqrt(r[i0] * r[i0] - s2 * (r[i0] * r[i0] - r[i1] * r[i1]));
    return (1.0 - lam) * cubic + lam * ell;
  };
  ring.ap = radius(in.AP, in.MAP);
  ring.am = radius(in.AM, in.MAM);
  ring.cr = radius(in.CC, in.MCC);
  return ring;
}

// ring j's vertices and texture coordinates; ct, st: the cos / sin table of the angles around
void put_ring(SurfaceMesh& mesh, const Ring& ring, int j, int NR, const std::vector<double>& ct,
              const std::vector<double>& st) {
  const int A = static_cast<int>(ct.size());
  const Vec3& P = ring.P;
  const Vec3 &u = ring.u, &w = ring.w;
  const double along = static_cast<double>(j) / NR;
  double* pv = mesh.vertices.data() + 3 * static_cast<std::ptrdiff_t>(j) * A;
  double* pt = mesh.uv.data() + 2 * static_cast<std::ptrdiff_t>(j) * A;
  for (int k = 0; k < A; ++k) {
    const double x = (ct[k] >= 0.0 ? ring.ap : ring.am) * ct[k], y = ring.cr * st[k];
    pv[3 * k + 0] = P.x() + x * u.x() + y * w.x();
    pv[3 * k + 1] = P.y() + x * u.y() + y * w.y();
    pv[3 * k + 2] = P.z() + x * u.z() + y * w.z();
    pt[2 * k + 0] = along;
    pt[2 * k + 1] = static_cast<double>(k) / A;
  }
}

// faces: two triangles per ring quad, then the root and tip fans (ring index wraps)
void put_faces(SurfaceMesh& mesh, int NR, int A, int root_cap, int apex) {
  mesh.faces.resize((NR - 1) * A * 2 + 2 * A, 3);
  int* pf = mesh.faces.data();
  auto tri = [&pf](int a, int b, int c) {
    pf[0] = a;
    pf[1] = b;
    pf[2] = c;
    pf += 3;
  };
  for (int j = 0; j + 1 < NR; ++j) {
    for (int k = 0; k < A; ++k) {
      const int k1 = (k + 1 == A) ? 0 : k + 1;
      const int a = j * A + k, b = j * A + k1, c = (j + 1) * A + k1, d = (j + 1) * A + k;
      tri(a, b, c);
      tri(a, c, d);
    }
  }
  for (int k = 0; k < A; ++k) tri(root_cap, (k + 1 == A) ? 0 : k + 1, k);
  const int last = (NR - 1) * A;
  for (int k = 0; k < A; ++k) tri(apex, last + k, last + ((k + 1 == A) ? 0 : k + 1));
}

// winding test: geometric normals of the first non-degenerate ring interval against the
// outward direction (vertex minus spine point); the tip fan decides if all rings coincide.
// Turns every face over when they face inward
void orient_outward(SurfaceMesh& mesh, const std::vector<Vec3>& ring_center, int A, int apex,
                    const Vec3& tip_center) {
  const int NR = static_cast<int>(ring_center.size());
  auto vert = [&mesh](int i) -> Vec3 { return mesh.vertices.row(i).transpose(); };
  double outward = 0.0;
  for (int j = 0; j + 1 < NR && outward == 0.0; ++j) {
    const Vec3 mid = (2.0 * ring_center[j] + ring_center[j + 1]) / 3.0;
    for (int k = 0; k < A; ++k) {
      const Vec3 a = vert(j * A + k), b = vert(j * A + (k + 1) % A), c = vert((j + 1) * A + (k + 1) % A);
      outward += ((b - a).cross(c - a)).dot((a + b + c) / 3.0 - mid);
    }
  }
  const int last = (NR - 1) * A;
  if (outward == 0.0) {
    const Vec3 a = vert(apex);
    for (int k = 0; k < A; ++k) {
      const Vec3 b = vert(last + k), c = vert(last + (k + 1) % A);
      outward += ((b - a).cross(c - a)).dot((a + b + c) / 3.0 - tip_center);
    }
  }
  if (outward >= 0.0) return;
  int* q = mesh.faces.data();
  for (Eigen::Index g = 0; g < mesh.faces.rows(); ++g, q += 3) std::swap(q[1], q[2]);
}

}  // namespace

SurfaceMesh sweep_surface(const std::vector<Section>& sections, const MeshOptions& opt) {
  const std::size_t S = sections.size();
  check_options(S, opt);
  const SweepInput in = checked_sections(sections);
  const int R = opt.rings_per_segment;
  const int A = opt.around;
  const int NR = static_cast<int>(static_cast<long long>(S - 1) * R + 1);

  // cos / sin table for t_k = 2 pi k / around
  std::vector<double> ct(A), st(A);
  for (int k = 0; k < A; ++k) {
    const double t = 2.0 * kPi * k / A;
    ct[k] = std::cos(t);
    st[k] = std::sin(t);
  }

  SurfaceMesh mesh;
  const int V = NR * A + 2;
  const int root_cap = NR * A;
  const int apex = NR * A + 1;
  mesh.vertices.resize(V, 3);
  mesh.uv.resize(V, 2);
  std::vector<Vec3> ring_center(NR);
  double handed = 0.0;
  Vec3 prev_u = Vec3::Zero();
  for (int j = 0; j < NR; ++j) {
    const int seg = (j == NR - 1) ? static_cast<int>(S) - 2 : j / R;
    const double s = (j == NR - 1) ? 1.0 : static_cast<double>(j - seg * R) / R;
    const Ring ring = sweep_ring(in, seg, s, j == 0, prev_u, handed);
    ring_center[j] = ring.P;
    put_ring(mesh, ring, j, NR, ct, st);
  }

  // root cap at O_0 and the pointed tip apex beyond the last section
  mesh.vertices.row(root_cap) = in.C[0].transpose();
  mesh.uv.row(root_cap) << 0.0, 0.5;
  // (a rounded tip segment ends on a blunt apex: its cone flattened as far as it is rounded)
  const double tip_len = 0.5 * std::max(in.CC[S - 1], 0.5 * (in.AP[S - 1] + in.AM[S - 1])) * (1.0 - kRoundedApexCut * in.round);
  mesh.vertices.row(apex) = (in.C[S - 1] + in.N[S - 1] * tip_len).transpose();
  mesh.uv.row(apex) << 1.0, 0.5;
  put_faces(mesh, NR, A, root_cap, apex);
  orient_outward(mesh, ring_center, A, apex, in.C[S - 1]);
  return mesh;
}

namespace {

// one crossing segment per straddling triangle: start/end edge keys, start point
struct Segment {
  std::uint64_t from, to;
  Vec2 p;
};

// the point (x, y) of the edge (i, j) where a field linear along it, w_i at i and w_j at j (of
// opposite signs), is 0; computed from the canonical order so both triangles of the edge get
// bit-identical points
Vec2 zero_on_edge(const SurfaceMesh& mesh, int i, int j, double wi, double wj) {
  const auto& Vx = mesh.vertices;
  if (i > j) std::swap(i, j), std::swap(wi, wj);
  const double t = wi / (wi - wj);  // signs differ, so wi != wj
  return Vec2(Vx(i, 0) + t * (Vx(j, 0) - Vx(i, 0)), Vx(i, 1) + t * (Vx(j, 1) - Vx(i, 1)));
}

// the z = 0 crossing on the edge (i, j)
Vec2 cross_point(const SurfaceMesh& mesh, int i, int j) {
  return zero_on_edge(mesh, i, j, mesh.vertices(i, 2), mesh.vertices(j, 2));
}

// a closed walk's points as a loop: the end's repeats of the start dropped; false for fewer
// than three points
bool as_loop(std::vector<Vec2>& pts, LoopMatrix& loop) {
  while (pts.size() > 1 && (pts.front() - pts.back()).squaredNorm() <= kSamePoint2) pts.pop_back();
  if (pts.size() < 3) return false;
  loop.resize(static_cast<Eigen::Index>(pts.size()), 2);
  for (std::size_t i = 0; i < pts.size(); ++i) loop.row(static_cast<Eigen::Index>(i)) = pts[i].transpose();
  return true;
}

void check_face(int f, const int* v, int V, const char* who = "footprint_loops") {
  if (static_cast<unsigned>(v[0]) < static_cast<unsigned>(V) && static_cast<unsigned>(v[1]) < static_cast<unsigned>(V) &&
      static_cast<unsigned>(v[2]) < static_cast<unsigned>(V))
    return;
  std::ostringstream os;
  os << who << ": face " << f << " has a vertex index out of range [0, " << V << "): (" << v[0]
     << ", " << v[1] << ", " << v[2] << ")";
  throw std::invalid_argument(os.str());
}

// orient each segment: with outward normal N the travel direction is e_z x N, so the
// solid lies to the left (outer loops ccw, holes cw); for a face (A, B, C) whose lone
// vertex is A this means  A below: edge CA -> edge AB,  A above: edge AB -> edge CA
std::vector<Segment> crossing_segments(const SurfaceMesh& mesh) {
  const auto& Vx = mesh.vertices;
  const int V = static_cast<int>(Vx.rows());
  const int F = static_cast<int>(mesh.faces.rows());
  std::vector<Segment> segs;
  segs.reserve(64);
  std::vector<unsigned char> up(static_cast<std::size_t>(V));
  for (int i = 0; i < V; ++i) up[i] = Vx(i, 2) >= 0.0 ? 1 : 0;
  const int* pf = mesh.faces.data();
  for (int f = 0; f < F; ++f, pf += 3) {
    const int v[3] = {pf[0], pf[1], pf[2]};
    check_face(f, v, V);
    const int up0 = up[v[0]], up1 = up[v[1]], up2 = up[v[2]];
    if (up0 == up1 && up1 == up2) continue;
    // rotate (cyclically, keeping the winding) so the lone vertex comes first
    const int lone = (up1 == up2) ? 0 : (up0 == up2) ? 1 : 2;
    const int a = v[lone], b = v[(lone + 1) % 3], c = v[(lone + 2) % 3];
    const std::uint64_t kab = edge_key(a, b), kca = edge_key(c, a);
    if (up[a] != 0) segs.push_back({kab, kca, cross_point(mesh, a, b)});
    else segs.push_back({kca, kab, cross_point(mesh, c, a)});
  }
  return segs;
}

// the segments by the edge each starts on, sorted: (edge key, segment)
using Starts = std::vector<std::pair<std::uint64_t, int>>;

// the first segment that starts on edge `key`, or -1
int starting_on(const Starts& by_start, std::uint64_t key) {
  const auto it = std::lower_bound(by_start.begin(), by_start.end(), std::make_pair(key, -1));
  return it != by_start.end() && it->first == key ? it->second : -1;
}

// walk from segment s0 until the loop returns to it, collecting its points (zero-length steps,
// a vertex lying exactly on the plane, skipped); false for an open chain (only possible for a
// mesh that is not closed)
bool walk_loop(const std::vector<Segment>& segs, const Starts& by_start, int s0, std::vector<char>& used,
               std::vector<Vec2>& pts) {
  pts.clear();
  int s = s0;
  while (true) {
    used[s] = 1;
    const Vec2& p = segs[s].p;
    if (pts.empty() || (p - pts.back()).squaredNorm() > kSamePoint2) pts.push_back(p);
    s = starting_on(by_start, segs[s].to);
    if (s < 0) return false;
    if (s == s0) return true;
    if (used[s]) return false;
  }
}

}  // namespace

std::vector<LoopMatrix> footprint_loops(const SurfaceMesh& mesh) {
  const std::vector<Segment> segs = crossing_segments(mesh);
  // link segments through their shared edge keys
  Starts by_start(segs.size());
  for (int s = 0; s < static_cast<int>(segs.size()); ++s) by_start[s] = {segs[s].from, s};
  std::sort(by_start.begin(), by_start.end());

  std::vector<LoopMatrix> loops;
  std::vector<char> used(segs.size(), 0);
  std::vector<Vec2> pts;
  pts.reserve(segs.size());
  for (int s0 = 0; s0 < static_cast<int>(segs.size()); ++s0) {
    if (used[s0] || !walk_loop(segs, by_start, s0, used, pts)) continue;
    // emit the loop as a (k, 2) row-major matrix, first point not repeated
    LoopMatrix m;
    if (as_loop(pts, m)) loops.push_back(std::move(m));
  }
  return loops;
}

namespace {

// One piece of the projection's outline: between two keyed points, unoriented unless
// `directed` (a piece of the z = 0 crossing, oriented as crossing_segments orients it).
struct Piece {
  std::uint64_t a, b;
  Vec2 pa, pb;
  bool directed;
};

// keys of the three kinds of outline point: the z = 0 crossing on an edge, the s = 0 crossing on
// an edge (s: the vertex normals' z, interpolated), and the point inside face f where both meet
inline std::uint64_t z_key(int i, int j) { return edge_key(i, j) << 2; }
inline std::uint64_t s_key(int i, int j) { return (edge_key(i, j) << 2) | 1; }
inline std::uint64_t f_key(int f) { return (static_cast<std::uint64_t>(f) << 2) | 2; }

// The outline pieces of the projection of the part of the surface below the paper that faces
// down, {z < 0} and {s < 0} with both fields linear over each face: on each face the z = 0
// line where s < 0 and the s = 0 line (the silhouette seen from below) where z < 0, each cut
// where the other field changes sign (the face's point f_key).
std::vector<Piece> projection_pieces(const SurfaceMesh& mesh, const std::vector<double>& sz) {
  const auto& Vx = mesh.vertices;
  const int V = static_cast<int>(Vx.rows());
  std::vector<double> z(static_cast<std::size_t>(V));
  for (int v = 0; v < V; ++v) z[v] = Vx(v, 2);
  auto neg = [](double x) { return x < 0.0; };
  std::vector<Piece> out;
  for (int f = 0; f < static_cast<int>(mesh.faces.rows()); ++f) {
    const int v[3] = {mesh.faces(f, 0), mesh.faces(f, 1), mesh.faces(f, 2)};
    const int zn = neg(z[v[0]]) + neg(z[v[1]]) + neg(z[v[2]]), sn = neg(sz[v[0]]) + neg(sz[v[1]]) + neg(sz[v[2]]);
    if (zn == 0 || sn == 0) continue;   // wholly on or above the paper, or facing up all over
    if (zn == 3 && sn == 3) continue;   // inside: below the paper and facing down all over
    // the point where both lines meet, by barycentric coordinates (l1, l2) of the face
    auto meet = [&]() {
      const double z1 = z[v[1]] - z[v[0]], z2 = z[v[2]] - z[v[0]], s1 = sz[v[1]] - sz[v[0]], s2 = sz[v[2]] - sz[v[0]];
      const double det = z1 * s2 - z2 * s1;
      const double l1 = det != 0.0 ? (-z[v[0]] * s2 + z2 * sz[v[0]]) / det : 1.0 / 3.0;
      const double l2 = det != 0.0 ? (-z1 * sz[v[0]] + s1 * z[v[0]]) / det : 1.0 / 3.0;
      const double a = std::clamp(l1, 0.0, 1.0), b = std::clamp(l2, 0.0, 1.0 - a);
      return Vec2((1 - a - b) * Vx(v[0], 0) + a * Vx(v[1], 0) + b * Vx(v[2], 0),
                  (1 - a - b) * Vx(v[0], 1) + a * Vx(v[1], 1) + b * Vx(v[2], 1));
    };
    // the two edges of the face where field w changes sign, as (i, j) pairs; false if none
    auto crossing_edges = [&](const std::vector<double>& w, int e[2][2]) {
      int n = 0;
      for (int k = 0; k < 3 && n < 2; ++k) {
        const int i = v[k], j = v[(k + 1) % 3];
        if (neg(w[i]) != neg(w[j])) e[n][0] = i, e[n][1] = j, ++n;
      }
      return n == 2;
    };
    // a line of field w (0 at its two edge crossings) kept where the other field u < 0: the
    // whole, the part up to the meeting point, or nothing
    auto line = [&](const std::vector<double>& w, const std::vector<double>& u, bool is_z) {
      int e[2][2];
      if (!crossing_edges(w, e)) return;
      auto key = [&](int k) { return is_z ? z_key(e[k][0], e[k][1]) : s_key(e[k][0], e[k][1]); };
      auto other = [&](int k) {  // u at the crossing of edge k, canonical order
        int i = e[k][0], j = e[k][1];
        if (i > j) std::swap(i, j);
        const double t = w[i] / (w[i] - w[j]);
        return u[i] + t * (u[j] - u[i]);
      };
      const Vec2 p0 = zero_on_edge(mesh, e[0][0], e[0][1], w[e[0][0]], w[e[0][1]]);
      const Vec2 p1 = zero_on_edge(mesh, e[1][0], e[1][1], w[e[1][0]], w[e[1][1]]);
      const bool in0 = neg(other(0)), in1 = neg(other(1));
      if (!in0 && !in1) return;
      Piece pc{key(0), key(1), p0, p1, false};
      if (!in1) pc.b = f_key(f), pc.pb = meet();
      if (!in0) pc.a = f_key(f), pc.pa = meet();
      if (is_z) {
        // orient as crossing_segments: the lone vertex a, below: from edge (c, a) to edge (a, b)
        const bool u0 = !neg(z[v[0]]), u1 = !neg(z[v[1]]), u2 = !neg(z[v[2]]);
        const int lone = (u1 == u2) ? 0 : (u0 == u2) ? 1 : 2;
        const int a = v[lone], b = v[(lone + 1) % 3], c = v[(lone + 2) % 3];
        // lone vertex above: from the crossing on edge (a, b); below: from the one on (c, a)
        const std::uint64_t from = !neg(z[a]) ? z_key(a, b) : z_key(c, a);
        if (key(0) != from) std::swap(pc.a, pc.b), std::swap(pc.pa, pc.pb);
        pc.directed = true;
      }
      out.push_back(pc);
    };
    line(z, sz, true);
    line(sz, z, false);
  }
  return out;
}

// loops of pieces joined at their keys; a loop takes the direction of its first z = 0 piece
// (counter-clockwise when it has none)
std::vector<LoopMatrix> link_pieces(const std::vector<Piece>& pieces) {
  // each piece at its two keys, in an open-addressed table of key -> the first of a chain of
  // the pieces there (a key has two in a closed outline)
  const std::size_t n = pieces.size();
  std::size_t cap = 16;
  while (cap < 4 * n) cap *= 2;
  std::vector<std::uint64_t> keys(cap);
  std::vector<int> head(cap, -1), next_at(2 * n, -1);
  auto slot = [&](std::uint64_t key) {
    std::size_t h = (key * 0x9E3779B97F4A7C15ULL) >> 20 & (cap - 1);
    while (head[h] >= 0 && keys[h] != key) h = (h + 1) & (cap - 1);
    return h;
  };
  for (std::size_t k = 0; k < n; ++k)
    for (const int end : {0, 1}) {
      const std::size_t h = slot(end ? pieces[k].b : pieces[k].a);
      keys[h] = end ? pieces[k].b : pieces[k].a;
      next_at[2 * k + end] = head[h];
      head[h] = static_cast<int>(2 * k + end);
    }
  std::vector<char> used(n, 0);
  auto other_at = [&](std::uint64_t key, int not_this) {
    const std::size_t h = slot(key);
    if (head[h] < 0) return -1;
    for (int o = head[h]; o >= 0; o = next_at[o])
      if (o / 2 != not_this && !used[o / 2]) return o / 2;
    return -1;
  };
  std::vector<LoopMatrix> loops;
  std::vector<Vec2> pts;
  for (int k0 = 0; k0 < static_cast<int>(pieces.size()); ++k0) {
    if (used[k0]) continue;
    pts.clear();
    int dir_votes = 0;
    std::uint64_t start = pieces[k0].a, key = pieces[k0].b;
    pts.push_back(pieces[k0].pa);
    used[k0] = 1;
    if (pieces[k0].directed) ++dir_votes;
    bool closed = false;
    for (int k = k0;;) {
      const Piece& pc = pieces[k];
      const bool forward = pc.a == key;   // entered at a, leaving at b
      if (k != k0) {
        pts.push_back(forward ? pc.pa : pc.pb);
        if (pc.directed) dir_votes += forward ? 1 : -1;
        key = forward ? pc.b : pc.a;
      }
      if (key == start) {
        closed = true;
        break;
      }
      const int next = other_at(key, k);
      if (next < 0) break;
      used[next] = 1;
      k = next;
    }
    LoopMatrix m;
    if (!closed || !as_loop(pts, m)) continue;
    const bool reverse = dir_votes != 0 ? dir_votes < 0 : loops_area({m}) < 0.0;
    if (reverse) m.colwise().reverseInPlace();
    loops.push_back(std::move(m));
  }
  return loops;
}

}  // namespace

std::vector<double> vertex_normal_z(const SurfaceMesh& mesh) {
  const int V = static_cast<int>(mesh.vertices.rows());
  const double* X = mesh.vertices.data();  // (V, 3) row-major
  std::vector<double> n(3 * static_cast<std::size_t>(V), 0.0);
  const int* t = mesh.faces.data();
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f, t += 3) {
    const int a = t[0], b = t[1], c = t[2];
    const double ux = X[3 * b] - X[3 * a], uy = X[3 * b + 1] - X[3 * a + 1], uz = X[3 * b + 2] - X[3 * a + 2];
    const double vx = X[3 * c] - X[3 * a], vy = X[3 * c + 1] - X[3 * a + 1], vz = X[3 * c + 2] - X[3 * a + 2];
    const double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    for (const int v : {a, b, c}) n[3 * v] += nx, n[3 * v + 1] += ny, n[3 * v + 2] += nz;
  }
  std::vector<double> out(static_cast<std::size_t>(V), 1.0);
  for (int v = 0; v < V; ++v) {
    const double len = std::sqrt(n[3 * v] * n[3 * v] + n[3 * v + 1] * n[3 * v + 1] + n[3 * v + 2] * n[3 * v + 2]);
    if (len > 0.0) out[v] = n[3 * v + 2] / len;
  }
  return out;
}

std::vector<LoopMatrix> footprint_projection(const SurfaceMesh& mesh, const std::vector<double>& normal_z) {
  if (normal_z.size() != static_cast<std::size_t>(mesh.vertices.rows()))
    throw std::invalid_argument("footprint_projection: one normal z a vertex");
  return link_pieces(projection_pieces(mesh, normal_z));
}

std::vector<LoopMatrix> footprint_projection(const SurfaceMesh& mesh) {
  const int V = static_cast<int>(mesh.vertices.rows());
  for (int f = 0; f < static_cast<int>(mesh.faces.rows()); ++f) check_face(f, &mesh.faces(f, 0), V, "footprint_projection");
  return footprint_projection(mesh, vertex_normal_z(mesh));
}

FootprintSpan footprint_span(const std::vector<LoopMatrix>& loops, double heading) {
  // area centroid by the shoelace moments: A = 1/2 sum cross, C = 1/(6A) sum (p_i + p_j) cross
  FootprintSpan out;
  double twice = 0.0, mx = 0.0, my = 0.0, sx = 0.0, sy = 0.0;
  Eigen::Index count = 0;
  Vec2 lo(kFar, kFar), hi(-kFar, -kFar);
  for (const auto& L : loops) {
    const Eigen::Index k = L.rows();
    for (Eigen::Index i = 0; i < k; ++i) {
      const Eigen::Index j = (i + 1 == k) ? 0 : i + 1;
      const double cr = L(i, 0) * L(j, 1) - L(j, 0) * L(i, 1);
      twice += cr;
      mx += (L(i, 0) + L(j, 0)) * cr;
      my += (L(i, 1) + L(j, 1)) * cr;
      sx += L(i, 0);
      sy += L(i, 1);
      lo = lo.cwiseMin(Vec2(L(i, 0), L(i, 1)));
      hi = hi.cwiseMax(Vec2(L(i, 0), L(i, 1)));
    }
    count += k;
  }
  const double area = 0.5 * twice;
  if (count == 0 || std::abs(area) < kMinFootprintArea) return out;
  out.valid = true;
  out.centroid = Vec2(mx, my) / (6.0 * area);
  if ((out.centroid.array() < lo.array()).any() || (out.centroid.array() > hi.array()).any())
    out.centroid = Vec2(sx, sy) / static_cast<double>(count);
  // extents across the heading and along it, about the centroid
  const Vec2 along(std::cos(heading), std::sin(heading)), across(-along.y(), along.x());
  double a_lo = kFar, a_hi = -kFar, c_lo = kFar, c_hi = -kFar;
  for (const auto& L : loops)
    for (Eigen::Index i = 0; i < L.rows(); ++i) {
      const Vec2 d = Vec2(L(i, 0), L(i, 1)) - out.centroid;
      a_lo = std::min(a_lo, d.dot(along));
      a_hi = std::max(a_hi, d.dot(along));
      c_lo = std::min(c_lo, d.dot(across));
      c_hi = std::max(c_hi, d.dot(across));
    }
  out.width = c_hi - c_lo;
  out.behind = -a_lo;
  out.ahead = a_hi;
  return out;
}

double loops_area(const std::vector<LoopMatrix>& loops) {
  // shoelace sum over every loop (ccw positive, cw negative)
  double twice = 0.0;
  for (const auto& L : loops) {
    const Eigen::Index k = L.rows();
    for (Eigen::Index i = 0; i < k; ++i) {
      const Eigen::Index j = (i + 1 == k) ? 0 : i + 1;
      twice += L(i, 0) * L(j, 1) - L(j, 0) * L(i, 1);
    }
  }
  return 0.5 * twice;
}

}  // namespace brushwork
