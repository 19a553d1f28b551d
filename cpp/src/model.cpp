// Parameter table, validation, presets and derived per-node arrays of BrushModel.
#include "brushwork/model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace brushwork {

namespace {

// one entry: the table row plus where the value lives in the struct
struct ParamSlot {
  ParamInfo info;
  double BrushModel::*d = nullptr;
  int BrushModel::*i = nullptr;
  bool BrushModel::*b = nullptr;
};

ParamSlot F(const char* name, const char* unit, double lo, double hi, double BrushModel::*p,
            const char* doc) {
  return ParamSlot{{name, unit, "float", doc, lo, hi}, p, nullptr, nullptr};
}
ParamSlot I(const char* name, const char* unit, double lo, double hi, int BrushModel::*p,
            const char* doc) {
  return ParamSlot{{name, unit, "int", doc, lo, hi}, nullptr, p, nullptr};
}
ParamSlot B(const char* name, bool BrushModel::*p, const char* doc) {
  return ParamSlot{{name, "-", "bool", doc, 0.0, 1.0}, nullptr, nullptr, p};
}

// the tuft's shape (seed "Brush geometry")
std::vector<ParamSlot> shape_slots() {
  return {
      I("n_segments", "-", 2, kMaxSegments, &BrushModel::n_segments,
        "spine segments n; shorter toward the tip"),
      F("tuft_length", "mm", 1.0, 500.0, &BrushModel::tuft_length,
        "length of the unbent tuft, root (ferrule) to tip"),
      F("belly_radius", "mm", 0.1, 100.0, &BrushModel::belly_radius,
        "largest initial tuft radius r (the belly)"),
      F("belly_position", "-", 0.05, 0.9, &BrushModel::belly_position,
        "where the radius peaks, as a fraction of the length from the root"),
      F("tip_radius_fraction", "-", 0.005, 0.5, &BrushModel::tip_radius_fraction,
        "initial radius at the tip / belly radius"),
      F("taper_power", "-", 0.1, 3.0, &BrushModel::taper_power,
        "shape of the taper from belly to tip: r ~ cos(...)^taper_power (small: fuller tip)"),
      F("segment_ratio", "-", 0.3, 1.0, &BrushModel::segment_ratio,
        "length of each segment / length of the one above it"),
      F("lateral_radius_fraction", "-", 0.05, 0.9, &BrushModel::lateral_radius_fraction,
        "r_lat / r_i: effective radius of a lateral node"),
      F("collision_shrink", "-", 0.05, 1.0, &BrushModel::collision_shrink,
        "size of the collision section Phi_i relative to Omega_i (1: no penetration)"),
  };
}

// the springs, friction and plasticity (seed "Energy minimization problems")
std::vector<ParamSlot> energy_slots() {
  return {
      F("exponent", "-", 2.0, 3.0, &BrushModel::exponent,
        "m in the spring energies kappa |x|^m (2 or 3 in the seed)"),
      F("bend_stiffness", "N*mm/rad^m", 1e-6, 1e6, &BrushModel::bend_stiffness,
        "kappa of the bend spring at the root joint"),
      F("stiffness_ratio", "-", 1.0, 1e6, &BrushModel::stiffness_ratio,
        "extra root : tip bend stiffness factor, geometric over the joints (1: the hair-count law alone)"),
      F("stiffness_radius_power", "-", 0.0, 4.0, &BrushModel::stiffness_radius_power,
        "q: bending stiffness EI(s) ~ rho(s)^q with rho the radius the hairs would fill at s "
        "(the belly radius above the belly); 2: hairs bend alone, 4: wet hairs bend as one bundle, 0: off"),
      F("twist_stiffness", "-", 0.0, 10.0, &BrushModel::twist_stiffness,
        "twist kappa / bend kappa at the same joint (no twist spring at the root)"),
      F("stretch_stiffness", "N*mm/mm^m", 1e-6, 1e6, &BrushModel::stretch_stiffness,
        "kappa of the stretch springs |delta^2 - S|^m"),
      F("lateral_bend_stiffness", "N*mm", 0.0, 1e6, &BrushModel::lateral_bend_stiffness,
        "bend springs between consecutive lateral nodes at the root; along the tuft they follow the bend springs' profile"),
      F("spread_gain", "-", 0.0, 5.0, &BrushModel::spread_gain,
        "stretch rest length S at full press (p = 1), as a fraction of r_i"),
      F("spread_bend_gain", "1/rad^2", 0.0, 10.0, &BrushModel::spread_bend_gain,
        "extra S per rad^2 of bend at the node (saturating: at most 4 rad^2 of bend count)"),
      F("spread_reach", "-", 0.0, 4.0, &BrushModel::spread_reach,
        "p_i, the pressed proportion that sets the stretch rest length S, counts the segment above "
        "node i and this many segments above that (fractional; 0: the segment above alone)"),
      F("internal_friction", "-", 0.0, 10.0, &BrushModel::internal_friction,
        "internal-friction kappa / spring kappa, on the change since the last frame"),
      F("friction_along", "-", 0.0, 5.0, &BrushModel::friction_along,
        "external friction mu for drag along the hairs"),
      F("friction_side", "-", 0.0, 5.0, &BrushModel::friction_side,
        "external friction mu for drag across the hairs"),
      F("wet_adhesion", "N", 0.0, 10.0, &BrushModel::wet_adhesion,
        "pull toward the paper per unit p_i of a wet node in contact"),
      F("contact_relaxation", "-", 0.01, 1.0, &BrushModel::contact_relaxation,
        "omega: the normal reaction R_i of the friction moves this fraction of the way to last "
        "frame's contact force each frame (1: the seed's lagged force; below 1 damps stick-slip)"),
      F("friction_smoothing", "mm", 1e-6, 1.0, &BrushModel::friction_smoothing,
        "eps in x_i = sqrt(|dx|^2 + eps^2) - eps (keeps the friction energy smooth)"),
      F("plasticity_alpha", "deg", 0.0, 90.0, &BrushModel::plasticity_alpha,
        "alpha: rest angles shift to clamp(theta', -alpha, alpha)"),
      F("pore_a", "mm/rad", 0.0, 1000.0, &BrushModel::pore_a, "a in the lead L = a t + b u + c"),
      F("pore_b", "mm/N", 0.0, 1000.0, &BrushModel::pore_b, "b in the lead L = a t + b u + c"),
      F("pore_c", "mm", 0.0, 1000.0, &BrushModel::pore_c, "c in the lead L = a t + b u + c"),
      F("pore_gamma", "deg", 0.0, 90.0, &BrushModel::pore_gamma,
        "critical tilt gamma within which the pores trap the tip"),
  };
}

// the features switched off one by one, and the frame's solver
std::vector<ParamSlot> solver_slots() {
  return {
      B("lateral_spreading", &BrushModel::lateral_spreading,
        "stretch DOFs delta_i (off: no spreading, seed Figure 1c)"),
      B("collision", &BrushModel::collision,
        "non-penetration constraints (off: the brush passes through, seed Figure 1d)"),
      B("pore_resistance", &BrushModel::pore_resistance,
        "blocking plane ahead of a touching tip"),
      I("q_max", "-", 1, 100000, &BrushModel::q_max, "SQP iterations per frame"),
      I("newton_after", "-", 0, 100000, &BrushModel::newton_after,
        "every this many iterations of a frame's SQP without convergence, H is set from the "
        "Lagrangian's Hessian by differences of its gradient (0: never)"),
      F("tolerance", "-", 1e-14, 1e-1, &BrushModel::tolerance,
        "scaled KKT residual at which a frame's solve stops"),
      B("warm_hessian", &BrushModel::warm_hessian,
        "carry the BFGS matrix across frames (off: a fresh one each frame)"),
  };
}

// multiple tufts (seed "Simulation with multiple tufts")
std::vector<ParamSlot> tuft_slots() {
  return {
      I("tufts", "-", 0, 8, &BrushModel::tufts,
        "child tufts T_j that sprout from the main tuft when it spreads (0: a single tuft)"),
      I("tuft_node", "-", 1, kMaxSegments - 1, &BrushModel::tuft_node,
        "parent node N_i the child tufts sprout from, counted from the root (below n_segments); "
        "it moves up a node while the section at it widens by sprout_spread; the sprouting score "
        "is the spread below it (even tufts too)"),
      F("tuft_radius", "-", 0.05, 1.0, &BrushModel::tuft_radius,
        "a child tuft's belly radius / the main tuft's radius r_i at its parent node"),
      F("sprout_spread", "-", 0.0, 10.0, &BrushModel::sprout_spread,
        "sprouting score (spread, bend and dryness below N_i) at which the children sprout; "
        "they merge when it has fallen below half of it and every tuft has cleared the paper by "
        "merge_clearance"),
      F("merge_clearance", "mm", 0.0, 50.0, &BrushModel::merge_clearance,
        "height above the paper of every tuft's lowest point (the sections Omega_i) beyond which a "
        "split brush whose spread has closed merges into one tuft"),
      F("tuft_core", "-", 0.05, 1.0, &BrushModel::tuft_core,
        "the main tuft's lateral radii below N_i while split, as a fraction (the hairs the "
        "children took)"),
      B("even_tufts", &BrushModel::even_tufts,
        "split into `tufts` evenly sized tufts rooted across the root's section, which replace the "
        "main tuft while split (off: `tufts` thin satellites on N_i beside the main tuft)"),
  };
}

std::vector<ParamSlot> make_slots() {
  std::vector<ParamSlot> table = shape_slots();
  for (const auto& rows : {energy_slots(), solver_slots(), tuft_slots()})
    table.insert(table.end(), rows.begin(), rows.end());
  return table;
}

const std::vector<ParamSlot>& slots() {
  static const std::vector<ParamSlot> table = make_slots();
  return table;
}

const ParamSlot& find_slot(const std::string& name) {
  for (const auto& s : slots())
    if (s.info.name == name) return s;
  throw std::invalid_argument("BrushModel has no parameter '" + name + "'");
}

double read(const BrushModel& m, const ParamSlot& s) {
  if (s.d) return m.*(s.d);
  if (s.i) return static_cast<double>(m.*(s.i));
  return (m.*(s.b)) ? 1.0 : 0.0;
}

std::string fmt(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

}  // namespace

const std::vector<ParamInfo>& param_table() {
  static const std::vector<ParamInfo> infos = [] {
    std::vector<ParamInfo> v;
    for (const auto& s : slots()) v.push_back(s.info);
    return v;
  }();
  return infos;
}

double get_param(const BrushModel& m, const std::string& name) { return read(m, find_slot(name)); }

void set_param(BrushModel& m, const std::string& name, double value) {
  const ParamSlot& s = find_slot(name);
  // check before writing, so a bad value leaves the model as it was
  if (!std::isfinite(value) || value < s.info.lo || value > s.info.hi)
    throw std::invalid_argument("BrushModel." + name + " = " + fmt(value) + " is out of range [" +
                                fmt(s.info.lo) + ", " + fmt(s.info.hi) + "] " + s.info.unit);
  if (s.i && value != std::floor(value))
    throw std::invalid_argument("BrushModel." + name + " = " + fmt(value) + " must be an integer");
  if (s.b && value != 0.0 && value != 1.0)
    throw std::invalid_argument("BrushModel." + name + " = " + fmt(value) + " must be a bool");
  if (s.d) m.*(s.d) = value;
  if (s.i) m.*(s.i) = static_cast<int>(value);
  if (s.b) m.*(s.b) = value != 0.0;
}

void BrushModel::validate() const {
  for (const auto& s : slots()) {
    const double v = read(*this, s);
    if (!std::isfinite(v) || v < s.info.lo || v > s.info.hi)
      throw std::invalid_argument("BrushModel." + s.info.name + " = " + fmt(v) +
                                  " is out of range [" + fmt(s.info.lo) + ", " + fmt(s.info.hi) +
                                  "] " + s.info.unit);
  }
  if (tufts > 0 && tuft_node >= n_segments)
    throw std::invalid_argument("BrushModel.tuft_node = " + fmt(tuft_node) +
                                " must be below n_segments = " + fmt(n_segments));
}

BrushModel BrushModel::child_model(int node) const {
  // the spine from N_i to the tip keeps its segment lengths: same ratio, the remaining length
  BrushModel c = *this;
  const Eigen::VectorXd s = node_arclength();
  const double f = tuft_radius;
  c.n_segments = n_segments - node;
  c.tuft_length = tuft_length - s[node];
  c.belly_radius = f * node_radii()[node];
  c.belly_position = 0.05;  // thickest at its root, tapering like the parent's tail
  // a child holds f^2 of the hairs at N_i: its springs are the parent's at joint i times f^2
  const Eigen::VectorXd kb = bend_kappa();
  c.bend_stiffness = f * f * kb[node];
  c.stiffness_ratio = std::max(1.0, std::pow(stiffness_ratio, static_cast<double>(c.n_segments - 1) /
                                                                  std::max(1, n_segments - 1)));
  c.stretch_stiffness = f * f * stretch_stiffness;
  c.lateral_bend_stiffness = f * f * lateral_bend_stiffness * stiffness_profile()[node];
  c.wet_adhesion = f * f * wet_adhesion;
  // thin tufts have no lateral nodes (seed: "eliminating lateral nodes of thin tufts"): they
  // keep their round sections and bend only
  c.lateral_spreading = false;
  c.tufts = 0;
  return c;
}

BrushModel BrushModel::even_model() const {
  // 1/k of the hairs: the section's area / k, the hair-count springs / k
  BrushModel c = *this;
  const double share = 1.0 / std::max(1, tufts);
  c.belly_radius = std::sqrt(share) * belly_radius;
  c.bend_stiffness = share * bend_stiffness;
  c.stretch_stiffness = share * stretch_stiffness;
  c.lateral_bend_stiffness = share * lateral_bend_stiffness;
  c.wet_adhesion = share * wet_adhesion;
  c.tufts = 0;
  c.even_tufts = false;
  return c;
}

Eigen::VectorXd BrushModel::segment_lengths() const {
  // l_j proportional to segment_ratio^j, summing to the tuft length
  Eigen::VectorXd l(n_segments);
  double sum = 0.0;
  for (int j = 0; j < n_segments; ++j) sum += (l[j] = std::pow(segment_ratio, j));
  return l * (tuft_length / sum);
}

Eigen::VectorXd BrushModel::node_arclength() const {
  Eigen::VectorXd l = segment_lengths(), s(n_segments + 1);
  s[0] = 0.0;
  for (int j = 0; j < n_segments; ++j) s[j + 1] = s[j] + l[j];
  return s;
}

double BrushModel::radius_profile(double t) const {
  // a Chinese brush profile: 0.8 r at the ferrule, swelling to the belly r at belly_position,
  // then tapering smoothly to tip_radius_fraction * r at the tip (t = s / L in [0, 1])
  const double pi = 3.14159265358979323846;
  double f;
  if (t <= belly_position) {
    f = 0.8 + 0.2 * std::sin(0.5 * pi * t / belly_position);
  } else {
    const double q = std::cos(0.5 * pi * std::min(t - belly_position, 1.0 - belly_position) /
                              (1.0 - belly_position));
    f = tip_radius_fraction + (1.0 - tip_radius_fraction) * std::pow(std::max(q, 0.0), taper_power);
  }
  return std::max(f, tip_radius_fraction);
}

Eigen::VectorXd BrushModel::node_radii() const {
  const Eigen::VectorXd s = node_arclength() / tuft_length;
  Eigen::VectorXd r(n_segments + 1);
  for (int i = 0; i <= n_segments; ++i) r[i] = belly_radius * radius_profile(s[i]);
  return r;
}

Eigen::VectorXd BrushModel::stiffness_profile() const {
  // Hair-count law (seed "Energy Functions": "the brush root is stiffer than the tip").  A tuft
  // is a bundle of hairs of graded lengths: every hair passes the ferrule and the belly, and the
  // taper below the belly is hairs ending, so the hair count at s goes as rho(s)^2 with rho = the
  // belly radius above the belly and the tuft radius r(s) below it (the belly's swelling is
  // looser packing, not more hairs).  Hairs bending alone give EI(s) ~ rho^2, wet hairs held
  // together by the ink bend as one bundle, EI(s) ~ rho^4: EI ~ rho^q.  Joint j stands for the
  // spine from half the segment above it to half the segment below it, and its spring is that
  // piece's springs in series: kappa_j ~ 1 / mean(1 / EI) (the tip node's own half segment has
  // no joint; its fine hair points would otherwise make the last spring vanish).  The
  // thin tail therefore folds easily and lies on the paper while the belly stays straight.
  // On top, stiffness_ratio adds the seed's empirical root : tip factor, geometric over the
  // joints.  (n,) dimensionless, 1 at the root joint.
  const int n = n_segments;
  const Eigen::VectorXd s = node_arclength() / tuft_length;
  const double q = stiffness_radius_power;
  Eigen::VectorXd h(n);
  constexpr int kSamples = 64;  // midpoint rule
  for (int j = 0; j < n; ++j) {
    const double a = j > 0 ? 0.5 * (s[j - 1] + s[j]) : 0.0;
    const double b = 0.5 * (s[j] + s[j + 1]);
    double compliance = 0.0;  // mean of (r_belly / rho)^q over [a, b]
    if (q > 0.0) {
      for (int k = 0; k < kSamples; ++k) {
        const double t = a + (b - a) * (k + 0.5) / kSamples;
        const double rho = t <= belly_position ? 1.0 : radius_profile(t);
        compliance += std::pow(rho, -q);
      }
      compliance /= kSamples;
    } else {
      compliance = 1.0;
    }
    h[j] = std::pow(stiffness_ratio, -static_cast<double>(j) / std::max(1, n - 1)) / compliance;
  }
  return h / h[0];
}

Eigen::VectorXd BrushModel::bend_kappa() const { return bend_stiffness * stiffness_profile(); }

std::vector<std::string> BrushModel::preset_names() { return {"small", "medium", "large"}; }

BrushModel BrushModel::preset(const std::string& name) {
  BrushModel m;  // the defaults are the medium brush
  if (name == "medium") return m;
  if (name == "small") {
    // a small, stiff wolf-hair brush (xiaokai): short, thin, springy
    m.tuft_length = 18.0;
    m.belly_radius = 2.2;
    m.bend_stiffness = 2.0;
    m.stiffness_ratio = 10.0;
    m.stretch_stiffness = 4.0;
    m.lateral_bend_stiffness = 0.3;
    m.plasticity_alpha = 1.0;
    return m;
  }
  if (name == "large") {
    // a large, soft goat-hair brush: long, wide, a supple tip that keeps its bend
    m.tuft_length = 50.0;
    m.belly_radius = 7.0;
    m.bend_stiffness = 2.5;
    m.stiffness_ratio = 40.0;
    m.stretch_stiffness = 1.0;
    m.lateral_bend_stiffness = 0.5;
    m.plasticity_alpha = 4.0;
    m.wet_adhesion = 0.03;
    return m;
  }
  std::string known;
  for (const auto& n : preset_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown brush preset '" + name + "' (known: " + known + ")");
}

}  // namespace brushwork
