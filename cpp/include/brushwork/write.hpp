// A brush writing on a paper (seed "Ink depositing", "Ink loading"): the paper inks what it takes
// of the brush (Brush::frame()), then the brush spends the ink the paper took (spend_ink, its
// state update).  One call for C++ callers and the bindings alike; ink may be null (black ink
// at a constant level, nothing spent).
#pragma once

#include "brushwork/brush.hpp"
#include "brushwork/ink_geometry.hpp"
#include "brushwork/render.hpp"

namespace brushwork {

DepositStats deposit(Paper& paper, Brush& brush, Ink* ink);
DepositStats deposit(VectorPaper& paper, Brush& brush, Ink* ink);

}  // namespace brushwork
