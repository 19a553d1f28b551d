"""How far the brush's joints wind while the kai or xing driver writes characters (session 7).

Counts the frames whose largest bend (theta_j) or lateral-line (psi_i) angle exceeds pi, and the
share of frames touching the paper and in the air whose largest bend exceeds 1.5 rad.  A study
script, not part of the package:

    PYTHONPATH=python python3 docs/experiments/winding.py mmah:PATH/graphics.txt kai [N]
"""
import math
import sys

import numpy as np

from brushwork.glyphs.sources import load_source
from brushwork.motion import Style, Writer, writing_paper


def main(source: str, style: str, count: int | None = None) -> None:
    glyphs = load_source(source)
    chars = list(glyphs)[:count] if count else list(glyphs)
    st = Style.load(style)
    past_pi, chars_past_pi, worst = 0, 0, (0.0, "")
    bent = {True: [0, 0], False: [0, 0]}       # touching?: [frames past 1.5 rad, frames]
    for char in chars:
        paper = writing_paper(st, 256)          # the motion does not depend on the resolution
        writer = Writer(paper, st, 0)
        names = writer.brush.variable_names()
        angles = np.array([n.startswith(("theta", "psi")) for n in names])
        bends = np.array([n.startswith("theta") for n in names])
        step, most = writer.brush.step, [0.0]

        def counted(pose, step=step, writer=writer, most=most):
            nonlocal past_pi
            stats = step(pose)
            x = np.abs(np.asarray(writer.brush.variables()))
            a = float(x[angles].max())
            past_pi += a > math.pi
            most[0] = max(most[0], a)
            tally = bent[stats.contacts > 0]
            tally[0] += float(x[bends].max()) > 1.5
            tally[1] += 1
            return stats

        writer.brush.step = counted
        writer.write(glyphs[char])
        chars_past_pi += most[0] > math.pi
        worst = max(worst, (most[0], char))
    frames = bent[True][1] + bent[False][1]
    print(f"{style}: {len(chars)} characters, {frames} frames; a bend or lateral angle past pi in "
          f"{past_pi} frames of {chars_past_pi} characters (largest {worst[0]:.1f} rad, {worst[1]}); "
          f"a bend past 1.5 rad in {100 * bent[True][0] / max(1, bent[True][1]):.2f}% of the frames "
          f"touching the paper and {100 * bent[False][0] / max(1, bent[False][1]):.2f}% of those in the air")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]) if len(sys.argv) > 3 else None)
