"""Frame-by-frame trace of one stroke as the kai driver writes it (session 10).

For each frame of stroke N of a character (default source, 512 px): the solver's iterations and
status, the press the driver asked for (fraction of the tuft length L), the footprint's width
across the travel (mm), the bend angles theta_0..theta_5 (rad), the spine nodes' heights (mm)
and their distance along the travel from the root (mm). A study script, not part of the
package:

    PYTHONPATH=python python3 docs/experiments/exit_trace.py 人 2 60 78 [q_max]

The bead at the end of a tapering stroke shows as a width that collapses in one frame (the
belly leaves the paper and only the tip touches; theta_5 swings by a radian or more) and then
grows again as the width loop presses down once more.
"""
import math
import sys

import numpy as np

from brushwork.brush import Brush
from brushwork.glyphs import load_source
from brushwork.motion import Style, Writer, _centroid_and_width, writing_paper


def main(char: str, stroke_no: int, first: int, last: int, q_max: int | None) -> None:
    glyph = load_source("default", char, errors=[])[char]
    style = Style.load("kai")
    writer = Writer(writing_paper(style, 512), style, 0)
    if q_max is not None:
        model = writer.brush.model
        model.q_max = q_max
        writer.brush = Brush(model)
    state = {"stroke": 0, "frame": 0}
    write_stroke, step = Writer.write_stroke, Writer._step

    def traced_stroke(self, points, kind):
        state["stroke"] += 1
        state["frame"] = 0
        write_stroke(self, points, kind)

    def traced_step(self, target, heading, press, tilt):
        step(self, target, heading, press, tilt)
        if state["stroke"] != stroke_no:
            return
        state["frame"] += 1
        if not first <= state["frame"] <= last:
            return
        names, x = self.brush.variable_names(), np.asarray(self.brush.variables())
        theta = " ".join(f"{x[names.index(f'theta_{k}')]:+.2f}" for k in range(6))
        seen = _centroid_and_width(self.contact, heading)
        nodes = np.asarray(self.brush.skeleton())                       # (n+1, 3) mm
        along = (nodes[:, :2] - nodes[0, :2]) @ np.array([math.cos(heading), math.sin(heading)])
        stats = self.brush.last_stats
        print(f"frame {state['frame']:3d}  it {stats.iterations:3d} {stats.status[:14]:14s}  press {press:+.3f} L  "
              f"width {seen[1] if seen else 0.0:5.2f} mm  theta {theta}  |  z " +
              " ".join(f"{z:5.2f}" for z in nodes[:, 2]) + "  |  along " + " ".join(f"{a:5.1f}" for a in along))

    Writer.write_stroke, Writer._step = traced_stroke, traced_step
    writer.write(glyph)


if __name__ == "__main__":
    a = sys.argv[1:]
    main(a[0], int(a[1]), int(a[2]), int(a[3]), int(a[4]) if len(a) > 4 else None)
