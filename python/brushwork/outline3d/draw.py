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


@dataclass
class View:
    """Where the camera is: azimuth and elevation (degrees) about the mesh's y axis, the
    vertical field of view (0: orthographic), and the image size (W, H) px."""
    azimuth: float = 30.0
    elevation: float = 20.0
    fov_deg: float = 30.0
    size: tuple = (1024, 1024)


@dataclass
class Drawing:
    """What `draw` made: the paper, the camera, the chains drawn, the depth image and stats."""
    paper: object
    camera: cam.Camera
    chains: list
    depth: np.ndarray
    lines: ln.Lines
    stats: dict = field(default_factory=dict)


def _median_length(chains: list, diagonal: float) -> float:
    lengths = [c.length for c in chains if c.visible]
    return float(np.median(lengths)) / diagonal if lengths else 0.0


def _line_stats(lines: ln.Lines, chains: list, size: tuple) -> dict:
    diag = math.hypot(*size)
    counts = {name: int(sum(1 for c in chains if c.visible and c.kind == k)) for k, name in enumerate(ln.KINDS)}
    return {"segments": int(len(lines.segments)), "chains": int(sum(1 for c in chains if c.visible)),
            "hidden_chains": int(sum(1 for c in chains if not c.visible)), "chains_by_kind": counts,
            "median_chain_over_diagonal": _median_length(chains, diag)}


def draw(surface: ln.Surface, view: View, style: OutlineStyle, kinds=DEFAULT_KINDS, crease_deg: float = 60.0,
         hidden: str = "none") -> Drawing:
    """Draw a prepared surface as `style` sees it from `view`; stats carry the time per phase."""
    times = {}
    t = time.perf_counter()
    camera = cam.fit(surface.vertices, view.size, view.azimuth, view.elevation, view.fov_deg)
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
    drawer = OutlineDrawer(style, view.size)
    # hidden lines first, faint, under the visible ones; silhouettes last, on top
    order = sorted((c for c in chains if c.visible or hidden == "faint"), key=lambda c: (c.visible, -c.kind))
    dist = [camera.eye_distance(c.depth) for c in order]
    lo = min((float(d.min()) for d in dist), default=0.0)
    hi = max((float(d.max()) for d in dist), default=1.0)
    for c, d in zip(order, dist):
        drawer.draw(c, (hi - d) / max(hi - lo, 1e-300))
    times["brush"], times["deposit"] = drawer.times.brush, drawer.times.deposit
    stats = {"faces": int(len(surface.faces)), "vertices": int(len(surface.vertices)),
             **_line_stats(lines, chains, view.size), "strokes": drawer.times.strokes,
             "frames": drawer.times.frames, "seconds": times}
    return Drawing(drawer.paper, camera, chains, depth, lines, stats)
