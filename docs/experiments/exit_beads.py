"""Count the beads at stroke exits, and the ink IoU, for brush and style variants (session 11).

For the first n characters of a Make Me a Hanzi file (512 px): each stroke's footprint width as
the driver saw it on its travel frames; a stroke counts as beaded when, over the last 30% of
those frames, the width dips and then grows again to at least 1.6 times the dip and 1 mm (a
bulb after a neck). Counted by stroke family: for `tapered` (撇) and `rising` (提) every such
stroke is a defect; `flared` (捺) and `hook` profiles swell near their ends by design, so their
counts are mostly the profile; `plain` strokes end pressed (顿) and thinner. Brush model fields
can be overridden (the style's preset otherwise). A study script, not part of the package:

    PYTHONPATH=python python3 docs/experiments/exit_beads.py PATH/graphics.txt 80 [STYLE] [--all-frames] [field=value ...]
    e.g. ... 80 kai q_max=60   or   ... 80 kai stiffness_radius_power=0.5 stiffness_ratio=5

--all-frames (session 12) reads the width on every frame of the stroke from its first touch,
the exit's lift included (a teardrop the tip leaves as it lifts shows only there), and counts a
bead where, over the last 30% of those frames, the width grows to 1.6 times its dip and at
least 0.4 mm more; it also prints the strokes broken and the frames held.
"""
import collections
import sys

import numpy as np

from brushwork import motion
from brushwork.brush import Brush
from brushwork.glyphs import load_source
from brushwork.glyphs.score import beaded, iou, stroke_masks
from brushwork.motion import Style, Writer, writing_paper

SIZE = 512


def is_beaded(widths: np.ndarray) -> bool:
    """A dip, then a rise to >= 1.6x the dip and >= 1 mm, over the last 30% of the frames."""
    low = np.inf
    for w in widths[int(0.7 * len(widths)):]:
        low = min(low, w)
        if w >= 1.0 and w >= 1.6 * low:
            return True
    return False


def is_beaded_all(widths: np.ndarray) -> bool:
    """--all-frames: from the first touch, `glyphs.score.beaded`."""
    touched = np.nonzero(widths)[0]
    return len(touched) > 0 and beaded(widths[touched[0]:])


def main(path: str, n: int, style_name: str, overrides: dict, all_frames: bool = False) -> None:
    glyphs = list(load_source(f"mmah:{path}", None, errors=[]).items())[:n]
    style = Style.load(style_name)
    seen: list = []                                   # the current stroke's widths, mm
    beads, strokes = collections.Counter(), collections.Counter()
    observe, write_stroke, step = Writer._observe, Writer.write_stroke, Writer._step

    def traced_step(self, target, heading, press, tilt):
        step(self, target, heading, press, tilt)
        c = motion._centroid_and_width(self.contact, heading)
        seen.append(c[1] if c else 0.0)

    def traced_observe(self, target, heading, width_target):
        if width_target is not None and not all_frames:
            c = motion._centroid_and_width(self.contact, heading)
            seen.append(c[1] if c else 0.0)
        observe(self, target, heading, width_target)

    def traced_stroke(self, points, kind):
        seen.clear()
        write_stroke(self, points, kind)
        strokes[motion.family(kind)] += 1
        beads[motion.family(kind)] += (is_beaded_all if all_frames else is_beaded)(np.asarray(seen))

    Writer._observe, Writer.write_stroke = traced_observe, traced_stroke
    if all_frames:
        Writer._step = traced_step
    scores, breaks, holds = [], 0, 0
    for char, glyph in glyphs:
        paper = writing_paper(style, SIZE)
        writer = Writer(paper, style, 0)
        if overrides:
            model = writer.brush.model
            for key, value in overrides.items():
                setattr(model, key, type(getattr(model, key))(float(value)))
            writer.brush = Brush(model)
        writer.write(glyph)
        breaks, holds = breaks + writer.breaks, holds + writer.holds
        scores.append(iou(paper.ink() > 0.5, np.any(stroke_masks(glyph, SIZE), axis=0)))
    print(f"{n} characters, style {style_name}, {overrides or 'the preset'}: mean IoU {np.mean(scores):.4f}"
          + (f", {breaks} strokes broken, {holds} frames held" if all_frames else ""))
    print("| family | strokes | beaded |")
    print("|---|---:|---:|")
    for fam, count in sorted(strokes.items()):
        print(f"| {fam} | {count} | {beads[fam]} |")


if __name__ == "__main__":
    args = sys.argv[1:]
    plain = [a for a in args if "=" not in a and not a.startswith("--")]
    main(plain[0], int(plain[1]) if len(plain) > 1 else 80, plain[2] if len(plain) > 2 else "kai",
         dict(a.split("=", 1) for a in args if "=" in a), "--all-frames" in args)
