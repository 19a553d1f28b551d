"""Work-precision benchmark: the reference, the settings swept and the notes the report carries."""
from __future__ import annotations

from typing import Callable, Optional


# the reference: the core at this tolerance and iteration budget, then the Newton polish
REF_TOLERANCE = 1e-10
REF_Q_MAX = 1000
# the settings swept (the shipped q_max and tolerance are added if missing)
Q_MAX_SWEEP = (1, 2, 3, 5, 10, 20, 50)
TOL_SWEEP = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
RATE_SWEEP = (0.5, 2.0, 4.0)
# a reference frame counts when its polished KKT is at most this (or, on a frame split into
# sub-steps, which cannot be polished, when the core's own KKT is at most REF_CORE_KKT_OK)
REF_KKT_OK = 1e-9
REF_CORE_KKT_OK = 1e-5
# denominator floor of the relative energy gap, in units of kappa_root (N*mm): frames in the
# air have E* ~ 0, where a relative gap means nothing
ENERGY_FLOOR = 1e-3
# a row is "faster" than the default only when its median time is this much smaller (timing noise
# on a shared 2-core machine)
FASTER_MARGIN = 0.05

# the end of the pipeline: ink-mask IoU of one rendered character against its reference render.
# A function (brush_model_overrides: dict) -> float; None turns the column off (--quick does).
def _ink_mask_iou_default() -> Callable[[dict], float]:
    from ..glyphs import InkMaskIoU

    return InkMaskIoU()


INK_MASK_IOU: Optional[Callable[[], Callable[[dict], float]]] = _ink_mask_iou_default
INK_NOTE = ("永 (bundled glyph) written in kai at 512 px with each setting's brush, against the "
            "same written with q_max 100000 and tolerance 1e-10; full runs only (not --quick)")
FLOAT_NOTE = "not built: the core is double only (cpp/include/brushwork/brush.hpp)"
TUFTS_NOTE = ("tufts: the main tuft and its children, split from the first touch (sprout_spread 0); "
              "mean q is the main tuft's, frames/s the whole brush's")

OURS = "brushwork SQP"
