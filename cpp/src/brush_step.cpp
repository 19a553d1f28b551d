// The whole brush, a main tuft and its children (seed "Simulation with multiple tufts"): each
// child one more (Tuft, BrushState) stepped by the one-tuft step() after its parent.
#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>

#include "brushwork/tufts.hpp"

namespace brushwork {

namespace {

int sprout_node_of(const BrushModel& m) { return m.even_tufts ? 0 : m.tuft_node; }

// child j as a brush of its tuft's model starts: at rest, reset, a single tuft
BrushState fresh_child(BrushTufts& b, std::size_t j) {
  const Tuft& t = b.children[j];
  BrushState cs = initial_state(t);
  cs.split_node = sprout_node_of(t.model);
  reset_state(t, cs, b.child_ws[j]);
  cs.tufts_active = 0;
  return cs;
}

void reset_child(BrushTufts& b, BrushState& s, std::size_t j) {
  reset_state(b.children[j], s.children[j], b.child_ws[j]);
  s.children[j].tufts_active = 0;
}

// the children remade to hang from N_node, unless they already do
void hang_children(BrushTufts& b, BrushState& s, int node) {
  if (node == s.split_node) return;
  b.hang(node);
  for (std::size_t j = 0; j < b.children.size(); ++j) s.children[j] = fresh_child(b, j);
  s.split_node = node;
}

// the children sprout from the sprout node, each seeded with its parent's angles below it
void sprout(BrushTufts& b, BrushState& s) {
  s.tufts_active = static_cast<int>(b.children.size());
  hang_children(b, s, b.sprout_node());
  for (std::size_t j = 0; j < b.children.size(); ++j) {
    reset_child(b, s, j);
    seed_child(b.main, s, s.split_node, b.children[j], s.children[j]);
    kinematics(b.children[j], s.children[j], s.children[j].x, b.child_ws[j]);
  }
}

// the satellites' parent node moves up by one, each child growing a segment at its root
void grow(BrushTufts& b, BrushState& s) {
  const int node = s.split_node - 1;
  const std::vector<BrushState> old = s.children;
  b.hang(node);
  for (std::size_t j = 0; j < b.children.size(); ++j) {
    s.children[j] = fresh_child(b, j);
    grow_child(b.main, s, node, old[j], b.children[j], s.children[j]);
    kinematics(b.children[j], s.children[j], s.children[j].x, b.child_ws[j]);
  }
  s.split_node = node;
}

// sprout or grow as the main tuft's spread says (friction acts only in contact: a tuft in the
// air does not sprout); the main tuft's sprouting score
double split(BrushTufts& b, BrushState& s, const StepStats& st) {
  const BrushModel& md = b.main.model;
  const double score = sprout_score(b.main, s, b.ws, md.tuft_node);
  if (s.tufts_active == 0 && st.contacts > 0 && score >= md.sprout_spread) sprout(b, s);
  // the satellites' parent node N_i spreads as a split does: it becomes N_{i-1}
  else if (s.tufts_active > 0 && !md.even_tufts && s.split_node > 1 && st.contacts > 0 &&
           split_reach(b.main, s, b.ws, s.split_node) >= md.sprout_spread)
    grow(b, s);
  return score;
}

// each sprouted child's own minimisation at the pose its parent's frame at N_i gives it
void step_children(BrushTufts& b, BrushState& s, StepStats& st) {
  const BrushModel& md = b.main.model;
  for (int j = 0; j < s.tufts_active; ++j) {
    const Vec2 r = child_displacement(j, md.tufts, md.even_tufts);
    const Pose p = child_pose(b.main, s, b.ws, s.split_node, r);
    // the tufts share the brush's ink: a child is as wet as the parent's nodes from its root down
    BrushState& cs = s.children[j];
    cs.wetness = s.wetness.tail(cs.wetness.size());
    const StepStats& c = step(b.children[j], cs, p, b.child_ws[j]);
    st.tuft_iterations += c.iterations;
    st.max_penetration = std::max(st.max_penetration, c.max_penetration);
    st.time += c.time;
  }
}

// `from`'s children fit the tufts they hang from in it
void check_children(const BrushTufts& b, const BrushState& from) {
  const std::size_t k = b.children.size();
  if (from.children.size() != k)
    throw std::invalid_argument("state: expected " + std::to_string(k) + " child tufts, got " +
                                std::to_string(from.children.size()));
  if (k == 0) return;
  // satellites hang from N_1..N_{tuft_node}, even tufts from the root
  const BrushModel& md = b.main.model;
  const bool hung = from.split_node == b.sprout_node() ||
                    (!md.even_tufts && from.split_node >= 1 && from.split_node < md.tuft_node);
  if (!hung)
    throw std::invalid_argument("state: child tufts on node " + std::to_string(from.split_node) +
                                ", which this brush's children cannot hang from");
  std::optional<Tuft> remade;  // the children's tuft on another node
  if (from.split_node != b.node) remade.emplace(md.child_model(from.split_node));
  const Tuft& t = remade ? *remade : b.children[0];
  for (const BrushState& cs : from.children) {
    check_state_shape(t, cs);
    if (!cs.children.empty())
      throw std::invalid_argument("state: expected 0 child tufts, got " + std::to_string(cs.children.size()));
  }
}

}  // namespace

BrushTufts::BrushTufts(const BrushModel& model) : main(model), ws(main), node(sprout_node()) {
  if (model.tufts <= 0) return;
  children.assign(model.tufts, Tuft(model.split_model()));
  child_ws.assign(model.tufts, Workspace(children[0]));
}

void BrushTufts::hang(int n) {
  if (n == node) return;
  const Tuft t(main.model.child_model(n));
  for (std::size_t j = 0; j < children.size(); ++j) {
    children[j] = t;
    child_ws[j] = Workspace(t);
  }
  node = n;
}

BrushState initial_state(BrushTufts& b) {
  BrushState s = initial_state(b.main);
  s.split_node = b.node;
  for (std::size_t j = 0; j < b.children.size(); ++j) s.children.push_back(fresh_child(b, j));
  return s;
}

void reset_state(BrushTufts& b, BrushState& s) {
  // a simple reset reverts a split brush to a single tuft
  reset_state(b.main, s, b.ws);
  s.tufts_active = 0;
  hang_children(b, s, b.sprout_node());
  for (std::size_t j = 0; j < b.children.size(); ++j) reset_child(b, s, j);
}

StepStats step(BrushTufts& b, BrushState& s, const Pose& pose) {
  StepStats st = step(b.main, s, pose, b.ws);
  if (b.children.empty()) return st;
  const double score = split(b, s, st);
  st.tuft_iterations = 0;
  st.sprout_score = score;
  step_children(b, s, st);
  // a split brush stays split while any of its tufts is near the paper (merged there, the one
  // tuft would lay its whole belly down); clear of it by merge_clearance, the tufts close into
  // one once the spread has fallen below half of sprout_spread
  const BrushModel& md = b.main.model;
  if (s.tufts_active > 0 && score < 0.5 * md.sprout_spread && clearance(b, s) > md.merge_clearance)
    s.tufts_active = 0;
  st.tufts_active = s.tufts_active;
  s.stats = st;
  return st;
}

void set_state(BrushTufts& b, BrushState& s, const BrushState& from) {
  check_state_shape(b.main, from);
  check_children(b, from);
  if (!b.children.empty()) b.hang(from.split_node);
  s = from;
  for (std::size_t j = 0; j < b.children.size(); ++j)
    kinematics(b.children[j], s.children[j], s.children[j].x, b.child_ws[j]);
  kinematics(b.main, s, s.x, b.ws);
}

double clearance(const BrushTufts& b, const BrushState& s) {
  double low = tuft_clearance(b.main, b.ws);
  for (int j = 0; j < s.tufts_active; ++j) low = std::min(low, tuft_clearance(b.children[j], b.child_ws[j]));
  return low;
}

}  // namespace brushwork
