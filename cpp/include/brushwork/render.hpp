// Offscreen rendering through EGL (seed "Ink depositing" and "System prototype"): a shared GL
// context, a paper canvas of float ink in tiles, the footprint pass that deposits what the brush
// leaves on the paper, and a brush view for previews.
//
// Coordinates: paper millimetres, x right, y up, origin at the paper's bottom-left corner, paper at
// z = 0 and z up (the brush core's frame).  Pixel (i, j) of the paper covers
// [i, i+1] x [j, j+1] / px_per_mm mm, row j = 0 at the bottom; readback flips rows once so that
// numpy row 0 is the top of the paper.
#pragma once

#include "brushwork/render/context.hpp"
#include "brushwork/render/deposit.hpp"
#include "brushwork/render/paper.hpp"
#include "brushwork/render/view.hpp"
#include "brushwork/scene.hpp"
