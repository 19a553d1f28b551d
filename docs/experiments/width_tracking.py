"""How much of the IoU the brush loses by not following the driver's own targets (session 10).

For the first n characters of a Make Me a Hanzi file (512 px, kai): the brush's ink IoU against
the outlines, beside two round pens laid as discs at the driver's targets (the centreline point
each travel frame aims the footprint at): one with the target width, one with the width the
footprint actually had. Then the relative width error (seen - target) / target over the frames,
by position along the stroke and by stroke family. A study script, not part of the package:

    PYTHONPATH=python python3 docs/experiments/width_tracking.py /path/to/graphics.txt 40
"""
import math
import sys

import cv2
import numpy as np

from brushwork import motion
from brushwork.glyphs import load_source
from brushwork.glyphs.score import iou, stroke_masks
from brushwork.motion import Style, Writer, writing_paper

SIZE = 512


def main(path: str, n: int) -> None:
    glyphs = list(load_source(f"mmah:{path}", None, errors=[]).items())[:n]
    style = Style.load("kai")
    rows, stroke = [], {"id": 0, "family": {}}       # rows: (x, y, target w, seen w, stroke id), mm
    observe, write_stroke = Writer._observe, Writer.write_stroke

    def traced_observe(self, target, heading, width_target):
        if width_target is not None:
            seen = motion._centroid_and_width(self.contact, heading)
            rows.append((target[0], target[1], width_target, seen[1] if seen else 0.0, stroke["id"]))
        observe(self, target, heading, width_target)

    def traced_stroke(self, points, kind):
        stroke["id"] += 1
        stroke["family"][stroke["id"]] = motion.family(kind)
        write_stroke(self, points, kind)

    Writer._observe, Writer.write_stroke = traced_observe, traced_stroke
    ppm = SIZE / style.em_mm
    scores = []
    for char, glyph in glyphs:
        start = len(rows)
        paper = writing_paper(style, SIZE)
        Writer(paper, style, 0).write(glyph)
        ref = np.any(stroke_masks(glyph, SIZE), axis=0)
        r = np.asarray(rows[start:])

        def pen(widths):
            mask = np.zeros((SIZE, SIZE), np.uint8)
            for (x, y), w in zip(r[:, :2], widths):
                if w > 0:
                    centre = (int(round(x * ppm * 16)), int(round((SIZE - y * ppm) * 16)))
                    cv2.circle(mask, centre, int(round(w * ppm * 8)), 1, -1, cv2.LINE_8, 4)
            return mask.astype(bool)

        scores.append((iou(paper.ink() > 0.5, ref), iou(pen(r[:, 2]), ref), iou(pen(r[:, 3]), ref)))
    s = np.mean(scores, axis=0)
    print(f"{len(glyphs)} characters: brush {s[0]:.4f}, pen at the target widths {s[1]:.4f}, "
          f"pen at the widths the footprint had {s[2]:.4f}")
    r = np.asarray(rows)
    rel = np.where(r[:, 3] > 0, (r[:, 3] - r[:, 2]) / r[:, 2], -1.0)
    pos = np.zeros(len(r))
    for k in np.unique(r[:, 4]):
        idx = np.where(r[:, 4] == k)[0]
        pos[idx] = np.linspace(0.0, 1.0, len(idx))
    for lo in np.arange(0.0, 1.0, 0.1):
        m = (pos >= lo) & (pos < lo + 0.1 + 1e-9)
        print(f"along {lo:.1f}-{lo + 0.1:.1f}: mean {rel[m].mean():+.3f}, mean |.| {np.abs(rel[m]).mean():.3f}")
    families = np.array([stroke["family"][int(k)] for k in r[:, 4]])
    for name in sorted(set(families)):
        m = families == name
        print(f"{name:8s}: {m.sum():5d} frames, mean {rel[m].mean():+.3f}, mean |.| {np.abs(rel[m]).mean():.3f}")


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 40)
