"""SVG path data (the `d` attribute) to polylines: M L H V C S Q T Z, absolute and relative."""
from __future__ import annotations

import math
import re

import numpy as np

from .model import MAX_COORD, GlyphError

_TOKEN = re.compile(r"([MmLlHhVvCcSsQqTtZzAa])|([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)|([\s,]+)")
_ARITY = {"M": 2, "L": 2, "H": 1, "V": 1, "C": 6, "S": 4, "Q": 4, "T": 2, "Z": 0}
FLATNESS = 1e-3  # largest chord-to-curve distance when flattening, as a fraction of the path's extent
MAX_CHARS = 200_000       # characters of path data
MAX_FLAT_POINTS = 100_000  # points of all subpaths after flattening


def _number(text: str, pos: int) -> float:
    v = float(text)
    if not -MAX_COORD <= v <= MAX_COORD:
        raise GlyphError("svg path", f"number {text[:20]} at offset {pos}: beyond the limit of +-{MAX_COORD:g}")
    return v


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
            out.append((None, _number(m.group(2), pos)))
        pos = m.end()
    return out


def _commands(toks):
    """(command letter, [numbers]) per command of the token list; GlyphError for a stray number,
    an arc or a wrong count of numbers."""
    if toks and toks[0][0] not in ("M", "m"):
        raise GlyphError("svg path", "must start with M or m")
    i = 0
    while i < len(toks):
        cmd = toks[i][0]
        if cmd is None:
            raise GlyphError("svg path", f"number {toks[i][1]:g} without a command")
        if cmd in "Aa":
            raise GlyphError("svg path", "arc commands (A, a) are not supported")
        i += 1
        args = []
        while i < len(toks) and toks[i][0] is None:
            args.append(toks[i][1])
            i += 1
        n = _ARITY[cmd.upper()]
        if n == 0 and args:
            raise GlyphError("svg path", f"{cmd} takes no numbers, got {len(args)}")
        if n and (not args or len(args) % n):
            raise GlyphError("svg path", f"{cmd} needs a multiple of {n} numbers, got {len(args)}")
        yield cmd, args


class _Pen:
    """The state of a path being read: current point, subpath start, the last control point and
    command (for the reflections of S and T), and the subpaths made so far."""

    def __init__(self):
        self.cur, self.start = np.zeros(2), np.zeros(2)
        self.last_ctrl, self.last_cmd = None, None
        self.subpaths: list = []

    def close(self) -> None:
        if self.subpaths and self.subpaths[-1] and np.any(self.cur != self.start):
            self.subpaths[-1].append(("L", self.cur.copy(), self.start.copy()))
        self.cur, self.last_ctrl, self.last_cmd = self.start.copy(), None, "Z"
        self.subpaths.append(None)  # marks "closed": a following command starts a new subpath at start

    def move(self, a: np.ndarray, rel: bool) -> None:
        self.cur = self.cur + a if rel else a
        self.start = self.cur.copy()
        self.subpaths.append([("M", self.cur.copy())])
        self.last_ctrl, self.last_cmd = None, "M"

    def _reflected(self, kinds: tuple) -> np.ndarray:
        return 2 * self.cur - self.last_ctrl if self.last_cmd in kinds else self.cur.copy()

    def segment(self, cmd: str, a: np.ndarray, rel: bool) -> tuple:
        """The absolute segment of one command's numbers `a`: ("L", p0, p1), ("Q", p0, c, p1)
        or ("C", p0, c1, c2, p1)."""
        cur, base = self.cur.copy(), (self.cur if rel else np.zeros(2))
        if cmd == "H":
            return "L", cur, np.array([base[0] + a[0], cur[1]])
        if cmd == "V":
            return "L", cur, np.array([cur[0], base[1] + a[0]])
        if cmd == "L":
            return "L", cur, base + a
        if cmd == "Q":
            return "Q", cur, base + a[0:2], base + a[2:4]
        if cmd == "T":
            return "Q", cur, self._reflected(("Q", "T")), base + a
        if cmd == "C":
            return "C", cur, base + a[0:2], base + a[2:4], base + a[4:6]
        return "C", cur, self._reflected(("C", "S")), base + a[0:2], base + a[2:4]    # S

    def draw(self, cmd: str, a: np.ndarray, rel: bool) -> None:
        if self.subpaths and self.subpaths[-1] is None:  # drawing on after Z: a new subpath at the old start
            self.subpaths.append([("M", self.cur.copy())])
        seg = self.segment(cmd, a, rel)
        self.subpaths[-1].append(seg)
        self.cur = seg[-1].copy()
        self.last_ctrl = seg[-2] if seg[0] in ("Q", "C") else None
        self.last_cmd = cmd


def _segments(d: str):
    """Subpaths as lists of absolute segments: ("L", p0, p1), ("Q", p0, c, p1), ("C", p0, c1, c2, p1)."""
    pen = _Pen()
    for cmd, args in _commands(_tokens(d)):
        up, rel = cmd.upper(), cmd.islower()
        if up == "Z":
            pen.close()
            continue
        n = _ARITY[up]
        for j in range(0, len(args), n):
            a = np.array(args[j:j + n])
            if up == "M" and j == 0:
                pen.move(a, rel)
            else:       # numbers after an M's first pair are lines
                pen.draw("L" if up == "M" else up, a, rel)
    return [sp for sp in pen.subpaths if sp]


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
    if len(d) > MAX_CHARS:
        raise GlyphError("svg path", f"{len(d)} characters, more than {MAX_CHARS}")
    subpaths = _segments(d)
    allpts = np.array([p for sp in subpaths for seg in sp for p in seg[1:]]).reshape(-1, 2)
    if not np.all(np.isfinite(allpts)):
        raise GlyphError("svg path", "a coordinate is not finite")
    extent = float(np.ptp(allpts, axis=0).max()) if len(allpts) else 0.0
    tol = max(extent, 1e-12) * FLATNESS
    out, total = [], 0
    for sp in subpaths:
        pts = [sp[0][1][None, :]] + [_flatten(seg, tol) for seg in sp[1:]]
        out.append(np.concatenate(pts, axis=0))
        total += len(out[-1])
        if total > MAX_FLAT_POINTS:
            raise GlyphError("svg path", f"more than {MAX_FLAT_POINTS} points once its curves are flattened")
    return out
