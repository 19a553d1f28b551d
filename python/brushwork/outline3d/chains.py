"""Segments linked into long chains, split where they pass out of sight, cleaned and smoothed.

Linking walks the graph whose nodes are the lines' points: through a node where a line of one
kind simply continues, and at a junction on along the segment that turns least (direction
continuity, in the image), ending when every way on turns more than MAX_TURN_DEG; a line that
simply continues (a node of two segments: a polygon's corner) is followed round turns up to
CORNER_TURN_DEG.  Each chain
is then resampled about once per pixel, its samples tested for visibility, and cut into runs of
one visibility (a closed chain restarted where its visibility changes); pieces whose ends meet
again, running on in one direction, are joined; runs shorter than a fraction of the image
diagonal are dropped, the rest smoothed with their ends held.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

MAX_TURN_DEG = 60.0    # a junction is passed straight on only when the way on turns less
CORNER_TURN_DEG = 135.0  # a line of one kind runs on round a corner that turns less
SAMPLE_PX = 1.0        # spacing of the samples along a chain
GAP_PX = 3.0           # visibility changes shorter than this along a chain are ignored
JOIN_PX = 2.5          # chain ends closer than this may be joined into one chain


@dataclass
class Chain:
    """One drawable line: points (k, 2) px (x right, y down), depth (k,) p2/p3, its kind code,
    whether the viewer sees it, and whether it closes on itself."""
    points: np.ndarray
    depth: np.ndarray
    kind: int
    visible: bool = True
    closed: bool = False

    @property
    def length(self) -> float:
        return float(np.sum(np.linalg.norm(np.diff(self.points, axis=0), axis=1)))


def _incidence(segments: np.ndarray, n_points: int) -> tuple[np.ndarray, np.ndarray]:
    """CSR lists of the segments at each point: segments of point p are order[start[p]:start[p+1]]."""
    ends = segments.reshape(-1)
    order = np.argsort(ends, kind="stable") // 2
    start = np.concatenate([[0], np.cumsum(np.bincount(ends, minlength=n_points))])
    return order, start


def _turn(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> float:
    """The turn in degrees at b of the path a -> b -> c (0 where a direction is undefined)."""
    u, v = b - a, c - b
    nu, nv = np.hypot(*u), np.hypot(*v)
    if nu == 0 or nv == 0:
        return 0.0
    return math.degrees(math.acos(max(-1.0, min(1.0, float(u @ v) / (nu * nv)))))


def link(xy: np.ndarray, segments: np.ndarray, kinds: np.ndarray) -> list[tuple[list[int], int]]:
    """Chains of point indices over the segments (S, 2), each of one kind: (nodes, kind)."""
    if len(segments) == 0:
        return []
    order, start = _incidence(segments, len(xy))
    degree = np.diff(start)
    used = np.zeros(len(segments), dtype=bool)
    seg_list = segments.tolist()
    kind_list = kinds.tolist()

    def walk(node: int, seg: int) -> list[int]:
        nodes = [node]
        while True:
            used[seg] = True
            a, b = seg_list[seg]
            prev, node = node, (b if a == node else a)
            nodes.append(node)
            best, best_turn = -1, CORNER_TURN_DEG if degree[node] == 2 else MAX_TURN_DEG
            for s in order[start[node]:start[node + 1]]:
                if used[s] or kind_list[s] != kind_list[seg]:
                    continue
                other = seg_list[s][1] if seg_list[s][0] == node else seg_list[s][0]
                t = _turn(xy[prev], xy[node], xy[other])
                if t <= best_turn:
                    best, best_turn = s, t
            if best < 0:
                return nodes
            seg = best

    chains = []
    # ends and junctions first, so that open chains start at an end; what is left are loops
    for node in np.concatenate([np.flatnonzero(degree != 2), np.flatnonzero(degree == 2)]):
        for s in order[start[node]:start[node + 1]]:
            if not used[s]:
                chains.append((walk(int(node), int(s)), kind_list[s]))
    return chains


def resample(points: np.ndarray, values: np.ndarray, spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """A polyline (k, 2) with (k,) values resampled every `spacing` along its length."""
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    n = max(2, int(math.ceil(s[-1] / spacing)) + 1)
    ss = np.linspace(0.0, s[-1], n)
    return np.stack([np.interp(ss, s, points[:, 0]), np.interp(ss, s, points[:, 1])], axis=1), np.interp(ss, s, values)


def _runs(flags: np.ndarray) -> list[tuple[int, int, bool]]:
    """Maximal runs [i, j) of equal flags: (i, j, flag)."""
    cuts = np.flatnonzero(np.diff(flags.astype(np.int8))) + 1
    bounds = np.concatenate([[0], cuts, [len(flags)]])
    return [(int(i), int(j), bool(flags[i])) for i, j in zip(bounds[:-1], bounds[1:])]


def steady(flags: np.ndarray, gap: int) -> np.ndarray:
    """`flags` with inner runs shorter than `gap` samples flipped to their neighbours' value
    (the depth test's flicker at a pixel's edge)."""
    out = flags.copy()
    runs = _runs(flags)
    for k, (i, j, f) in enumerate(runs):
        if 0 < k < len(runs) - 1 and j - i < gap:
            out[i:j] = not f
    return out


def smooth(points: np.ndarray, passes: int, closed: bool = False) -> np.ndarray:
    """Laplacian smoothing (each point toward its neighbours' mean, half way) `passes` times;
    an open polyline keeps its two ends."""
    p = points.copy()
    for _ in range(passes):
        if closed:
            p = 0.5 * p + 0.25 * (np.roll(p, 1, axis=0) + np.roll(p, -1, axis=0))
        elif len(p) > 2:
            p[1:-1] = 0.5 * p[1:-1] + 0.25 * (p[:-2] + p[2:])
    return p


def _start_at_a_change(pts: np.ndarray, depth: np.ndarray, flags: np.ndarray):
    """A closed chain (first sample = last) restarted where its visibility changes, so that the
    run through its seam stays one piece; unchanged when it is of one visibility."""
    runs = _runs(flags)
    if len(runs) < 2 or flags[0] != flags[-1]:
        return pts, depth, flags
    cut = runs[0][1]
    order = np.concatenate([np.arange(cut, len(pts)), np.arange(1, cut + 1)])
    return pts[order], depth[order], flags[order]


def _end(c: Chain, e: int) -> tuple[np.ndarray, np.ndarray]:
    """End e (0: start, 1: finish) of a chain: its point and the unit direction leaving it."""
    pts = c.points if e == 1 else c.points[::-1]
    k = min(len(pts) - 1, 5)
    d = pts[-1] - pts[-1 - k]
    return pts[-1], d / max(float(np.hypot(*d)), 1e-12)


def _flipped(c: Chain) -> Chain:
    return Chain(c.points[::-1].copy(), c.depth[::-1].copy(), c.kind, c.visible, c.closed)


def _end_grid(pieces: list[Chain]) -> tuple[list, dict]:
    """Each chain end's (point, outward unit direction), end 2 i + e of chain i, and the open
    chains' ends binned in cells of JOIN_PX."""
    grid: dict = {}
    ends = []
    for i, c in enumerate(pieces):
        for e in (0, 1):
            p, d = _end(c, e)
            ends.append((p, d))
            if not c.closed:
                grid.setdefault((int(p[0] // JOIN_PX), int(p[1] // JOIN_PX)), []).append(2 * i + e)
    return ends, grid


def _end_pairs(pieces: list[Chain]) -> list[tuple[float, int, int]]:
    """(distance, end, end) of ends within JOIN_PX of each other, of two chains of one kind and
    visibility, the one running on from the other within MAX_TURN_DEG."""
    ends, grid = _end_grid(pieces)
    cos_max = math.cos(math.radians(MAX_TURN_DEG))

    def fits(e: int, f: int) -> bool:
        a, b = pieces[e // 2], pieces[f // 2]
        # leaving a at end e, the way on enters b at end f against b's own outward direction
        return (f > e and e // 2 != f // 2 and a.kind == b.kind and a.visible == b.visible
                and float(ends[e][1] @ -ends[f][1]) >= cos_max)

    pairs = []
    for (cx, cy), members in grid.items():
        near = [f for dx in (-1, 0, 1) for dy in (-1, 0, 1) for f in grid.get((cx + dx, cy + dy), ())]
        for e, f in ((e, f) for e in members for f in near if fits(e, f)):
            dist = float(np.hypot(*(ends[e][0] - ends[f][0])))
            if dist <= JOIN_PX:
                pairs.append((dist, e, f))
    return sorted(pairs)


def _walk(pieces: list[Chain], partner: dict, e: int, seen: list) -> Chain:
    """The pieces joined from end e on through their partners, as one chain."""
    parts = []
    while True:
        seen[e // 2] = True
        c = pieces[e // 2]
        parts.append(c if e % 2 == 0 else _flipped(c))
        nxt = partner.get(e ^ 1)
        if nxt is None or seen[nxt // 2]:
            break
        e = nxt
    if len(parts) == 1:
        return parts[0]
    return Chain(np.vstack([parts[0].points] + [q.points[1:] for q in parts[1:]]),
                 np.concatenate([parts[0].depth] + [q.depth[1:] for q in parts[1:]]), parts[0].kind, parts[0].visible)


def join(pieces: list[Chain]) -> list[Chain]:
    """Chains whose ends meet (within JOIN_PX, the direction running on) joined into one: a
    contour cut where a junction or its own seam broke it runs on as one stroke.  Each end
    takes its nearest partner; the partnered pieces are then walked end to end."""
    partner: dict = {}
    for _, e, f in _end_pairs(pieces):
        if e not in partner and f not in partner:
            partner[e], partner[f] = f, e
    seen = [False] * len(pieces)
    out = []
    # pieces with a free end first (entered there), then what is left (rings of pieces)
    free = [2 * i if 2 * i not in partner else 2 * i + 1 for i in range(len(pieces))
            if 2 * i not in partner or 2 * i + 1 not in partner]
    for e in free + [2 * i for i in range(len(pieces))]:
        if not seen[e // 2]:
            out.append(_walk(pieces, partner, e, seen))
    return out


def build(lines, camera, is_visible, min_length_px: float, smooth_passes: int) -> list[Chain]:
    """Chains of `lines` as the camera sees them: linked, sampled, split by `is_visible`
    ((k, 3) samples -> (k,) bool), joined where split ends meet again, runs shorter than
    min_length_px dropped, smoothed."""
    proj = camera.project(lines.points)
    pieces: list[Chain] = []
    for nodes, kind in link(proj[:, :2], lines.segments, lines.kinds):
        pts, depth = resample(proj[nodes, :2], proj[nodes, 2], SAMPLE_PX)
        flags = steady(is_visible(np.column_stack([pts, depth])), int(GAP_PX / SAMPLE_PX) + 1)
        loop = nodes[0] == nodes[-1] and len(nodes) > 3
        if loop:
            pts, depth, flags = _start_at_a_change(pts, depth, flags)
        whole = len(_runs(flags)) == 1
        pieces += [Chain(pts[i:j], depth[i:j], kind, vis, loop and whole) for i, j, vis in _runs(flags) if j - i >= 2]
    out = [c for c in join(pieces) if c.length >= min_length_px]
    for c in out:
        c.points = smooth(c.points, smooth_passes, c.closed)
    return out
