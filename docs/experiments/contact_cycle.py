"""Frames caught in a period-2 contact cycle, on the precision motions at 1x (session 15, issue 5).

A study script, not part of the package:

    cd <repo> && PYTHONPATH=python OPENBLAS_NUM_THREADS=1 \
        python3 docs/experiments/contact_cycle.py [field=value ...]

For each motion of `brushwork bench precision` (1x poses, the shipped settings, or BrushModel
overrides such as wet_adhesion=0.0): how many frames flip the frozen contact set (touching or
not, `StepStats.contacts > 0`) against both neighbours, the solver's iterations on those frames
and on the others, and the share of frames at q_max.  With `--trace A B` it prints, for frames A
to B of the motion named by `--motion NAME`, the root, the section heights (mm, the solver's
constraints) and the contact multipliers: the cycle shows as sections that lift 1-2 mm on every
other frame.
"""
import sys

import numpy as np

from brushwork import Brush
from brushwork.bench import precision as P
from precision_quick import parse  # this folder is on sys.path when run as a script


def main() -> None:
    args = sys.argv[1:]
    trace, motion = None, None
    if "--trace" in args:
        k = args.index("--trace")
        trace = (int(args[k + 1]), int(args[k + 2]))
        del args[k:k + 3]
    if "--motion" in args:
        k = args.index("--motion")
        motion = args[k + 1]
        del args[k:k + 2]
    over = [(a.split("=")[0], parse(a.split("=")[1])) for a in args]
    total, cyc, capped = 0, 0, 0
    for mo in P.motions(False):
        if motion is not None and mo.name != motion:
            continue
        model = P._model_for(mo, over)
        brush = Brush(model)
        touch, its = [], []
        for f, pose in enumerate(mo.poses(1.0)):
            s = brush.step(pose)
            touch.append(s.contacts > 0)
            its.append(s.iterations)
            if trace and trace[0] <= f <= trace[1]:
                print(f"{f:4d} it {s.iterations:2d} contacts {s.contacts} KKT {s.kkt_residual:.0e} "
                      f"root x {pose.position[0]:6.2f} heights {np.round(brush.section_heights(), 2)} "
                      f"lambda {np.round(np.array(brush.multipliers()), 4)}")
        touch, its = np.array(touch), np.array(its)
        flip = np.zeros(len(touch), bool)
        flip[1:-1] = (touch[1:-1] != touch[:-2]) & (touch[1:-1] != touch[2:])
        total += len(touch)
        cyc += int(flip.sum())
        capped += int(np.sum(its >= model.q_max))
        on = f"{its[flip].mean():5.1f}" if flip.any() else "    -"
        print(f"{mo.name:36s} frames {len(touch):3d}  in the cycle {flip.sum():3d} (it/frame {on})  "
              f"others it/frame {its[~flip].mean():5.1f}  at q_max {np.mean(its >= model.q_max):.0%}")
    print(f"overrides {over}: {cyc} of {total} frames in the cycle, {capped} at q_max")


if __name__ == "__main__":
    main()
