"""Which parts of the feature lines the viewer sees: a depth buffer of the mesh rendered through
the project's EGL context (`_core.render_depth`), and each line sample tested against it.

A sample at distance d from the eye (along the view axis) is visible when some pixel of the
3 x 3 block around it holds a surface no nearer than d - tol: a contour lies where the surface
turns away, so the pixels beside it show the surface behind it or the background.  tol is
TOL_PX pixels' width at that depth plus TOL_RADIUS of the mesh's radius, so the test scales
with the view and not with the mesh's units.
"""
from __future__ import annotations

import numpy as np

from .. import _core

TOL_PX = 2.0          # pixels' width at the sample's depth
TOL_RADIUS = 0.004    # of the bounding sphere's radius
FAR = np.inf          # stands for "no surface" in the distance image


def depth_image(surface, camera) -> np.ndarray:
    """(H, W) float32 depth p2/p3 of the nearest surface per pixel, +inf where none."""
    w, h = camera.size
    return _core.render_depth(np.ascontiguousarray(surface.vertices, dtype=np.float64),
                              np.ascontiguousarray(surface.faces, dtype=np.int64), camera.matrix, w, h)


def farthest_near(depth: np.ndarray, camera) -> np.ndarray:
    """(H, W) float64 the largest eye distance over each pixel's 3 x 3 block (FAR for background)."""
    import cv2

    covered = np.isfinite(depth)
    dist = np.where(covered, camera.eye_distance(np.where(covered, depth, 0.0).astype(np.float64)), FAR)
    return cv2.dilate(dist, np.ones((3, 3), np.uint8))       # float64: mesh units of any size


def visible(samples: np.ndarray, block_far: np.ndarray, camera, radius: float) -> np.ndarray:
    """(k,) bool for (k, 3) samples (pixel x, pixel y, depth p2/p3) against `farthest_near`."""
    h, w = block_far.shape
    ix = np.clip(np.floor(samples[:, 0]).astype(np.int64), 0, w - 1)
    iy = np.clip(np.floor(samples[:, 1]).astype(np.int64), 0, h - 1)
    d = camera.eye_distance(samples[:, 2])
    tol = TOL_PX * camera.pixel_size(d) + TOL_RADIUS * radius
    inside = (samples[:, 0] >= 0) & (samples[:, 0] < w) & (samples[:, 1] >= 0) & (samples[:, 1] < h)
    return inside & (d <= block_far[iy, ix] + tol)
