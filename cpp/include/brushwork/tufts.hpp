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
