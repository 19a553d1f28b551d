"""How far a better width model could lift the glyph IoU (session 17, issue 4).

A round pen laid as discs along each stroke's centreline, every `step_mm`, scored against the
union of the outlines at 512 px (as `bench glyphs` scores the brush), with four sets of widths:

- the kai driver's target widths (`motion.stroke_targets`, the character's density, no jitter);
- the oracle: twice the outline's own distance to its edge at each point (the stroke's mask,
  OpenCV's distance transform): the most any width model can give on these centrelines;
- log-linear corrections of the driver's targets, fitted by least squares to log(oracle /
  target) on the even-numbered characters and scored on the odd ones (so a feature that only
  memorises this sample gains nothing on the held-out half). Features, all from the centrelines
  alone (what a driver has for a character without outlines): `ends` (bumps at 0, 0.5, 1 of the
  stroke's length), `family` (one per stroke family), `direction` (|sin heading|), `length`
  (log of the stroke's length), `crowd` (log of the distance, clipped to 1..30 mm, to the nearest
  point of another stroke).

Two placements of the discs: `median` (the points of the resampled centreline) and, with
`--aim`, the points the driver aimed the footprint at in each travel frame of a real run of the
brush (offsets, reach at the ends; 2 processes, about 60 s), where the brush's own ink, and discs
at the widths its footprint had in each of those frames, are scored too. A study script, not part of the package:

    PYTHONPATH=python python3 docs/experiments/width_model_ceiling.py PATH/graphics.txt [--aim]
"""
import sys
from concurrent.futures import ProcessPoolExecutor

import cv2
import numpy as np

from brushwork import motion
from brushwork.glyphs import load_source
from brushwork.glyphs.score import iou, stroke_masks
from brushwork.motion import Style, Writer, family, stroke_targets, writing_paper

SIZE = 512
FAMILIES = ("dot", "flared", "hook", "plain", "rising", "tapered")
MODELS = {"targets": None, "ends": ("ends",), "ends+family+direction": ("ends", "family", "direction"),
          "+length": ("ends", "family", "direction", "length"),
          "+crowd": ("ends", "family", "direction", "crowd"),
          "all five": ("ends", "family", "direction", "length", "crowd")}


def features(pts, frac, fam, heading, length, crowd, use) -> np.ndarray:
    """(n, k) design matrix for n points: a constant, then the features in `use`."""
    n = len(pts)
    cols = [np.ones(n)]
    if "ends" in use:
        cols += [np.exp(-((frac - c) / 0.1) ** 2) for c in (0.0, 0.5, 1.0)]
    if "family" in use:
        cols += [(fam == f).astype(float) for f in FAMILIES[1:]]
    if "direction" in use:
        cols.append(np.abs(np.sin(heading)))
    if "length" in use:
        cols.append(np.log(length))
    if "crowd" in use:
        cols.append(np.log(np.clip(crowd, 1.0, 30.0)))
    return np.stack(cols, axis=1)


def pen(px: np.ndarray, radius_px: np.ndarray) -> np.ndarray:
    """(SIZE, SIZE) bool: discs of `radius_px` (n,) at `px` (n, 2) image pixels (x right, y down)."""
    mask = np.zeros((SIZE, SIZE), np.uint8)
    for (x, y), r in zip(px, radius_px):
        if r > 0:
            cv2.circle(mask, (int(round(x * 16)), int(round(y * 16))), int(round(r * 16)), 1, -1, cv2.LINE_8, 4)
    return mask.astype(bool)


def aim_points(task):
    """Write characters with the kai driver; per travel frame (aim point x, y mm, stroke index, the
    footprint's width that frame mm) and the ink."""
    glyphs, style = task
    out = []
    for glyph in glyphs:
        rows, stroke = [], [-1]
        writer = Writer(writing_paper(style, SIZE), style, 0)
        observe, write_stroke = writer._observe, writer.write_stroke

        def traced_observe(target, heading, width_target):
            if width_target is not None:
                seen = motion._centroid_and_width(writer.contact, heading)
                rows.append((target[0], target[1], stroke[0], seen[1] if seen else 0.0))
            observe(target, heading, width_target)

        def traced_stroke(points, kind):
            stroke[0] += 1
            write_stroke(points, kind)

        writer._observe, writer.write_stroke = traced_observe, traced_stroke
        writer.write(glyph)
        out.append((np.asarray(rows), writer.paper.ink() > 0.5))
    return out


def character(glyph, style: Style, aimed=None) -> dict:
    """Per point of the character (on its centrelines, or at the aim points): image px, target and
    oracle width (px), and the features."""
    ppm = SIZE / style.em_mm
    masks = stroke_masks(glyph, SIZE)
    strokes = [np.asarray(s.points, dtype=float) * style.em_mm for s in glyph.strokes]
    w_nom = style.width_em * style.em_mm * style.density(len(strokes))
    dense = [motion._resample(p, style.step_mm)[0] for p in strokes]
    cols = {k: [] for k in ("px", "target", "oracle", "seen", "frac", "fam", "heading", "length", "crowd")}
    for k, (stroke, pts) in enumerate(zip(glyph.strokes, strokes)):
        path, s, heading, width = stroke_targets(style, pts, stroke.kind, w_nom)
        length = max(s[-1], 1e-6)
        frac = s / length
        at = path                      # where the discs go, mm on the paper
        if aimed is not None:
            # the aim points of this stroke's travel frames (the driver adds the style's offset to
            # the centreline), each given the features of its nearest centreline point
            mine = aimed[aimed[:, 2] == k] if len(aimed) else np.zeros((0, 4))
            at, seen = mine[:, :2], mine[:, 3]
            path = at - np.asarray(style.offset_em) * style.em_mm
            near = np.argmin(((path[:, None, :] - dense[k][None]) ** 2).sum(-1), axis=1)
            frac, heading, width = frac[near], heading[near], width[near]
        else:
            seen = np.zeros(len(path))
        if len(path) == 0:
            continue
        others = [dense[j] for j in range(len(dense)) if j != k]
        crowd = (np.sqrt(((path[:, None, :] - np.concatenate(others)[None]) ** 2).sum(-1)).min(axis=1)
                 if others else np.full(len(path), 30.0))
        px = np.stack([at[:, 0] * ppm, SIZE - at[:, 1] * ppm], axis=1)
        dt = cv2.distanceTransform(masks[k].astype(np.uint8), cv2.DIST_L2, 5)
        ij = np.clip(np.round(px).astype(int), 0, SIZE - 1)
        for key, val in (("px", px), ("target", width * ppm), ("oracle", 2.0 * dt[ij[:, 1], ij[:, 0]]), ("seen", seen * ppm),
                         ("frac", frac), ("fam", np.full(len(path), family(stroke.kind))), ("heading", heading),
                         ("length", np.full(len(path), length)), ("crowd", crowd)):
            cols[key].append(val)
    out = {k: np.concatenate(v) for k, v in cols.items()}
    out["ref"] = np.any(masks, axis=0)
    return out


def design(c: dict, use) -> np.ndarray:
    return features(c["px"], c["frac"], c["fam"], c["heading"], c["length"], c["crowd"], use)


def main(path: str, aim: bool) -> None:
    style = Style.load("kai")
    glyphs = [g for _, g in load_source(f"mmah:{path}", None, errors=[]).items()]
    aimed, inks = [None] * len(glyphs), None
    if aim:
        halves = [glyphs[0::2], glyphs[1::2]]
        with ProcessPoolExecutor(2) as pool:
            runs = list(pool.map(aim_points, [(h, style) for h in halves]))
        order = [runs[k % 2][k // 2] for k in range(len(glyphs))]
        aimed, inks = [o[0] for o in order], [o[1] for o in order]
    chars = [character(g, style, a) for g, a in zip(glyphs, aimed)]
    train, test = chars[0::2], chars[1::2]
    def score(widths_of, part) -> float:
        """Mean IoU over `part` of discs whose diameters (px) are `widths_of(character)`."""
        return float(np.mean([iou(pen(c["px"], 0.5 * widths_of(c)), c["ref"]) for c in part]))

    print(f"{len(glyphs)} characters, discs at the {'aim points of a run of the brush' if aim else 'centrelines'}; "
          f"mean IoU on the held-out (odd) half, and on all")
    if inks is not None:
        print(f"  the brush itself: {np.mean([iou(ink, c['ref']) for ink, c in zip(inks, chars)]):.4f} (all)")
        print(f"  the widths the footprint had: {score(lambda c: c['seen'], test):.4f} / {score(lambda c: c['seen'], chars):.4f}")
    print(f"  oracle widths: {score(lambda c: c['oracle'], test):.4f} / {score(lambda c: c['oracle'], chars):.4f}")
    for name, use in MODELS.items():
        if use is None:
            beta = np.zeros(1)
        else:
            X, y = [], []
            for c in train:
                ok = c["oracle"] > 2.0      # points whose centreline lies inside the outline
                X.append(design(c, use)[ok])
                y.append(np.log(c["oracle"][ok] / c["target"][ok]))
            beta = np.linalg.lstsq(np.concatenate(X), np.concatenate(y), rcond=None)[0]
        for scale in (1.0, 1.05, 1.1):
            w = lambda c, b=beta, u=use: c["target"] * np.exp(design(c, u or ()) @ b) * scale
            print(f"  {name:24s} x{scale:.2f}: {score(w, test):.4f} / {score(w, chars):.4f}"
                  + ("" if use is None or scale != 1.0 else f"   coefficients {np.round(beta, 3).tolist()}"))


if __name__ == "__main__":
    main(sys.argv[1], "--aim" in sys.argv[2:])
