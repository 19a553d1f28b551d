"""Work-precision benchmark: a frame's errors against the reference (skeleton, footprint, scaled KKT residual) and the
Newton polish of a reference frame."""
from __future__ import annotations

import math
from typing import Optional

import numpy as np

from ...brush import Brush


def skeleton_error(a: np.ndarray, b: np.ndarray) -> float:
    """Largest distance between corresponding spine nodes of two (n+1, 3) skeletons, mm."""
    return float(np.max(np.linalg.norm(np.asarray(a) - np.asarray(b), axis=1)))


def _signed_area(p: np.ndarray) -> float:
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _shapely_region(loops):
    # outer loops counter-clockwise, holes clockwise (Brush.footprint's convention)
    from shapely.geometry import Polygon
    from shapely.ops import unary_union

    outers = [Polygon(p).buffer(0) for p in loops if len(p) >= 3 and _signed_area(p) > 0]
    holes = [Polygon(p).buffer(0) for p in loops if len(p) >= 3 and _signed_area(p) < 0]
    region = unary_union(outers) if outers else Polygon()
    return region.difference(unary_union(holes)) if holes else region


RASTER_PX = 400       # the raster backend's grid: RASTER_PX x RASTER_PX cells over both footprints' bounds
_SUBPIXEL_BITS = 8    # cv2.fillPoly's fixed-point fraction bits for the vertices


def _raster_region(loops, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """(RASTER_PX, RASTER_PX) bool: the even-odd fill of every loop (mm) on a grid spanning lo..hi
    (mm): each loop toggles its cells, so holes return to empty."""
    import cv2

    scale = (RASTER_PX - 1) / np.maximum(hi - lo, 1e-12) * (1 << _SUBPIXEL_BITS)
    inside = np.zeros((RASTER_PX, RASTER_PX), dtype=np.uint8)
    for p in loops:
        if len(p) >= 3:
            mask = np.zeros_like(inside)
            px = np.round((np.asarray(p) - lo) * scale).astype(np.int32)
            cv2.fillPoly(mask, [px], 1, lineType=cv2.LINE_8, shift=_SUBPIXEL_BITS)
            inside ^= mask
    return inside.astype(bool)


def footprint_backend() -> str:
    """"shapely" when it is installed, else "raster" (cv2.fillPoly on a RASTER_PX x RASTER_PX grid)."""
    try:
        import shapely  # noqa: F401
        return "shapely"
    except ImportError:
        return "raster"


def footprint_error(a, b, backend: Optional[str] = None) -> float:
    """1 - IoU of two footprints (lists of (k, 2) polygons in mm); 0 when both are empty."""
    a = [np.asarray(p, float) for p in a]
    b = [np.asarray(p, float) for p in b]
    if not any(len(p) >= 3 for p in a) and not any(len(p) >= 3 for p in b):
        return 0.0
    if (backend or footprint_backend()) == "shapely":
        ra, rb = _shapely_region(a), _shapely_region(b)
        union = ra.union(rb).area
        return 0.0 if union <= 0.0 else 1.0 - ra.intersection(rb).area / union
    pts = np.vstack([p for p in a + b if len(p)])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    ia, ib = _raster_region(a, lo, hi), _raster_region(b, lo, hi)
    union = np.count_nonzero(ia | ib)
    return 0.0 if union == 0 else 1.0 - np.count_nonzero(ia & ib) / union


def kkt_residual(brush: Brush, z: np.ndarray, lam: np.ndarray) -> float:
    """The core's scaled KKT residual (sqp.cpp Brush::kkt) of the prepared frame problem at
    (z, lam): max(|grad f - J^T lam|_inf / kappa_root, max(-g) / L, max|lam_i g_i| / kappa_root)."""
    m = brush.model
    grad = brush.energy_gradient(z)
    g = brush.constraints(z)
    stat = grad - brush.constraint_jacobian(z).T @ lam if len(g) else grad
    feas = max(0.0, float(np.max(-g))) if len(g) else 0.0
    comp = float(np.max(np.abs(lam * g))) if len(g) else 0.0
    r = max(float(np.max(np.abs(stat))) / m.bend_stiffness, feas / m.tuft_length,
            comp / m.bend_stiffness)
    return r if math.isfinite(r) else math.inf


def peer_kkt(brush: Brush, z: np.ndarray) -> float:
    """kkt_residual at a point z that came without multipliers: lam from least squares on the
    constraints within 1e-6 L of the paper, clipped at 0 (the best stationarity they allow)."""
    g = brush.constraints(z)
    lam = np.zeros(len(g))
    act = np.flatnonzero(g < 1e-6 * brush.model.tuft_length)
    if len(act):
        J = brush.constraint_jacobian(z)[act]
        lam[act] = np.maximum(np.linalg.lstsq(J.T, brush.energy_gradient(z), rcond=None)[0], 0.0)
    return kkt_residual(brush, z, lam)


def polish(brush: Brush, z: np.ndarray, lam: np.ndarray, target: float = 1e-12,
           max_iter: int = 20) -> tuple[np.ndarray, np.ndarray, float]:
    """Newton's method on the KKT system of the prepared frame problem from (z, lam): active
    set A = {lam_i > 0 or g_i ~ 0}, Hessian of the Lagrangian f - lam_A^T g_A by central
    differences of the analytic gradients (step 1e-6), steps from the (least-squares) solution of
        [ H    -J_A^T ] [dz  ]     [ grad f - J_A^T lam_A ]
        [ J_A   0     ] [dlam] = - [ g_A                  ],
    multipliers kept >= 0.  Returns the best (z, lam, kkt_residual) seen, the start included."""
    model = brush.model
    z, lam = np.array(z, float), np.array(lam, float)
    best = (z.copy(), lam.copy(), kkt_residual(brush, z, lam))
    n, h = len(z), 1e-6
    for _ in range(max_iter):
        if best[2] <= target:
            break
        g = brush.constraints(z)
        act = np.flatnonzero((lam > 0.0) | (g < 1e-9 * model.tuft_length)) if len(g) else np.zeros(0, int)

        def grad_l(x):
            gl = brush.energy_gradient(x)
            return gl - brush.constraint_jacobian(x)[act].T @ lam[act] if len(act) else gl

        H = np.empty((n, n))
        for j in range(n):
            e = np.zeros(n)
            e[j] = h
            H[:, j] = (grad_l(z + e) - grad_l(z - e)) / (2.0 * h)
        H = 0.5 * (H + H.T)
        Ja = brush.constraint_jacobian(z)[act] if len(act) else np.zeros((0, n))
        k = len(act)
        K = np.block([[H, -Ja.T], [Ja, np.zeros((k, k))]])
        rhs = -np.concatenate([grad_l(z), g[act] if k else np.zeros(0)])
        d = np.linalg.lstsq(K, rhs, rcond=1e-14)[0]
        if not np.all(np.isfinite(d)):
            break
        z = z + d[:n]
        lam = lam.copy()
        lam[act] = np.maximum(lam[act] + d[n:], 0.0)
        r = kkt_residual(brush, z, lam)
        if r < best[2]:
            best = (z.copy(), lam.copy(), r)
    return best
