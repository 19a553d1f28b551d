"""Footprint width against press depth in a steady drag (session 7).

The small brush (kai's) dragged straight at 15 degrees of tilt, 1 mm a frame, at press depths
0.16 to 0.46 tuft lengths below first contact; prints the mean footprint width across the
travel (mm) over the steady middle of each drag.  A study script, not part of the package:

    PYTHONPATH=python python3 docs/experiments/width_press.py [field=value ...]

field=value: BrushModel overrides, e.g. spread_gain=0.5 or lateral_spreading=False.
"""
import sys

import numpy as np

import brushwork as bw
from brushwork.motion import _centroid_and_width
from brushwork.motions import straight_stroke


def main(overrides: list[str]) -> None:
    fields = {}
    for item in overrides:
        name, value = item.split("=")
        fields[name] = value == "True" if value in ("True", "False") else float(value)
    model = bw.BrushModel.preset("small").replace(**fields)
    out = []
    for press in np.arange(0.16, 0.47, 0.02):
        brush, widths = bw.Brush(model), []
        for pose in straight_stroke(model, start=(0, 0), length_mm=40, step_mm=1.0, press=press, tilt_deg=15.0):
            brush.step(pose)
            seen = _centroid_and_width(brush.footprint(), 0.0)    # heading 0: the drag is along +x
            widths.append(seen[1] if seen else 0.0)
        out.append(f"{press:.2f} L: {np.mean(widths[25:-8]):.2f} mm")
    print(", ".join(out))


if __name__ == "__main__":
    main(sys.argv[1:])
