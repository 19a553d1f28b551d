"""A variable font with a weight axis written by the brush: each master is the same writing with
the style's nominal stroke width (`width_em`, which the hand's press follows) scaled by the
master's factor (MASTERS); every stroke its own closed contour, overlaps kept.

Masters are made interpolation-compatible stroke by stroke: each stroke's ink is taken off the
paper as it is written (the brush, its ink and the character's other strokes as in the whole
writing), its outer edge (the ink's exact outer loop when the ink is geometry, else traced from its
image) cut at its two tips (the regular master's farthest-apart
points, in the other masters the points nearest those), each half sampled at the same fractions of its own
length in every master; the regular master's samples are fitted (fit.py) and every master's are
fitted with the same cuts, each piece one cubic between the tangents of its own samples. fontTools'
varLib merges the masters: CFF2 in an OTF, gvar in a TTF (quadratics compatible across masters by
cu2qu), either one as WOFF2."""
from __future__ import annotations

import dataclasses

import numpy as np

from .fit import _fit_split, _merge, _unit, fit_one
from .outline import Em, loops_to_px, placement
from .trace import SPACING_PX, _signed_area, arc as _arc, ink_coverage, resample_closed, trace

# wght -> the factor on the style's width_em; the default master is the style as it is
# (500, between them, a master too: the brush's ink grows more slowly than its press towards the
# heavy end, and the straight line from 400 to 700 would draw 500 a shade light)
MASTERS = {300: 0.7, 400: 1.0, 500: 1.15, 700: 1.45}
DEFAULT_WGHT = 400
HALF_SAMPLES = 240       # samples along each half of a stroke's edge, tip to tip
TANGENT_REACH = 3        # samples either side over which a cut's tangent is the chord
FIT_TOL_PX = 0.5         # the regular master's fit: mean distance in px of the render


def master_style(style, factor: float):
    """style with its nominal stroke width scaled by factor."""
    return dataclasses.replace(style, width_em=style.width_em * factor)


def _each_stroke(glyph, size: int, style, seed: int, ink: str, take) -> list:
    """[take(paper)] once a stroke: the paper holding the ink of that stroke alone as the brush
    writes glyph in style (the paper cleared after each), its ink on the path `ink` picks."""
    from ..writing import Writer, writing_paper

    paper = writing_paper(style, size, 1, ink=ink)
    writer = Writer(paper, style, seed)
    out: list = []

    def stroke_done(k: int) -> None:
        out.append(take(paper))
        paper.clear()

    writer.write(glyph, on_stroke=stroke_done)
    return out


def stroke_images(glyph, size: int, style, seed: int = 0, ink: str = "gl") -> list:
    """(size, size, 3) uint8 images, one a stroke: the ink each stroke of glyph leaves as the brush
    writes the glyph in style."""
    return _each_stroke(glyph, size, style, seed, ink, lambda paper: paper.image())


def _edge(paper) -> np.ndarray | None:
    """The outer edge (n, 2) px of the largest ink on paper: its exact outer loop when the ink is
    geometry, else traced from its image."""
    if paper.inked_by == "geometry":
        return _largest(loops_to_px(paper.outlines(), paper.height_mm, paper.height_px))
    return outer_edge(paper.image())


def stroke_edges(glyph, size: int, style, seed: int = 0, ink: str = "gl") -> list:
    """The outer edge (n, 2) px of a size px render, or None, of each stroke's ink (_each_stroke)."""
    return _each_stroke(glyph, size, style, seed, ink, _edge)


def _largest(polys: list) -> np.ndarray | None:
    """The polyline of polys (each (n, 2) px, outer edges positive) enclosing the most ink, or None."""
    outer = [p for p in polys if _signed_area(p) > 0]
    return max(outer, key=_signed_area) if outer else None


def outer_edge(rgb: np.ndarray) -> np.ndarray | None:
    """The outer edge (n, 2) px of the largest ink in rgb, positive area (y down), or None."""
    return _largest(trace(ink_coverage(rgb)))


def _tips(p: np.ndarray) -> tuple:
    """Indices of the two points of p (n, 2) farthest apart."""
    d = np.linalg.norm(p[:, None, :] - p[None, :, :], axis=2)
    i, j = np.unravel_index(int(np.argmax(d)), d.shape)
    return int(i), int(j)


def ring(edge: np.ndarray, tips: tuple | None = None) -> np.ndarray:
    """The closed edge (n, 2) as 2 HALF_SAMPLES points: from one tip to the other, then back, each
    half sampled evenly along its length; the tips are its farthest-apart points, or its points
    nearest `tips` (the default master's, so that every master's halves start at the same ends)."""
    p = resample_closed(edge, SPACING_PX)
    if tips is None:
        i, j = _tips(p)
    else:
        i, j = (int(np.argmin(np.linalg.norm(p - t, axis=1))) for t in tips)
        if i == j:
            i, j = _tips(p)
    p = np.roll(p, -i, axis=0)
    j = (j - i) % len(p)
    closed = np.concatenate([p, p[:1]])
    h = HALF_SAMPLES
    return np.concatenate([_arc(closed[:j + 1], h + 1)[:h], _arc(closed[j:], h + 1)[:h]])


def _back(r: np.ndarray, i: int) -> np.ndarray:
    """The unit tangent of the closed ring r at sample i pointing back along it."""
    k, n = TANGENT_REACH, len(r)
    return _unit(r[(i - k) % n] - r[(i + k) % n])


def cuts(r: np.ndarray, tol: float = FIT_TOL_PX) -> list:
    """The ring's sample indices (ascending, 0 and HALF_SAMPLES among them) where its fitted cubics
    meet: each half fitted within tol px (fit.py), the tips always cut."""
    h = HALF_SAMPLES
    out: list = []
    for a in (0, h):
        p = np.concatenate([r, r[:1]])[a:a + h + 1]
        pieces = _merge(p, _fit_split(p, -_back(r, a), _back(r, (a + h) % len(r)), tol, TANGENT_REACH), tol)
        out += [a + first for first, _, _ in pieces]
    return out


def _piece(r: np.ndarray, a: int, b: int, tol: float) -> tuple:
    """fit_one of the ring r's samples a..b (b may be len(r): the start again)."""
    closed = np.concatenate([r, r[:1]])
    return fit_one(closed[a:b + 1], -_back(r, a), _back(r, b % len(r)), tol)


def shared_cuts(rings: list, tol: float = FIT_TOL_PX, rounds: int = 12) -> list:
    """Cuts (as cuts gives them) that fit every ring of rings (one stroke in every master, the
    same number of samples, the default master's first): the default's cuts, and each piece that
    some master's samples do not fit within tol cut again at that master's farthest sample."""
    at = cuts(rings[0], tol)
    for _ in range(rounds):
        ends = at + [len(rings[0])]
        more = set()
        for a, b in zip(ends, ends[1:]):
            for r in rings:
                _, err, i = _piece(r, a, b, tol)
                if err > 1.0 and b - a > 2 * TANGENT_REACH:
                    more.add(a + min(max(i, TANGENT_REACH), b - a - TANGENT_REACH))
                    break
        if not more:
            break
        at = sorted(set(at) | more)
    return at


def fit_at(r: np.ndarray, at: list) -> np.ndarray:
    """(len(at), 4, 2) cubics around the ring r, one between each two cuts (the last closing it),
    each ending on its cut samples with the ring's own tangents there, its handles fitted."""
    ends = list(at) + [len(r)]
    return np.array([_piece(r, a, b, FIT_TOL_PX)[0] for a, b in zip(ends, ends[1:])])


def master_outlines(glyph, em: Em, style, seed: int = 0, masters: dict = MASTERS, ink: str = "gl") -> dict:
    """{wght: [contour (m, 4, 2) font units a stroke]}: the glyph written at each master's press
    (its ink on the path `ink` picks), every master's contours compatible (same cubics, stroke by
    stroke), all moved by the placement of the default master's ink in the em box. ValueError when a stroke leaves no ink in some master."""
    edges = {w: stroke_edges(glyph, em.size, master_style(style, f), seed, ink) for w, f in masters.items()}
    # every master moved alike: the default master's ink centred in the em box
    shift = placement([e for e in edges[DEFAULT_WGHT] if e is not None], em.size)
    out: dict = {w: [] for w in masters}
    for k in range(len(glyph.strokes)):
        if any(edges[w][k] is None for w in masters):
            raise ValueError(f"stroke {k + 1} of {glyph.char} leaves no ink at some weight")
        ref = ring(edges[DEFAULT_WGHT][k])
        tips = (ref[0], ref[HALF_SAMPLES])
        rings = {w: ref if w == DEFAULT_WGHT else ring(edges[w][k], tips) for w in masters}
        at = shared_cuts([ref] + [r for w, r in rings.items() if w != DEFAULT_WGHT])
        for w in masters:
            out[w].append(em.to_font(fit_at(rings[w], at) + shift))
    return out


def _ccw(contours: list):
    """A RecordingPen of the cubic contours (each (m, 4, 2), clockwise as traced) reversed to run
    counter-clockwise, overlaps kept (nonzero winding fills their union)."""
    from fontTools.pens.recordingPen import RecordingPen

    rec = RecordingPen()
    for c in contours:
        back = c[::-1, ::-1]
        rec.moveTo(tuple(back[0, 0].tolist()))
        for cubic in back:
            rec.curveTo(*map(tuple, cubic[1:].tolist()))
        rec.closePath()
    return rec


def _quadratic_masters(masters: dict) -> dict:
    """{wght: {char: RecordingPen of quadratics}}: each cubic of each stroke made quadratic by cu2qu
    across all masters at once (the same number of points in each), counter-clockwise (build's
    glyf pen turns them clockwise)."""
    from fontTools.cu2qu import curves_to_quadratic
    from fontTools.pens.recordingPen import RecordingPen

    from .build import QUAD_ERR

    weights = list(masters)
    out: dict = {w: {} for w in weights}
    for char in masters[weights[0]]:
        recs = {w: RecordingPen() for w in weights}
        for k in range(len(masters[weights[0]][char])):
            backs = [masters[w][char][k][::-1, ::-1] for w in weights]
            for w, b in zip(weights, backs):
                recs[w].moveTo(tuple(b[0, 0].tolist()))
            for j in range(len(backs[0])):
                splines = curves_to_quadratic([b[j].tolist() for b in backs], [QUAD_ERR] * len(weights))
                for w, spline in zip(weights, splines):
                    recs[w].qCurveTo(*map(tuple, spline[1:]))
            for w in weights:
                recs[w].closePath()
        for w in weights:
            out[w][char] = recs[w]
    return out


def _designspace(fonts: dict):
    """A DesignSpaceDocument of the master TTFonts {wght: font} on a wght axis, with a named
    instance at each master."""
    from fontTools.designspaceLib import AxisDescriptor, DesignSpaceDocument, InstanceDescriptor, SourceDescriptor

    doc = DesignSpaceDocument()
    axis = AxisDescriptor()
    axis.tag, axis.name = "wght", "Weight"
    axis.minimum, axis.default, axis.maximum = min(fonts), DEFAULT_WGHT, max(fonts)
    doc.addAxis(axis)
    for w, font in sorted(fonts.items()):
        src = SourceDescriptor()
        src.font, src.name, src.location = font, f"wght{w}", {"Weight": w}
        doc.addSource(src)
    for w in _named_weights(fonts):
        inst = InstanceDescriptor()
        inst.styleName, inst.location = WEIGHT_NAMES[w], {"Weight": w}
        doc.addInstance(inst)
    return doc


def _named_weights(fonts: dict) -> list:
    """The standard weights (WEIGHT_NAMES) within the masters' span: the named instances."""
    return [w for w in sorted(WEIGHT_NAMES) if min(fonts) <= w <= max(fonts)]


def _stat(vf, weights: list) -> None:
    """A STAT table naming each of the weights on the wght axis, Regular elidable."""
    from fontTools.otlLib.builder import buildStatTable

    values = [{"value": w, "name": WEIGHT_NAMES[w], **({"flags": 0x2} if w == DEFAULT_WGHT else {})} for w in weights]
    buildStatTable(vf, [{"tag": "wght", "name": "Weight", "values": values}])


WEIGHT_NAMES = {100: "Thin", 200: "ExtraLight", 300: "Light", 400: "Regular", 500: "Medium", 600: "SemiBold",
                700: "Bold", 800: "ExtraBold", 900: "Black"}


def make_variable(masters: dict, info, cff: bool = True):
    """A variable TTFont (CFF2 when cff, else glyf + gvar) of masters {wght: {char: [contours]}}
    on a wght axis; the glyf contours flagged as overlapping (OVERLAP_SIMPLE)."""
    from fontTools import varLib

    from .build import make_font

    quads = None if cff else _quadratic_masters(masters)
    fonts = {}
    for w, outlines in masters.items():
        draw = (lambda c, contours: _ccw(contours)) if cff else (lambda c, contours, q=quads[w]: q[c])
        fonts[w] = make_font(outlines, info, cff=cff, draw=draw, specialize=False)
    vf, _, _ = varLib.build(_designspace(fonts), exclude=["BASE", "STAT"])
    vf["BASE"] = fonts[DEFAULT_WGHT]["BASE"]
    _stat(vf, _named_weights(fonts))
    if not cff:
        for name in vf.getGlyphOrder():
            glyph = vf["glyf"][name]
            if glyph.numberOfContours > 0:
                glyph.flags[0] |= 0x40          # OVERLAP_SIMPLE: the strokes overlap by design
    return vf


def press_factor(wght: float) -> float:
    """The factor on the style's width_em that the axis's wght stands for: MASTERS' factors
    joined by straight lines."""
    ws = sorted(MASTERS)
    return float(np.interp(wght, ws, [MASTERS[w] for w in ws]))


def write_variable(outlines: dict, path, info) -> str:
    """The variable font of outlines {char: {wght: contours}} at path (.otf CFF2, .ttf gvar,
    .woff2 of the CFF2 font), written atomically. Returns the path."""
    import os

    from ..files import write_atomic
    from .build import check_font_path

    path = os.fspath(path)
    suffix = check_font_path(path)
    masters = {w: {c: o[w] for c, o in outlines.items()} for w in MASTERS}
    font = make_variable(masters, info, cff=suffix != ".ttf")
    if suffix == ".woff2":
        font.flavor = "woff2"
    write_atomic(path, font.save, suffix=suffix)
    return path

