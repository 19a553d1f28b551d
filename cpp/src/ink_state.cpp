// The brush's ink (seed "Ink loading"): the full load, its checks, and what a deposit does to it:
// depletion, capillary flow inside the tuft and the soaked tip's drain.
#include "brushwork/ink.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace brushwork {

namespace {

constexpr double kMinCapacity = 1e-9;  // mm^2: the least ink a node holds (a section of no area)
constexpr double kNoInk = 1e-15;       // mm^2: ink left to take below which depletion stops
constexpr int kTakePasses = 3;         // passes over the nodes to take a deposit's ink: the first
                                       // by pressure x load, the later ones by load alone

void check_ramp(const std::vector<std::array<float, 4>>& ramp) {
  if (ramp.empty()) throw std::invalid_argument("ink.ramp: at least one colour");
  for (const auto& c : ramp)
    for (float v : c)
      if (!std::isfinite(v) || v < 0.0f || v > 1.0f)
        throw std::invalid_argument("ink.ramp: colour components must be in 0..1");
}

void check_node(int i, double load, double capacity) {
  if (!std::isfinite(load) || !std::isfinite(capacity) || load < 0 || capacity <= 0)
    throw std::invalid_argument("ink: load[" + std::to_string(i) + "] = " + std::to_string(load) +
                                ", capacity = " + std::to_string(capacity) + ": expected load >= 0, capacity > 0");
}

// take `gained` mm^2 from the nodes that still hold ink, first in proportion to pressure x load
// (the pressed nodes give the ink), then to load alone for what the first pass could not take
void take_ink(Ink& ink, double gained, const std::vector<float>& pressure) {
  const int nodes = static_cast<int>(ink.load.size());
  double remaining = std::min(gained, ink.load.sum());
  for (int pass = 0; pass < kTakePasses && remaining > kNoInk; ++pass) {
    double wsum = 0.0;
    Eigen::VectorXd wgt(nodes);
    for (int i = 0; i < nodes; ++i) wsum += (wgt[i] = (pass == 0 ? pressure[i] : 1.0) * ink.load[i]);
    if (wsum <= 0.0) continue;
    double taken = 0.0;
    for (int i = 0; i < nodes; ++i) {
      const double take = std::min(ink.load[i], remaining * wgt[i] / wsum);
      ink.load[i] -= take;
      taken += take;
    }
    remaining -= taken;
  }
}

}  // namespace

Ink Ink::full(const std::vector<Section>& secs, double total_mm2) {
  if (!std::isfinite(total_mm2) || total_mm2 <= 0.0)
    throw std::invalid_argument("ink total = " + std::to_string(total_mm2) + ": expected a finite positive number");
  Ink ink;
  ink.capacity.resize(static_cast<Eigen::Index>(secs.size()));
  // capacity in proportion to the section area pi a c (the water a node can hold)
  for (std::size_t i = 0; i < secs.size(); ++i)
    ink.capacity[i] = std::max(0.5 * (secs[i].a_plus + secs[i].a_minus) * secs[i].c, kMinCapacity);
  ink.capacity *= total_mm2 / ink.capacity.sum();
  ink.load = ink.capacity;
  ink.excess = 1.0;  // freshly dipped: soaked
  return ink;
}

void Ink::validate(int nodes) const {
  check_ramp(ramp);
  if (load.size() != nodes || capacity.size() != nodes)
    throw std::invalid_argument("ink: load and capacity need " + std::to_string(nodes) +
                                " entries (one per spine node), got " +
                                std::to_string(load.size()) + " and " +
                                std::to_string(capacity.size()));
  for (int i = 0; i < nodes; ++i) check_node(i, load[i], capacity[i]);
  if (!std::isfinite(excess) || excess < 0.0 || excess > 1.0)
    throw std::invalid_argument("ink.excess = " + std::to_string(excess) + ": expected 0..1");
}

void spend_ink(const InkUse& stats, const SceneFeatures& scene, Ink& ink, Eigen::VectorXd& wetness) {
  if (scene.depletion && stats.drawn) {
    // what the paper gained is what the brush lost (seed: "automatically subtract the ink
    // values from the brush"; the paper's gain measured in millimetres, Paper::wet_gain), taken
    // from the pressed nodes that still hold ink
    take_ink(ink, stats.deposited, stats.pressure);
    ink.deposited += stats.deposited;
    // capillary flow inside the tuft: every node's wetness relaxes toward the tuft's mean by
    // the fraction `capillary` per frame; sum(load) is unchanged (load_i += b (w_mean cap_i -
    // load_i) sums to zero), so conservation holds
    const double w_mean = ink.load.sum() / ink.capacity.sum();
    ink.load += scene.capillary * (w_mean * ink.capacity - ink.load);
    for (Eigen::Index i = 0; i < ink.load.size(); ++i) wetness[i] = std::clamp(ink.load[i] / ink.capacity[i], 0.0, 1.0);
  }
  // the soaked tip drains with the distance it travels in contact
  if (scene.soaked_tip && stats.contact) ink.excess *= std::exp(-stats.travel / scene.soak_drain_mm);
}

}  // namespace brushwork
