"""The edge of the ink as closed polylines: the 0.5 iso-line of the ink's coverage, found by
OpenCV's contour follower on a bilinearly upsampled image, in image pixels (x right, y down,
pixel k spanning [k, k+1]), outer edges with a positive shoelace area, holes negative: in font
coordinates (y up) outer edges run clockwise, as TrueType wants."""
from __future__ import annotations

import numpy as np

UPSAMPLE = 4           # sub-pixels per image pixel along each axis the contour follower sees
MIN_AREA_PX = 1.0      # px^2: specks of ink (or pinholes) traced smaller than a pixel are dropped
SMOOTH_PX = 1.0        # px: the widest Gaussian smoothing along a contour (takes out the steps and finest facets)
SPACING_PX = 0.5       # px between the points of a traced contour


def ink_coverage(rgb: np.ndarray) -> np.ndarray:
    """(H, W) float32 in [0, 1]: how dark each pixel of an ink-on-white image (H, W, 3) uint8 or
    uint16 is (1 - its mean channel value)."""
    top = 65535.0 if rgb.dtype == np.uint16 else 255.0
    return 1.0 - rgb[..., :3].astype(np.float32).mean(axis=2) / np.float32(top)


def ink_mask(cov: np.ndarray) -> np.ndarray:
    """(H, W) bool: the pixels that are ink, coverage at least one half."""
    return cov >= 0.5


def _signed_area(p: np.ndarray) -> float:
    """Shoelace area of the closed polyline p (n, 2): positive when it turns x towards y."""
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _smooth_closed(p: np.ndarray, sigma: float) -> np.ndarray:
    """p (n, 2) smoothed along the closed polyline by a Gaussian of `sigma` points."""
    if sigma <= 0 or len(p) < 8:
        return p
    r = int(3 * sigma)
    k = np.exp(-0.5 * (np.arange(-r, r + 1) / sigma) ** 2)
    k /= k.sum()
    wrapped = np.concatenate([p[-r:], p, p[:r]])
    return np.stack([np.convolve(wrapped[:, i], k, mode="valid") for i in range(2)], axis=1)


def arc(p: np.ndarray, n: int) -> np.ndarray:
    """The open polyline p resampled at n points evenly along its length, ends kept."""
    d = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
    s = np.linspace(0.0, d[-1], n)
    return np.stack([np.interp(s, d, p[:, 0]), np.interp(s, d, p[:, 1])], axis=1)


def resample_closed(p: np.ndarray, spacing: float) -> np.ndarray:
    """The closed polyline p (n, 2) resampled at even steps of about `spacing` along its length."""
    ring = np.concatenate([p, p[:1]])
    d = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(ring, axis=0).T))])
    n = max(int(round(d[-1] / spacing)), 3)
    s = np.linspace(0.0, d[-1], n, endpoint=False)
    return np.stack([np.interp(s, d, ring[:, 0]), np.interp(s, d, ring[:, 1])], axis=1)


def _away_from_ink(p: np.ndarray) -> np.ndarray:
    """(n, 2) unit normals of the closed polyline p pointing out of the ink: (t_y, -t_x) for the
    tangent t, outwards of a positive-area outer edge and into a negative-area hole."""
    t = np.roll(p, -1, axis=0) - np.roll(p, 1, axis=0)
    t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-12)
    return np.stack([t[:, 1], -t[:, 0]], axis=1)


def trace(cov: np.ndarray, smooth_px: float = SMOOTH_PX, upsample: int = UPSAMPLE) -> list:
    """The ink's edge in cov (H, W coverage): a list of closed polylines (n, 2) in px, points
    SPACING_PX apart, x right,
    y down, outer edges with a positive shoelace area and holes with a negative one; each smoothed
    along its length by a Gaussian of smooth_px, then those enclosing under MIN_AREA_PX dropped."""
    import cv2

    h, w = cov.shape
    big = cv2.resize(np.pad(cov, 1).astype(np.float32), ((w + 2) * upsample, (h + 2) * upsample),
                     interpolation=cv2.INTER_LINEAR)
    mask = (big >= 0.5).astype(np.uint8)
    found, hierarchy = cv2.findContours(mask, cv2.RETR_CCOMP, cv2.CHAIN_APPROX_NONE)
    out = []
    for k, c in enumerate(found):
        # sub-pixel centre i lies at image coordinate (i + 0.5) / upsample, less the padding
        p = (c[:, 0, :].astype(np.float64) + 0.5) / upsample - 1.0
        if len(p) < 3:
            continue
        hole = hierarchy[0][k][3] >= 0
        if (_signed_area(p) > 0) == hole:
            p = p[::-1]
        p = _smooth_closed(p, smooth_px * upsample)
        # the follower walks the centres of the edge's ink sub-pixels: the edge is half a sub-pixel out
        p = p + _away_from_ink(p) * (0.5 / upsample)
        if abs(_signed_area(p)) >= MIN_AREA_PX:
            out.append(resample_closed(p, SPACING_PX))
    return out
