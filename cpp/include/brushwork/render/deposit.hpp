// What one deposit of the brush on the paper did (seed "Ink depositing"); what it took from the
// brush's ink (InkUse) is the brush's to spend (ink.hpp).
#pragma once

#include <array>
#include <vector>

#include "brushwork/ink.hpp"
#include "brushwork/scene.hpp"
#include "brushwork/tuft_frame.hpp"

namespace brushwork {

// What one deposit did: what it took from the ink (contact, drawn, deposited, pressure, travel),
// and how it drew.
struct DepositStats : InkUse {
  bool new_stroke = false;     // this deposit started a stroke
  int substeps = 0;            // footprints swept between the last deposit and this one
  int slides = 0;              // copies of a footprint slid along its move, the larger of the
                               // last and this part's count (0: blend only)
  std::array<int, 4> rect{{0, 0, 0, 0}};  // px x0, y0, x1, y1 (exclusive) touched, y up
};

// depletion: the density in [0, 1] a tuft's footprint reaches the paper at, from its nodes' wetness
double ink_density(const TuftFrame& tuft);

}  // namespace brushwork
