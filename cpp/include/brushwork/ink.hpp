// The brush's ink (seed "Ink loading"): its load on each spine node, what a deposit spends of it,
// and the wetness the nodes take from it.  A state update of the brush, as step() is: the paper
// says what it took (InkUse), spend_ink() takes it from the brush.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "brushwork/geometry.hpp"
#include "brushwork/scene.hpp"

namespace brushwork {

// Ink on one brush.  Colours are straight (not premultiplied) RGBA in [0, 1]; alpha is the ink's
// opacity.  load/capacity are per spine node, in mm^2 of paper covered at full density; the
// brush's wetness is load / capacity.
struct Ink {
  std::vector<std::array<float, 4>> ramp{{0.0f, 0.0f, 0.0f, 1.0f}};  // root .. tip, >= 1 entry
  Eigen::VectorXd load;      // (n+1) mm^2
  Eigen::VectorXd capacity;  // (n+1) mm^2
  double excess = 0.0;       // soaked tip: excess moisture in [0, 1]
  double deposited = 0.0;    // mm^2 given to the paper so far (depletion scenes)

  // full ink of `total_mm2`, split over the nodes Omega_0..Omega_n in proportion to the section areas
  static Ink full(const std::vector<Section>& sections, double total_mm2);
  bool loaded() const { return load.size() > 0; }  // false until the brush is first dipped
  double total() const { return load.sum(); }
  void validate(int nodes) const;
};

// What one deposit took from the brush's ink, as the paper measured it.
struct InkUse {
  bool contact = false;         // some of the surface was below the paper
  bool drawn = false;           // the paper was inked
  double deposited = 0.0;       // mm^2 of full-density ink given to the paper (depletion only)
  std::vector<float> pressure;  // (n+1) node pressure in [0, 1] the paper was inked with (when drawn)
  double travel = 0.0;          // mm: the largest move of the surface in reach of the paper
};

// The ink's state update after a deposit: with depletion, the ink the paper gained taken from the
// nodes (first in proportion to pressure x load), capillary flow toward the tuft's mean wetness,
// and the nodes' `wetness` ((n+1,)) set to load / capacity; with a soaked tip, the excess
// moisture drained by the distance travelled in contact.
void spend_ink(const InkUse& use, const SceneFeatures& scene, Ink& ink, Eigen::VectorXd& wetness);

}  // namespace brushwork
