"""SVG path data (the `d` attribute) to polylines: M L H V C S Q T Z, absolute and relative."""
from __future__ import annotations

import math
import re

import numpy as np

from .model import GlyphError

_TOKEN = re.compile(r"([MmLlHhVvCcSsQqTtZzAa])|([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)|([\s,]+)")
_ARITY = {"M": 2, "L": 2, "H": 1, "V": 1, "C": 6, "S": 4, "Q": 4, "T": 2, "Z": 0}
FLATNESS = 1e-3  # largest chord-to-curve distance when flattening, as a fraction of the path's extent


def _tokens(d: str):
    """[(command letter or None, number or None)] ; GlyphError at the first character that fits no token."""
    out, pos = [], 0
    while pos < len(d):
        m = _TOKEN.match(d, pos)
        if m is None or m.end() == pos:
            raise GlyphError("svg path", f"unexpected character {d[pos]!r} at offset {pos}")
        if m.group(1):
            out.append((m.group(1), None))
        elif m.group(2):
            out.append((None, float(m.group(2))))
        pos = m.end()
    return out


def _segments(d: str):
    """Subpaths as lists of absolute segments: ("L", p0, p1), ("Q", p0, c, p1), ("C", p0, c1, c2, p1)."""
    toks = _tokens(d)
    if toks and toks[0][0] not in ("M", "m"):
        raise GlyphError("svg path", "must start with M or m")
    subpaths, cur, start = [], np.zeros(2), np.zeros(2)
    last_ctrl, last_cmd = None, None   # reflected control point for S / T
    i = 0
    while i < len(toks):
        cmd = toks[i][0]
        if cmd is None:
            raise GlyphError("svg path", f"number {toks[i][1]:g} without a command")
        if cmd in "Aa":
            raise GlyphError("svg path", "arc commands (A, a) are not supported")
        i += 1
        up, rel = cmd.upper(), cmd.islower()
        n = _ARITY[up]
        args = []
        while i < len(toks) and toks[i][0] is None:
            args.append(toks[i][1])
            i += 1
        if up == "Z":
            if args:
                raise GlyphError("svg path", f"{cmd} takes no numbers, got {len(args)}")
            if subpaths and subpaths[-1] and np.any(cur != start):
                subpaths[-1].append(("L", cur.copy(), start.copy()))
            cur, last_ctrl, last_cmd = start.copy(), None, "Z"
            subpaths.append(None)  # marks "closed": a following command starts a new subpath at start
            continue
        if not args or len(args) % n:
            raise GlyphError("svg path", f"{cmd} needs a multiple of {n} numbers, got {len(args)}")
        for j in range(0, len(args), n):
            a = np.array(args[j:j + n])
            if up == "M" and j == 0:
                cur = cur + a if rel else a
                start = cur.copy()
                subpaths.append([])
                subpaths[-1].append(("M", cur.copy()))
                last_ctrl, last_cmd = None, "M"
                continue
            if subpaths and subpaths[-1] is None:  # drawing on after Z: a new subpath at the old start
                subpaths.append([("M", cur.copy())])
            seg_cmd = "L" if up == "M" else up
            base = cur if rel else np.zeros(2)
            if seg_cmd == "H":
                p1 = np.array([cur[0] + a[0] if rel else a[0], cur[1]])
                seg = ("L", cur.copy(), p1)
            elif seg_cmd == "V":
                p1 = np.array([cur[0], cur[1] + a[0] if rel else a[0]])
                seg = ("L", cur.copy(), p1)
            elif seg_cmd == "L":
                seg = ("L", cur.copy(), base + a)
            elif seg_cmd == "Q":
                seg = ("Q", cur.copy(), base + a[0:2], base + a[2:4])
            elif seg_cmd == "T":
                c = 2 * cur - last_ctrl if last_cmd in ("Q", "T") else cur.copy()
                seg = ("Q", cur.copy(), c, base + a)
            elif seg_cmd == "C":
                seg = ("C", cur.copy(), base + a[0:2], base + a[2:4], base + a[4:6])
            else:  # S
                c1 = 2 * cur - last_ctrl if last_cmd in ("C", "S") else cur.copy()
                seg = ("C", cur.copy(), c1, base + a[0:2], base + a[2:4])
            subpaths[-1].append(seg)
            cur = seg[-1].copy()
            last_ctrl = seg[-2] if seg[0] in ("Q", "C") else None
            last_cmd = seg_cmd
    return [sp for sp in subpaths if sp]


def _flatten(seg, tol: float) -> np.ndarray:
    """Points after the segment's start, (n, 2): a Bezier split into n chords within tol of the curve."""
    if seg[0] == "L":
        return seg[2][None, :]
    p = np.array(seg[1:])
    if seg[0] == "Q":   # |B''| = 2 |p0 - 2 p1 + p2|; chord error <= |B''| / (8 n^2)
        dd = 2 * np.linalg.norm(p[0] - 2 * p[1] + p[2])
    else:               # |B''| <= 6 max |second differences of the control points|
        dd = 6 * max(np.linalg.norm(p[0] - 2 * p[1] + p[2]), np.linalg.norm(p[1] - 2 * p[2] + p[3]))
    n = min(256, max(1, math.ceil(math.sqrt(dd / (8 * tol)))))
    t = np.linspace(0, 1, n + 1)[1:, None]
    s = 1 - t
    if seg[0] == "Q":
        return s * s * p[0] + 2 * s * t * p[1] + t * t * p[2]
    return s ** 3 * p[0] + 3 * s * s * t * p[1] + 3 * s * t * t * p[2] + t ** 3 * p[3]


def parse_svg_path(d: str) -> list[np.ndarray]:
    """SVG path data -> one (k, 2) float64 polyline per subpath, in the path's own units.

    Curves (C S Q T) are flattened to within FLATNESS of the path's extent; Z closes a subpath by
    repeating its first point. Malformed data raises GlyphError ("svg path: PROBLEM").
    """
    if not isinstance(d, str):
        raise GlyphError("svg path", f"expected a string, got {type(d).__name__}")
    subpaths = _segments(d)
    allpts = np.array([p for sp in subpaths for seg in sp for p in seg[1:]]).reshape(-1, 2)
    if not np.all(np.isfinite(allpts)):
        raise GlyphError("svg path", "a coordinate is not finite")
    extent = float(np.ptp(allpts, axis=0).max()) if len(allpts) else 0.0
    tol = max(extent, 1e-12) * FLATNESS
    out = []
    for sp in subpaths:
        pts = [sp[0][1][None, :]] + [_flatten(seg, tol) for seg in sp[1:]]
        out.append(np.concatenate(pts, axis=0))
    return out
