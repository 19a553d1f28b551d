// BrushModel: the read-only parameters of one tuft (what the brush *is*), after MuJoCo's
// mjModel/mjData split.  Every field is listed once in param_table() with its unit, range and
// meaning; validation, the Python docs and the README table are all made from that table.
//
// Units: lengths in mm, forces in N, energies in N*mm (= mJ), angles in degrees at the
// interface and radians inside.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace brushwork {

struct BrushModel {
  // --- geometry (seed "Brush geometry", Figures 2-3) ---
  int n_segments = 6;                   // spine segments n
  double tuft_length = 30.0;            // mm, root to tip, unbent
  double belly_radius = 4.0;            // mm, largest initial tuft radius r
  double belly_position = 0.3;          // fraction of the length from the root where r peaks
  double tip_radius_fraction = 0.04;    // tip radius / belly radius
  double taper_power = 0.5;             // r ~ cos(...)^taper_power from belly to tip (small: fuller)
  double segment_ratio = 0.8;           // length of segment j+1 / length of segment j (< 1: shorter toward tip)
  double lateral_radius_fraction = 0.35;  // r_lat / r_i, effective radius of a lateral node
  double collision_shrink = 0.4;        // Phi_i / Omega_i: shrunk sections used for collision

  // --- strain energy (seed "Energy Functions") ---
  double exponent = 2.0;                // m in kappa |theta|^m
  double bend_stiffness = 3.0;          // N*mm/rad^m, kappa of the bend spring at the root
  double stiffness_ratio = 10.0;        // extra root : tip factor, geometric over the joints
  double stiffness_radius_power = 2.0;  // q in EI(s) ~ rho(s)^q, rho the hair-count radius (0: off)
  double twist_stiffness = 2.0;         // twist kappa / bend kappa at the same joint (none at the root)
  double stretch_stiffness = 2.0;       // N*mm/mm^m, kappa of the stretch spring |delta^2 - S|^m at the belly
  double lateral_bend_stiffness = 0.5;  // N*mm, lateral bend springs at the root (scaled like kappa_j)
  double spread_gain = 1.5;             // S at full press, as a fraction of r_i
  double spread_bend_gain = 0.5;        // 1/rad^2, S x (1 + this 4 tanh(theta^2 / 4)) at bend theta
  double spread_reach = 0.0;            // p_i counts the segment above node i and this many segments above that

  // --- dissipation ---
  double internal_friction = 0.1;       // internal-friction kappa / spring kappa (same form, on the change since last frame); 0.3 made dragged footprints flip size every other frame
  double friction_along = 0.25;         // mu for drag along the hairs
  double friction_side = 0.6;           // mu for drag across the hairs
  double wet_adhesion = 0.02;           // N, pull toward the paper per unit p_i of a wet node in contact
  double contact_relaxation = 0.5;      // omega: R_i moves this fraction of the way to last frame's force
  double friction_smoothing = 0.05;     // mm, x_i = sqrt(|dx|^2 + eps^2) - eps keeps the friction energy smooth

  // --- plasticity and pore resistance ---
  double plasticity_alpha = 2.0;        // deg, alpha in rho = clamp(theta', -alpha, alpha)
  double pore_a = 5.0;                  // mm/rad, L = a t + b u + c
  double pore_b = 1.0;                  // mm/N
  double pore_c = 0.2;                  // mm
  double pore_gamma = 20.0;             // deg, critical tilt gamma within which pores trap the tip

  // --- features a scene may leave out ---
  bool lateral_spreading = true;        // stretch DOFs delta_i (off: seed Figure 1c)
  bool collision = true;                // non-penetration constraints (off: seed Figure 1d)
  bool pore_resistance = true;          // blocking plane ahead of the tip

  // --- solver (seed "Real-time simulation") ---
  int q_max = 40;                       // SQP iterations per frame
  int newton_after = 8;                 // every this many SQP iterations unconverged, H from the Lagrangian's Hessian (0: never)
  double tolerance = 1e-5;              // KKT residual (scaled, see kkt_residual) to stop
  bool warm_hessian = true;             // carry the BFGS matrix L_xx across frames

  // --- multiple tufts (seed "Simulation with multiple tufts", Figure 6) ---
  int tufts = 0;                        // child tufts T_j at most (0: a single tuft)
  int tuft_node = 2;                    // parent node N_i the children sprout from (1..n-1; it may move up)
  double tuft_radius = 0.4;             // child belly radius / the parent's r_i at N_i
  double sprout_spread = 1.0;           // sprouting score at which the children sprout (they merge below half)
  double merge_clearance = 0.5;         // mm, every tuft's lowest point above the paper before a split brush merges
  double tuft_core = 0.2;               // the parent's lateral radii below N_i while split, as a fraction
  bool even_tufts = false;              // split into `tufts` even tufts replacing the main one (off: satellites)

  // throws std::invalid_argument naming the field and the value
  void validate() const;

  // derived per-node arrays
  Eigen::VectorXd segment_lengths() const;  // (n,) mm, root first, shorter toward the tip
  Eigen::VectorXd node_radii() const;       // (n+1,) mm, initial tuft radius r_i at spine node N_i
  Eigen::VectorXd node_arclength() const;   // (n+1,) mm, distance from the root along the unbent spine
  Eigen::VectorXd bend_kappa() const;       // (n,) N*mm/rad^m, kappa at joints 0..n-1, root stiffest
  Eigen::VectorXd stiffness_profile() const;  // (n,) -, kappa_j / kappa_0 (bend and lateral bend springs)
  double radius_profile(double t) const;    // -, r(t) / belly radius at t = s / L along the unbent spine
  // the model of a child tuft T_j hanging from N_node (1..n-1): the parent's spine from that node
  // to the tip, its radius tuft_radius r_i, its springs scaled by the hair count, no lateral
  // spreading (a thin tuft), tufts = 0
  BrushModel child_model(int node) const;
  // the model of one of k = tufts even tufts (seed: "brushes that split into evenly sized tufts"):
  // the whole spine with 1/k of the hairs, so its radii r_i / sqrt(k) and its springs / k; tufts = 0
  BrushModel even_model() const;
  // the model of this brush's split tufts as they sprout: even_model() or child_model(tuft_node)
  BrushModel split_model() const { return even_tufts ? even_model() : child_model(tuft_node); }

  static BrushModel preset(const std::string& name);
  static std::vector<std::string> preset_names();
};

// One row of the parameter table.
struct ParamInfo {
  std::string name, unit, kind, doc;  // kind: "float", "int" or "bool"
  double lo, hi;                      // inclusive range (bools: 0..1)
};
const std::vector<ParamInfo>& param_table();
double get_param(const BrushModel& m, const std::string& name);
void set_param(BrushModel& m, const std::string& name, double value);  // validates range

constexpr int kMaxSegments = 16;

// A BrushModel and the constants derived from it once (MuJoCo's compiled mjModel): read-only
// while the brush moves.  Per segment j = 0..n-1 or per node i = 0..n.
struct Tuft {
  BrushModel model;
  int n = 0;            // spine segments
  int nx = 0;           // 5n, entries of the full variable vector x
  int mmax = 0;         // n + 1, the most constraints a frame can have (sections and pore plane)
  double m_exp = 2.0;   // m, the spring exponent
  double f_scale = 1.0; // N*mm, kappa at the root: the force scale of the KKT residual
  double shrink = 0.5;  // Phi_i / Omega_i
  Eigen::VectorXd len;   // (n,) mm, segment lengths l_j
  Eigen::VectorXd r0;    // (n+1,) mm, unspread radius r_i
  Eigen::VectorXd rlat;  // (n+1,) mm, effective radius r_lat of the lateral nodes
  Eigen::VectorXd kb;    // (n,) N*mm/rad^m, bend springs kappa_j
  Eigen::VectorXd kt;    // (n,) N*mm/rad^m, twist springs
  Eigen::VectorXd kpsi;  // (n+1,) N*mm/rad^m, springs on the lateral lines' rotation psi_i
  Eigen::VectorXd klb;   // (n+1,) N*mm, lateral bend springs at node i
  double ks = 0.0;       // N*mm/mm^m, stretch springs
  double eta = 0.0;      // -, internal friction as a fraction of each spring
  std::vector<int> active;  // indices into x of the variables the solver moves
  // rest (t_i - t_{i-1}) of each side's lateral polyline (+u, -u), in (w_i, u_i, n_i) coordinates
  std::vector<Eigen::Vector3d> lb_rest[2];

  explicit Tuft(const BrushModel& m);  // validates m
  int na() const { return static_cast<int>(active.size()); }
};

}  // namespace brushwork
