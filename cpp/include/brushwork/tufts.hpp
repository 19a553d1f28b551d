// Multiple tufts in a hierarchy (seed "Simulation with multiple tufts", Figure 6): child tuft T_j
// hangs from spine node N_i of its parent, its root on N_i's joint-bisecting plane inside the
// elliptic section Omega_ij at the lateral displacement r_j = (r_xj, r_yj), normalised by the
// section's major and minor radii.  Each child is one more (Tuft, BrushState) stepped by the same
// step() after its parent, with a pose made from the parent's frame at N_i; the parent and its
// children may intersect.
#pragma once

#include "brushwork/step.hpp"

namespace brushwork {

// the parent's sprouting score below N_i (seed: "simple heuristics on the parent tuft's
// friction, bend angles, and wetness"): the mean fractional spread (a_i + b_i) / 2r_i - 1 of
// the sections N_i..N_{n-1}, plus a quarter of the bend of the joints below N_i in quarter
// turns, both grown by dryness (1 + 1 - mean wetness); friction enters as the caller's
// contact test
double sprout_score(const Tuft& t, const BrushState& s, const Workspace& w, int node);

// the height of the tuft's lowest point above the paper, mm: min over i = 1..n of O_i,z minus
// the reach of the unshrunk section Omega_i (negative while a section dips into the paper)
double tuft_clearance(const Tuft& t, const Workspace& w);

// how far the split reaches up to N_i: the widening (a_i + b_i) / 2r_i - 1 of the section at
// the children's parent node, grown by its dryness (1 + 1 - wetness_i); at sprout_spread the
// hairs part above N_i and the parent node moves up
double split_reach(const Tuft& t, const BrushState& s, const Workspace& w, int node);

// r_j of child j of k (|r_j| < 1): spread along the major axis (the lateral line, where the
// displaced lateral nodes pull the hairs out); satellites alternate a small fixed offset along
// the minor axis, even tufts stay on the major axis (each as deep in the paper as its neighbours)
Vec2 child_displacement(int j, int k, bool even);

// the pose that puts a child's root at r on N_i's bisecting plane with its root frame the
// parent's segment frame F_{i-1} (the root frame R_0 for N_0, where even tufts start; so equal
// bend and turn angles continue the parent's spine), leaned out toward its side of the lateral
// line in proportion to r_x (a fan, Figure 6b)
Pose child_pose(const Tuft& t, const BrushState& s, const Workspace& w, int node, const Vec2& r);

// a new child's degrees of freedom: the parent's bend, turn and lateral-line angles below N_i
// (seed: "the system initially assigns it the same bend and turn angles"), unstretched
void seed_child(const Tuft& parent, const BrushState& ps, int node, const Tuft& child, BrushState& cs);

// a child grown by one segment at its root as its parent node moves up to N_node (seed: "the
// parent node can become N_{i-1}; the child tuft then grows by one segment at its root"): the
// new root joint takes the parent's angles at N_node, the rest the child's own (`old`)
void grow_child(const Tuft& parent, const BrushState& ps, int node, const BrushState& old, const Tuft& child,
                BrushState& cs);

}  // namespace brushwork

namespace brushwork {

// ---------------------------------------------------------------------------------------------
// The whole brush: the main tuft T_0 and its children, stepped as one (seed "Simulation with
// multiple tufts").  BrushState holds every state (the children's in `children`); BrushTufts holds
// what is read-only and the scratch: the main tuft and its workspace, and the child tufts as made
// for the node N_i they hang from (BrushState::split_node), each with its workspace.
struct BrushTufts {
  Tuft main;
  Workspace ws;
  int node = 0;                     // N_i the children's tufts are made for
  std::vector<Tuft> children;       // (model.tufts) T_j
  std::vector<Workspace> child_ws;  // (model.tufts)

  explicit BrushTufts(const BrushModel& model);  // the children as they sprout (split_model())
  // the node the split tufts sprout from: N_0 for even tufts, else N_{tuft_node}
  int sprout_node() const { return main.model.even_tufts ? 0 : main.model.tuft_node; }
  // the children's tufts for N_node (child_model(node)), with fresh workspaces, unless made for it
  void hang(int node);
};

// straight, unstrained, a single tuft, each child at rest; then reset_state()
BrushState initial_state(BrushTufts& b);
// the main tuft and every child reset (reset_state above), the brush a single tuft again
void reset_state(BrushTufts& b, BrushState& s);
// one frame: the main tuft's minimisation, then (model.tufts > 0) sprouting or the split
// reaching up a node, each sprouted child's own minimisation at the pose its parent's frame
// gives it, and merging once the brush has cleared the paper; the children's figures added to
// the main tuft's
StepStats step(BrushTufts& b, BrushState& s, const Pose& pose);
// s = from and the workspaces' kinematics at it; throws std::invalid_argument (s unchanged)
// unless `from` was made for a brush of b's shape, children and their node included
void set_state(BrushTufts& b, BrushState& s, const BrushState& from);
// mm, the lowest point of every sprouted tuft's sections Omega_1..Omega_n above the paper
double clearance(const BrushTufts& b, const BrushState& s);

}  // namespace brushwork
