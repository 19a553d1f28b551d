"""A mesh file to a brush drawing: load, fit the camera, find the feature lines, test them
against the depth buffer, chain them and draw each chain as one stroke of the brush."""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from . import camera as cam
from . import chains as ch
from . import lines as ln
from . import visibility as vis
from .meshfile import load_mesh  # noqa: F401  (the pipeline's first step, re-exported)
from .strokes import OutlineDrawer, OutlineStyle

DEFAULT_KINDS = ("silhouette", "boundary", "crease")
OCCLUSION_REACH = 0.02      # of the image diagonal: how far from a nearer line a line thins
OCCLUSION_STEPS = 4         # radii up to that reach: the thinning's ramp
OCCLUSION_DEPTH = 0.02      # of the mesh's diagonal: how much nearer a line must be to thin another


@dataclass
class View:
    """Where the camera is: azimuth and elevation (degrees) about the mesh's y axis, the
    vertical field of view (0: orthographic), and the image size (W, H) px; or a scene's own
    camera (its camera-to-world matrix and vertical field of view, meshfile.scene_camera)."""
    azimuth: float = 30.0
    elevation: float = 20.0
    fov_deg: float = 30.0
    size: tuple = (1024, 1024)
    scene_camera: tuple | None = None

    def camera(self, vertices: np.ndarray) -> cam.Camera:
        if self.scene_camera is not None:
            return cam.from_pose(vertices, self.size, *self.scene_camera)
        return cam.fit(vertices, self.size, self.azimuth, self.elevation, self.fov_deg)


@dataclass
class Drawing:
    """What `draw` made: the paper, the camera, the chains drawn, the depth image and stats."""
    paper: object
    camera: cam.Camera
    chains: list
    depth: np.ndarray
    lines: ln.Lines
    stats: dict = field(default_factory=dict)
    shapes: list = field(default_factory=list)     # vector.StrokeShape per stroke, when asked for


def _median_length(chains: list, diagonal: float) -> float:
    lengths = [c.length for c in chains if c.visible]
    return float(np.median(lengths)) / diagonal if lengths else 0.0


def _line_stats(lines: ln.Lines, chains: list, size: tuple) -> dict:
    diag = math.hypot(*size)
    counts = {name: int(sum(1 for c in chains if c.visible and c.kind == k)) for k, name in enumerate(ln.KINDS)}
    return {"segments": int(len(lines.segments)), "chains": int(sum(1 for c in chains if c.visible)),
            "hidden_chains": int(sum(1 for c in chains if not c.visible)), "chains_by_kind": counts,
            "median_chain_over_diagonal": _median_length(chains, diag)}


def _nearness(chains: list, camera) -> list:
    """Per chain (k,): 1 at the nearest point of all the chains, 0 at the farthest."""
    dist = [camera.eye_distance(c.depth) for c in chains]
    lo = min((float(d.min()) for d in dist), default=0.0)
    hi = max((float(d.max()) for d in dist), default=1.0)
    return [(hi - d) / max(hi - lo, 1e-300) for d in dist]


def _behind(chains: list, camera, size: tuple, margin: float) -> list:
    """Per chain (k,) in 0..1: how near (in the image) each point lies to a visible line that is
    nearer the eye than it by `margin` mesh units, 1 on it, 0 at OCCLUSION_REACH of the image
    diagonal and beyond (the visible lines' eye distances drawn into an image, its minimum
    taken over squares of OCCLUSION_STEPS half-sides up to that reach: separable, a few ms)."""
    import cv2

    w, h = size
    near = np.full((h, w), np.inf)                     # float64: mesh units of any size
    for c in chains:
        if c.visible:
            d = camera.eye_distance(c.depth)
            ix = np.clip(np.round(c.points).astype(int), 0, [w - 1, h - 1])
            np.minimum.at(near, (ix[:, 1], ix[:, 0]), d)
    reach = OCCLUSION_REACH * math.hypot(w, h)
    radii = [reach * (k + 1) / OCCLUSION_STEPS for k in range(OCCLUSION_STEPS)]
    mins = [cv2.erode(near, np.ones((2 * int(r) + 1,) * 2, np.uint8)) for r in radii]
    out = []
    for c in chains:
        ix = np.clip(np.round(c.points).astype(int), 0, [w - 1, h - 1])
        d = camera.eye_distance(c.depth) - margin
        hits = sum((m[ix[:, 1], ix[:, 0]] < d).astype(float) for m in mins)
        out.append(hits / OCCLUSION_STEPS)
    return out


def weights(chains: list, camera, style: OutlineStyle, diagonal: float) -> list:
    """Per chain (k,) its width against the kind's: the depth weight (nearer lines wider) and the
    thinning where a line runs on behind a nearer one (by more than OCCLUSION_DEPTH of the
    mesh's diagonal)."""
    near = _nearness(chains, camera)
    behind = _behind(chains, camera, camera.size, OCCLUSION_DEPTH * diagonal)
    return [(1.0 + style.depth_weight * (n - 0.5)) * (1.0 - style.occlusion_thinning * b)
            for n, b in zip(near, behind)]


def _strokes(drawer: OutlineDrawer, order: list, camera, style: OutlineStyle, diagonal: float,
             vector: bool) -> list:
    """Draw the chains in `order`, each one stroke; with `vector`, each stroke's outline as it
    is drawn (vector.StrokeShape): its region as geometry where the ink is geometry, else its
    share of the paper's coverage, traced."""
    from . import vector as vec

    shapes = []
    traced = vector and drawer.stroke_paper is None
    prior = drawer.paper.ink() if traced else None
    for c, w in zip(order, weights(order, camera, style, diagonal)):
        drawer.draw(c, w)
        alpha = 1.0 if c.visible else style.hidden_alpha
        if traced:
            inked = drawer.paper.ink()
            shapes.append(vec.StrokeShape(c.kind, c.visible, alpha, vec.stroke_outline(prior, inked, alpha)))
            prior = inked
        elif vector:
            shapes.append(vec.StrokeShape(c.kind, c.visible, alpha, drawer.stroke_loops()))
    return shapes


def draw(surface: ln.Surface, view: View, style: OutlineStyle, kinds=DEFAULT_KINDS, crease_deg: float = 60.0,
         hidden: str = "none", vector: bool = False, ink: str = "gl") -> Drawing:
    """Draw a prepared surface as `style` sees it from `view` on a paper whose ink takes the path
    `ink` (paper.INK_PATHS); stats carry the time per phase; with `vector`, the drawing's shapes
    carry each stroke's outline."""
    times = {}
    t = time.perf_counter()
    camera = view.camera(surface.vertices)
    lines = ln.extract(surface, camera, kinds, crease_deg)
    times["lines"] = time.perf_counter() - t
    t = time.perf_counter()
    depth = vis.depth_image(surface, camera)
    block = vis.farthest_near(depth, camera)
    radius = 0.5 * surface.diagonal
    is_visible = lambda samples: vis.visible(samples, block, camera, radius)  # noqa: E731
    times["visibility"] = time.perf_counter() - t
    t = time.perf_counter()
    min_px = style.min_length * math.hypot(*view.size)
    chains = ch.build(lines, camera, is_visible, min_px, style.smooth_passes)
    times["chaining"] = time.perf_counter() - t
    drawer = OutlineDrawer(style, view.size, ink, stroke_regions=vector)
    # hidden lines first, faint, under the visible ones; then the silhouettes, with the freshest ink
    # of a drying brush, and the lighter kinds after them
    order = sorted((c for c in chains if c.visible or hidden == "faint"), key=lambda c: (c.visible, c.kind))
    shapes = _strokes(drawer, order, camera, style, surface.diagonal, vector)
    times["brush"], times["deposit"] = drawer.times.brush, drawer.times.deposit
    stats = {"faces": int(len(surface.faces)), "vertices": int(len(surface.vertices)),
             **_line_stats(lines, chains, view.size), "strokes": drawer.times.strokes, "ink": drawer.paper.inked_by,
             "frames": drawer.times.frames, "seconds": times}
    return Drawing(drawer.paper, camera, chains, depth, lines, stats, shapes)
