// What the renderer takes of a brush at one deposit (seed "Ink depositing"): each tuft's
// geometry (its sections Omega_0..Omega_n, from which the swept surface and the footprint are
// made), the wetness of its nodes, its ink's colours, and an identity that tells a paper whether
// the tuft was there at the last deposit (a stroke is swept between two frames of one tuft only).
// Values: nothing in them refers back to the brush they were taken from.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "brushwork/geometry.hpp"

namespace brushwork {

using Loops = std::vector<Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>;

// One tuft at one deposit.
struct TuftFrame {
  int tuft = 0;                   // which tuft of its brush: 0 the main tuft, 1 + j the child T_j
  std::vector<Section> sections;  // Omega_0..Omega_n, mm (the swept surface's rings)
  Vec3 root = Vec3::Zero();       // mm, the root O_0
  Eigen::VectorXd wetness;        // (n+1,) in [0, 1], root to tip
  double segment_mm = 0.0;        // mm, the longest spine segment (the render mesh is sized by it)
  double belly_mm = 0.0;          // mm, the belly radius r (likewise)
  std::vector<std::array<float, 4>> ramp;  // the tuft's own ink, straight RGBA root..tip (empty: not loaded)
  int nodes() const { return static_cast<int>(sections.size()); }
};

// A brush at one deposit: the tufts that meet the paper (the main tuft first; even tufts in its
// place while split), and what the ink it spends is measured by.
struct BrushFrame {
  std::uint64_t brush = 0;        // the brush's identity: a stroke goes on only with the brush it began with
  int nodes = 0;                  // the main tuft's n+1 (its ink holds one entry per node)
  std::vector<float> pressure;    // (n+1) the main tuft's node pressure (node_pressure)
  std::vector<TuftFrame> tufts;
};

// pressure per spine node in [0, 1]: how deep the lowest point of Omega_i lies below the paper,
// in units of its minor radius c_i (seed "Dry brush": the threshold varies with node pressure)
std::vector<float> node_pressure(const std::vector<Section>& sections);

// the footprint loops of these sections swept into a mesh of `opt`; the last few are kept, so a
// frame's footprint asked for twice (by the writer, by the ink's ledger) is cut once
Loops footprint_of(const std::vector<Section>& sections, const MeshOptions& opt = MeshOptions{});

// the tuft's footprint on the core's own mesh (MeshOptions{}), whatever a paper's resolution
Loops own_footprint(const TuftFrame& tuft);

}  // namespace brushwork
