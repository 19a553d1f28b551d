"""`brushwork bench outline`: the 3-D outlines measured on generated low-poly meshes, a large
procedural one and a folder of meshes (--meshes), 8 views each.

Per view, against the depth buffer of the mesh (the truth the drawing is judged by):
- silhouette recall: of the pixels on the boundary of the mesh's projected area (outer outline
  and holes), the share with ink within TOL of the image size;
- precision: of the ink pixels, the share within TOL of a true visible line (the projected
  area's boundary, a jump in depth past what the surface's slope explains, a visible crease or
  mesh boundary);
- the silhouettes' median ink width over the creases' (twice the ink's distance to its edge on
  the chains' centre lines), where both are drawn;
- the median visible chain's length over the image diagonal, chains and strokes;
- seconds per phase (load, lines, visibility, chaining, brush, deposit).
Orbit coherence: over an orbit of ORBIT_VIEWS views, the ink of each view carried into the next
through its depth (each ink pixel lifted onto the nearest surface under it and projected by the
next camera) against the next view's ink: the IoU of the two, each widened by COHERENCE_PX, and
the F-measure at TOL (as for boundaries in image segmentation).  A contour slides over the
surface as the view turns (10 degrees move a sphere's contour points 1.5% of its radius inward),
which the strict IoU counts against it and the F-measure forgives; chains that appear or vanish
from one view to the next lower both.
The low-poly set (`lowpoly_set`: icospheres, a coarse torus, boxes, a faceted head) and a
procedural bumpy torus of SYNTH_FACES faces (the time target of a large mesh), written to
temporary PLYs, are measured too.
"""
from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from ..outline3d.meshfile import SUFFIXES
from . import report

TOL = 0.015              # of the image size: how far ink may lie from the line it draws
VIEWS = 8
ORBIT_VIEWS = 36
COHERENCE_PX = 2         # px each mask is widened by before the IoU
JUMP_PX = 4.0            # px widths past the surface's own slope: a jump in depth between neighbouring pixels
INK = 0.25               # coverage above which a pixel counts as ink
SYNTH_FACES = 70000


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--meshes", metavar="DIR", help="a folder of meshes to measure too (default: only the generated "
                   "low-poly set and the procedural torus)")
    p.add_argument("--size", type=int, default=1024, help="image side in px (default 1024)")
    p.add_argument("--style", default="baimiao", help="outline style (default baimiao)")
    p.add_argument("--orbit-size", type=int, default=512, help="image side of the orbit views (default 512)")
    p.add_argument("--no-synthetic", action="store_true", help="skip the 70,000-face procedural mesh")
    p.add_argument("--no-lowpoly", action="store_true", help="skip the generated low-poly meshes")
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")


def _mask_distance(mask: np.ndarray) -> np.ndarray:
    """(H, W) px from each pixel to the nearest pixel of `mask` (large where the mask is empty)."""
    import cv2

    if not mask.any():
        return np.full(mask.shape, 1e9, dtype=np.float32)
    return cv2.distanceTransform((~mask).astype(np.uint8), cv2.DIST_L2, 5)


def depth_jumps(dist: np.ndarray, area: np.ndarray, pixel: np.ndarray) -> np.ndarray:
    """(H, W) bool: pixels beside a jump in the eye distance `dist` (mesh units, over the
    covered `area`) that the surface's own slope does not explain.  Between neighbours p, q
    along a row or column, the slope on each side (p's from its other neighbour, q's from
    its) carried across the step predicts the other's distance; the step is a jump when both
    predictions miss by more than JUMP_PX times the width `pixel` of a pixel there: a sheet
    ending in front of another, however close behind it lies, and not a surface seen at a
    grazing angle, whose steps are large but steady."""
    jump = np.zeros_like(area)
    for axis in (0, 1):
        d = np.moveaxis(dist, axis, 0)
        a = np.moveaxis(area, axis, 0)
        w = np.moveaxis(pixel, axis, 0)
        step = d[2:-1] - d[1:-2]                      # between p = 1..n-3 and q = p + 1
        miss_p = np.abs(step - (d[1:-2] - d[:-3]))    # p's slope carried on to q
        miss_q = np.abs(step - (d[3:] - d[2:-1]))     # q's slope carried back to p
        both = a[:-3] & a[1:-2] & a[2:-1] & a[3:]
        big = both & (np.minimum(miss_p, miss_q) > JUMP_PX * np.minimum(w[1:-2], w[2:-1]))
        out = np.moveaxis(jump, axis, 0)
        out[1:-2] |= big
        out[2:-1] |= big
    return jump


def truth(drawing) -> tuple[np.ndarray, np.ndarray]:
    """The projected area's boundary and every true visible line, (H, W) bool each."""
    import cv2

    depth, camera = drawing.depth, drawing.camera
    area = np.isfinite(depth)
    rim = area & ~cv2.erode(area.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    dist = np.where(area, camera.eye_distance(np.where(area, depth, 0.0).astype(np.float64)), 0.0)
    lines = rim | depth_jumps(dist, area, camera.pixel_size(dist))
    canvas = np.zeros(area.shape, np.uint8)
    for c in drawing.chains:
        if c.visible and c.kind in (1, 2):                     # boundary, crease
            cv2.polylines(canvas, [np.round(c.points).astype(np.int32)], False, 1, 1)
    return rim, lines | canvas.astype(bool)


def kind_widths(drawing) -> dict:
    """The median ink width (px) along the visible chains of each kind drawn: twice the ink's
    distance to its edge at the chain's points (its centre line)."""
    import cv2

    ink = (drawing.paper.ink() > INK).astype(np.uint8)
    half = cv2.distanceTransform(ink, cv2.DIST_L2, 5)
    h, w = ink.shape
    out = {}
    for kind in sorted({c.kind for c in drawing.chains if c.visible}):
        pts = np.vstack([c.points for c in drawing.chains if c.visible and c.kind == kind])
        ix = np.clip(np.round(pts - 0.5).astype(int), 0, [w - 1, h - 1])
        out[kind] = float(2.0 * np.median(half[ix[:, 1], ix[:, 0]]))
    return out


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
    widths = kind_widths(drawing)
    crease = widths.get(2, 0.0)
    return {"recall": recall, "precision": precision, "median_chain": s["median_chain_over_diagonal"],
            "outline_over_crease": widths.get(0, 0.0) / crease if crease else float("nan"),
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


def _bevelled_box():
    """A box of sides 2 x 1.4 x 1 whose edges are rounded in a few flat bevels: a subdivided cube
    pushed onto a sphere, scaled past the box and clipped to it (flat sides, faceted corners)."""
    import trimesh

    cube = trimesh.creation.box((2.0, 2.0, 2.0)).subdivide().subdivide()
    v = cube.vertices / np.linalg.norm(cube.vertices, axis=1, keepdims=True)
    return trimesh.Trimesh(np.clip(1.25 * v, -1.0, 1.0) * [1.0, 0.7, 0.5], cube.faces)


def _faceted_head():
    """A low-poly head of a few hundred faces in the manner of Blender's monkey: a coarse
    sphere, two ears and a snout as separate shells through it, eyes of 20 faces, and one
    non-manifold edge (a face hidden inside the head on one of its edges)."""
    import trimesh

    head = trimesh.creation.uv_sphere(1.0, count=[10, 12])
    head.apply_scale([1.0, 0.95, 0.9])
    parts = [head]
    for side in (-1.0, 1.0):
        ear = trimesh.creation.icosphere(subdivisions=1, radius=1.0)
        ear.apply_scale([0.12, 0.45, 0.38])
        ear.apply_translation([side * 1.05, 0.25, -0.1])
        eye = trimesh.creation.icosphere(subdivisions=0, radius=0.22)
        eye.apply_translation([side * 0.35, 0.25, 0.86])
        parts += [ear, eye]
    snout = trimesh.creation.capsule(height=0.5, radius=0.35, count=[6, 6])
    snout.apply_scale([1.3, 0.8, 1.0])
    snout.apply_translation([0.0, -0.3, 0.7])
    parts.append(snout)
    mesh = trimesh.util.concatenate(parts)
    a, b = head.faces[0, :2]
    centre = len(mesh.vertices)
    return trimesh.Trimesh(np.vstack([mesh.vertices, [[0.0, 0.0, 0.0]]]),
                           np.vstack([mesh.faces, [[b, a, centre]]]), process=False)


def bunny_blob():
    """A smooth bunny of a few thousand faces in the manner of the Stanford bunny's pose: an
    egg of a body, a head forward and up, two long ears leaning back, a tail; each part a
    shell of its own through the body (their intersections are where lines meet)."""
    import trimesh

    body = trimesh.creation.icosphere(subdivisions=3)
    body.apply_scale([0.75, 0.7, 1.0])
    head = trimesh.creation.icosphere(subdivisions=3, radius=0.42)
    head.apply_scale([1.0, 0.9, 1.1])
    head.apply_translation([0.0, 0.55, 0.75])
    parts = [body, head]
    for side in (-1.0, 1.0):
        ear = trimesh.creation.capsule(height=0.7, radius=0.1, count=[24, 12])
        ear.apply_scale([0.45, 1.0, 1.0])                   # flat, broad seen from the front
        turn = trimesh.transformations.rotation_matrix(np.radians(-120.0), [1.0, 0.0, 0.0])    # up and back
        tilt = trimesh.transformations.rotation_matrix(np.radians(side * -15.0), [0.0, 0.0, 1.0])
        ear.apply_transform(tilt @ turn)
        ear.apply_translation([side * 0.2, 1.22, 0.48])
        parts.append(ear)
    tail = trimesh.creation.icosphere(subdivisions=2, radius=0.18)
    tail.apply_translation([0.0, 0.1, -1.0])
    return trimesh.util.concatenate(parts + [tail])


def lowpoly_set() -> dict:
    """Faceted and low-poly test meshes by name (trimesh objects): icospheres of subdivision
    0..2, a torus of few sections, a box, a bevelled box and a faceted head."""
    import trimesh

    meshes = {f"icosphere{k}": trimesh.creation.icosphere(subdivisions=k) for k in range(3)}
    meshes["torus_lowpoly"] = trimesh.creation.torus(1.0, 0.4, major_sections=12, minor_sections=6)
    meshes["box"] = trimesh.creation.box((1.0, 1.4, 0.8))
    meshes["bevelled_box"] = _bevelled_box()
    meshes["faceted_head"] = _faceted_head()
    return meshes


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
    mean = {k: float(np.nanmean([r[k] for r in rows])) if any(np.isfinite(r[k]) for r in rows) else float("nan")
            for k in rows[0]}
    phases = ("lines", "visibility", "chaining", "brush", "deposit")
    out = {"mesh": path.name, "faces": len(surface.faces), "recall": mean["recall"],
           "recall_min": min(r["recall"] for r in rows), "precision": mean["precision"],
           "precision_min": min(r["precision"] for r in rows), "median_chain": mean["median_chain"],
           "outline_over_crease": mean["outline_over_crease"],
           "chains": mean["chains"], "strokes": mean["strokes"], "load": load,
           **{p: mean[p] for p in phases}, "seconds": load + sum(mean[p] for p in phases),
           "orbit_iou": float(np.mean(iou)), "orbit_iou_min": float(np.min(iou)), "orbit_f": float(np.mean(f)),
           "orbit_f_min": float(np.min(f))}
    if progress:
        progress(f"{path.name}: recall {out['recall']:.3f} precision {out['precision']:.3f} "
                 f"{out['seconds']:.2f} s/view orbit IoU {out['orbit_iou']:.3f} F {out['orbit_f']:.3f}")
    return out


def run(args, progress=None) -> dict:
    from ..outline3d.meshfile import mesh_files

    files = mesh_files(args.meshes) if args.meshes else []
    results = [_measure(p, args, progress) for p in files]
    with tempfile.TemporaryDirectory() as tmp:
        made = {} if args.no_lowpoly else {**lowpoly_set(), "bunny_blob": bunny_blob()}
        if not args.no_synthetic:
            made[f"bumpy_torus_{SYNTH_FACES}"] = bumpy_torus()
        for name, mesh in made.items():
            path = Path(tmp) / f"{name}.ply"
            mesh.export(path)
            results.append(_measure(path, args, progress))
    return {"size": args.size, "style": args.style, "views": VIEWS, "orbit_views": ORBIT_VIEWS, "tol": TOL,
            "meshes": results}


def table(result: dict) -> str:
    cols = ["mesh", "faces", "recall", "recall_min", "precision", "precision_min", "outline_over_crease",
            "median_chain", "chains",
            "strokes", "seconds", "load", "lines", "visibility", "chaining", "brush", "deposit", "orbit_iou",
            "orbit_iou_min", "orbit_f", "orbit_f_min"]
    head = (f"3-D outlines, style {result['style']}, {result['size']} px, {result['views']} views per mesh "
            f"(means; _min: the worst view); tolerance {result['tol']:.1%} of the image; orbit of "
            f"{result['orbit_views']} views; seconds per view, load once per mesh\n")
    return head + report.markdown_table(result["meshes"], cols)


def handle(args: argparse.Namespace) -> int:
    from .report import progress, run_benchmark

    return run_benchmark("outline", args, lambda: run(args, progress=progress), table)
