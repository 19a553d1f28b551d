// What one deposit of the brush on the paper did, and what it did to the brush's ink (seed
// "Ink loading").
#pragma once

#include <array>
#include <vector>

#include "brushwork/scene.hpp"
#include "brushwork/state.hpp"
#include "brushwork/tuft_frame.hpp"

namespace brushwork {

// What one deposit did.
struct DepositStats {
  bool contact = false;        // some of the surface was below the paper
  bool new_stroke = false;     // this deposit started a stroke
  int substeps = 0;            // footprints swept between the last deposit and this one
  int slides = 0;              // copies of a footprint slid along its move, the larger of the
                               // last and this part's count (0: blend only)
  double deposited = 0.0;      // mm^2 of full-density ink given to the paper (depletion only)
  std::array<int, 4> rect{{0, 0, 0, 0}};  // px x0, y0, x1, y1 (exclusive) touched, y up
  bool drawn = false;          // the footprint pass drew (contact, and some pixel of the paper)
  std::vector<float> pressure; // (n+1) node pressure in [0, 1] the pass drew with (when drawn)
  double travel = 0.0;         // mm: the largest move of the surface in reach of the paper
};

// What a deposit did to the brush's ink (seed "Ink loading"): with depletion, the ink the pass
// gave the paper taken from the nodes (first in proportion to pressure x load), capillary flow
// toward the tuft's mean wetness, and the brush's wetness set to load / capacity; with a soaked
// tip, the excess moisture drained by the distance travelled in contact.
void spend_ink(const DepositStats& stats, const SceneFeatures& scene, Ink& ink, Brush& brush);

// depletion: the density in [0, 1] a tuft's footprint reaches the paper at, from its nodes' wetness
double ink_density(const TuftFrame& tuft);

}  // namespace brushwork
