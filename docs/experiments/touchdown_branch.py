"""Which way a pressed tuft buckles, against the frame rate and q_max (session 16, issue 5).

    cd <repo> && PYTHONPATH=python python3 docs/experiments/touchdown_branch.py [q_max ...]

The `small` brush, handle at 15 deg, pressed straight down from 0.1 L above first contact to
0.3 L below it (straight_stroke's press) in 12 x k frames, k = 1, 2, 4, 8, 16, then held for 30
frames.  Per run: the extra sub-steps Brush.step split the frames into, the footprint's area at
the end of the press and after the hold (mm^2), and node 4's x at the end of the press (mm; the
root is at x = 15, the tip touches near 10): above ~12 the belly buckled forward, under the
handle's lean, and lies on the paper; below ~9 it buckled backward and stands on its folded tip.
Also the tip joint's bend theta_5 a quarter into the press (rad): negative there, the tuft ended
backward in every run of session 16; positive, forward in all but one (q_max 30, 48 frames).
"""
import math
import sys

import numpy as np

import brushwork as bw
from brushwork.bench.precision import _signed_area


def area(loops) -> float:
    """mm^2 of the footprint: Brush.footprint's outer loops run counter-clockwise and its holes
    clockwise, so the signed areas of its (k, 2) mm loops add up to the inked area."""
    return sum(_signed_area(np.asarray(loop, dtype=float)) for loop in loops if len(loop) >= 3)


def main() -> None:
    caps = [int(a) for a in sys.argv[1:]] or [20]
    for q in caps:
        model = bw.BrushModel.preset("small")
        model.q_max = q
        L = model.tuft_length
        cz = L * math.cos(math.radians(15.0))
        z_air, z_press = cz + 0.1 * L, cz - 0.3 * L
        for k in (1, 2, 4, 8, 16):
            b = bw.Brush(model)
            n, extra = 12 * k, 0
            for j in range(n):
                z = z_air + (z_press - z_air) * (j + 1) / n
                extra += b.step(bw.Pose((15.0, 15.0, z), 15.0, 0.0)).substeps - 1
                if j == n // 4:
                    tip_bend = b.full_state()[2 * (model.n_segments - 1)]  # theta_5, rad
            pressed, node4 = area(b.footprint()), b.skeleton()[4][0]
            for _ in range(30):
                b.step(bw.Pose((15.0, 15.0, z_press), 15.0, 0.0))
            print(f"q_max {q:3d}  frames x{k:2d}: extra sub-steps {extra:2d}  footprint {pressed:6.2f} mm2 "
                  f"at the end of the press (node 4 at x {node4:6.2f} mm, theta_5 early {tip_bend:+.2f}), "
                  f"{area(b.footprint()):6.2f} after 30 held")


if __name__ == "__main__":
    main()
