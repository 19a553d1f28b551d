"""`brushwork bench outline`: the 3-D outlines measured on a folder of meshes, 8 views each.

Per view, against the depth buffer of the mesh (the truth the drawing is judged by):
- silhouette recall: of the pixels on the boundary of the mesh's projected area (outer outline
  and holes), the share with ink within TOL of the image size;
- precision: of the ink pixels, the share within TOL of a true visible line (the projected
  area's boundary, a jump in depth, a visible crease or mesh boundary);
- the median visible chain's length over the image diagonal, chains and strokes;
- seconds per phase (load, lines, visibility, chaining, brush, deposit).
Orbit coherence: over an orbit of ORBIT_VIEWS views, the ink of each view carried into the next
through its depth (each ink pixel lifted onto the nearest surface under it and projected by the
next camera) against the next view's ink: the IoU of the two, each widened by COHERENCE_PX, and
the F-measure at TOL (as for boundaries in image segmentation).  A contour slides over the
surface as the view turns (10 degrees move a sphere's contour points 1.5% of its radius inward),
which the strict IoU counts against it and the F-measure forgives; chains that appear or vanish
from one view to the next lower both.
A procedural bumpy torus of SYNTH_FACES faces, written to a temporary PLY, is measured too (the
time target of a large mesh).
"""
from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from . import report

TOL = 0.015              # of the image size: how far ink may lie from the line it draws
VIEWS = 8
ORBIT_VIEWS = 36
COHERENCE_PX = 2         # px each mask is widened by before the IoU
DEPTH_JUMP = 0.02        # of the mesh's diagonal: a jump in depth between neighbouring pixels
INK = 0.25               # coverage above which a pixel counts as ink
SYNTH_FACES = 70000
SUFFIXES = (".obj", ".ply", ".stl", ".off", ".glb", ".gltf")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--meshes", metavar="DIR", default="/work/shared/data/meshes",
                   help="folder of meshes to measure (default /work/shared/data/meshes)")
    p.add_argument("--size", type=int, default=1024, help="image side in px (default 1024)")
    p.add_argument("--style", default="baimiao", help="outline style (default baimiao)")
    p.add_argument("--orbit-size", type=int, default=512, help="image side of the orbit views (default 512)")
    p.add_argument("--no-synthetic", action="store_true", help="skip the 70,000-face procedural mesh")
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")


def _mask_distance(mask: np.ndarray) -> np.ndarray:
    """(H, W) px from each pixel to the nearest pixel of `mask` (large where the mask is empty)."""
    import cv2

    if not mask.any():
        return np.full(mask.shape, 1e9, dtype=np.float32)
    return cv2.distanceTransform((~mask).astype(np.uint8), cv2.DIST_L2, 5)


def truth(drawing) -> tuple[np.ndarray, np.ndarray]:
    """The projected area's boundary and every true visible line, (H, W) bool each."""
    import cv2

    depth, camera = drawing.depth, drawing.camera
    area = np.isfinite(depth)
    rim = area & ~cv2.erode(area.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    dist = np.where(area, camera.eye_distance(np.where(area, depth, 0.0).astype(np.float64)), 0.0)
    diag = float(np.linalg.norm(drawing.lines.points.max(axis=0) - drawing.lines.points.min(axis=0))) \
        if len(drawing.lines.points) else 1.0
    jump = np.zeros_like(area)
    for axis in (0, 1):
        step = np.abs(np.diff(dist, axis=axis)) > DEPTH_JUMP * diag
        step &= np.diff(area.astype(np.int8), axis=axis) == 0
        pad = [(0, 0), (0, 0)]
        pad[axis] = (0, 1)
        jump |= np.pad(step, pad)
    lines = rim | jump
    canvas = np.zeros(area.shape, np.uint8)
    for c in drawing.chains:
        if c.visible and c.kind in (1, 2):                     # boundary, crease
            cv2.polylines(canvas, [np.round(c.points).astype(np.int32)], False, 1, 1)
    return rim, lines | canvas.astype(bool)


def score(drawing) -> dict:
    """Recall, precision and chain figures of one view."""
    size = drawing.camera.size
    tol = TOL * max(size)
    ink = drawing.paper.ink() > INK
    rim, lines = truth(drawing)
    to_ink, to_line = _mask_distance(ink), _mask_distance(lines)
    recall = float(np.mean(to_ink[rim] <= tol)) if rim.any() else 1.0
    precision = float(np.mean(to_line[ink] <= tol)) if ink.any() else 0.0
    s = drawing.stats
    return {"recall": recall, "precision": precision, "median_chain": s["median_chain_over_diagonal"],
            "chains": s["chains"], "strokes": s["strokes"], **{k: v for k, v in s["seconds"].items()}}


def _lift(ink: np.ndarray, depth: np.ndarray, camera) -> np.ndarray:
    """(k, 3) mesh-space points under the ink pixels, each on the nearest surface within 3 px."""
    import cv2

    near = cv2.erode(np.where(np.isfinite(depth), depth, 4.0).astype(np.float32), np.ones((7, 7), np.uint8))
    ys, xs = np.nonzero(ink & (near < 2.0))
    p = np.column_stack([xs + 0.5, ys + 0.5, near[ys, xs], np.ones(len(xs))])
    v = p @ np.linalg.inv(camera.matrix).T
    return v[:, :3] / v[:, 3:4]


def coherence(a, b) -> tuple[float, float]:
    """View a's ink carried into view b against b's ink: (IoU of the two, each widened by
    COHERENCE_PX; F-measure at TOL: the harmonic mean of the share of b's ink near the carried
    ink and of the carried ink near b's)."""
    import cv2

    w, h = b.camera.size
    ink_a, ink_b = a.paper.ink() > INK, b.paper.ink() > INK
    q = b.camera.project(_lift(ink_a, a.depth, a.camera))
    carried = np.zeros((h, w), bool)
    inside = (q[:, 0] >= 0) & (q[:, 0] < w) & (q[:, 1] >= 0) & (q[:, 1] < h)
    carried[q[inside, 1].astype(int), q[inside, 0].astype(int)] = True
    kernel = np.ones((2 * COHERENCE_PX + 1,) * 2, np.uint8)
    ma = cv2.dilate(carried.astype(np.uint8), kernel).astype(bool)
    mb = cv2.dilate(ink_b.astype(np.uint8), kernel).astype(bool)
    union = (ma | mb).sum()
    iou = float((ma & mb).sum() / union) if union else 1.0
    tol = TOL * max(w, h)
    p = float(np.mean(_mask_distance(carried)[ink_b] <= tol)) if ink_b.any() else 0.0
    r = float(np.mean(_mask_distance(ink_b)[carried] <= tol)) if carried.any() else 0.0
    return iou, (2 * p * r / (p + r) if p + r > 0 else 0.0)


def bumpy_torus(faces: int = SYNTH_FACES):
    """A torus of `faces` triangles with bumps of two frequencies (a procedural test mesh)."""
    import trimesh

    minor = 140
    major = faces // (2 * minor)
    mesh = trimesh.creation.torus(major_radius=1.0, minor_radius=0.35, major_sections=major, minor_sections=minor)
    v = mesh.vertices
    theta, z = np.arctan2(v[:, 1], v[:, 0]), v[:, 2]
    ring = np.column_stack([np.cos(theta), np.sin(theta), np.zeros(len(v))])
    radial = v - ring
    radial /= np.linalg.norm(radial, axis=1, keepdims=True)
    bump = 0.06 * np.sin(7 * theta) * np.cos(3 * np.arctan2(z, (v[:, :2] * ring[:, :2]).sum(1) - 1.0))
    mesh.vertices = v + bump[:, None] * radial
    return mesh


def _mesh_files(folder: str) -> list[Path]:
    root = Path(folder)
    if not root.is_dir():
        raise ValueError(f"--meshes {folder}: no such folder")
    return sorted(p for p in root.iterdir() if p.suffix.lower() in SUFFIXES)


def _measure(path: Path, args, progress) -> dict:
    """8 views and the orbit of one mesh file: the per-view means and extremes."""
    from ..outline3d import View, draw, load_mesh, prepare
    from ..outline3d.strokes import OutlineStyle

    style = OutlineStyle.load(args.style)
    t0 = time.perf_counter()
    surface = prepare(*load_mesh(path)[:2])
    load = time.perf_counter() - t0
    rows = [score(draw(surface, View(360.0 * k / VIEWS, 20.0, 30.0, (args.size, args.size)), style))
            for k in range(VIEWS)]
    orbit = [draw(surface, View(360.0 * k / ORBIT_VIEWS, 20.0, 30.0, (args.orbit_size,) * 2), style)
             for k in range(ORBIT_VIEWS)]
    iou, f = zip(*[coherence(orbit[k], orbit[(k + 1) % ORBIT_VIEWS]) for k in range(ORBIT_VIEWS)])
    mean = {k: float(np.mean([r[k] for r in rows])) for k in rows[0]}
    phases = ("lines", "visibility", "chaining", "brush", "deposit")
    out = {"mesh": path.name, "faces": len(surface.faces), "recall": mean["recall"],
           "recall_min": min(r["recall"] for r in rows), "precision": mean["precision"],
           "precision_min": min(r["precision"] for r in rows), "median_chain": mean["median_chain"],
           "chains": mean["chains"], "strokes": mean["strokes"], "load": load,
           **{p: mean[p] for p in phases}, "seconds": load + sum(mean[p] for p in phases),
           "orbit_iou": float(np.mean(iou)), "orbit_iou_min": float(np.min(iou)), "orbit_f": float(np.mean(f)),
           "orbit_f_min": float(np.min(f))}
    if progress:
        progress(f"{path.name}: recall {out['recall']:.3f} precision {out['precision']:.3f} "
                 f"{out['seconds']:.2f} s/view orbit IoU {out['orbit_iou']:.3f} F {out['orbit_f']:.3f}")
    return out


def run(args, progress=None) -> dict:
    files = _mesh_files(args.meshes)
    results = [_measure(p, args, progress) for p in files]
    if not args.no_synthetic:
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / f"bumpy_torus_{SYNTH_FACES}.ply"
            bumpy_torus().export(path)
            results.append(_measure(path, args, progress))
    return {"size": args.size, "style": args.style, "views": VIEWS, "orbit_views": ORBIT_VIEWS, "tol": TOL,
            "meshes": results}


def table(result: dict) -> str:
    cols = ["mesh", "faces", "recall", "recall_min", "precision", "precision_min", "median_chain", "chains",
            "strokes", "seconds", "load", "lines", "visibility", "chaining", "brush", "deposit", "orbit_iou",
            "orbit_iou_min", "orbit_f", "orbit_f_min"]
    head = (f"3-D outlines, style {result['style']}, {result['size']} px, {result['views']} views per mesh "
            f"(means; _min: the worst view); tolerance {result['tol']:.1%} of the image; orbit of "
            f"{result['orbit_views']} views; seconds per view, load once per mesh\n")
    return head + report.markdown_table(result["meshes"], cols)


def handle(args: argparse.Namespace) -> int:
    from .report import progress, run_benchmark

    return run_benchmark("outline", args, lambda: run(args, progress=progress), table)
