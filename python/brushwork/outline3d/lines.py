"""Feature lines of a triangle mesh seen from a camera: occluding contours of the smooth surface,
boundaries, creases and (optionally) suggestive contours.

Contours are the zero set of g = n . v interpolated linearly over each face from the normals n
at its corners and the unit vectors v toward the eye (Bénard & Hertzmann 2019, "interpolated
contours"), on the mesh welded across texture seams, so they run smooth and unbroken across
coarse faces.  A facet edge is one whose faces part so far that a smooth curve through it would
miss the flat faces' outline by more than FACET_SAG_PX; at a vertex on one, each corner takes its
face's own normal, elsewhere a corner's normal is the mean of the faces around its vertex.  On a
faceted or low-poly surface g thus jumps across the facet edges, and where its two faces lie on
either side of the zero set the contour runs along the edge itself (the outline of the polygons,
as a flat-shaded rendering shows it).  Suggestive contours are zeros of the radial curvature,
taken as zeros of D_w g (the derivative of g along w, the view vector projected on the tangent
plane) where it rises along w, on front faces (DeCarlo et al. 2003).

Lines come out as points (P, 3) in mesh units and segments (S, 2) of point indices with a kind
per segment; segments of one kind share points where they meet (an edge's crossing, a vertex),
which is what chains them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

KINDS = ("silhouette", "boundary", "crease", "suggestive")
SILHOUETTE, BOUNDARY, CREASE, SUGGESTIVE = range(4)
MAX_COORDINATE = 1e100      # larger coordinates overflow the squares of lengths
WELD = 1e-6                 # vertices closer than this fraction of the bounding diagonal are one
SUGGESTIVE_RISE = 0.02      # D_w(D_w g) per unit of g's range over the diagonal below which a zero is dropped
SUGGESTIVE_GRAZING = 0.5    # suggestive contours only where g = n . v is below this
FACET_SAG_PX = 0.75         # px a smooth curve may bulge past the chord of a facet edge before the edge is kept
FACET_MIN_DEG = 8.0         # faces meeting at less than this are never a facet edge


class MeshError(ValueError):
    """A mesh that cannot be drawn at all (nothing left after cleaning)."""


@dataclass
class Surface:
    """A welded, cleaned triangle mesh: vertices (n, 3), faces (m, 3), unit vertex normals (n, 3)
    (area-weighted), unit face normals (m, 3), unique edges (e, 2), the edge of each face's side
    face_edges (m, 3) (side k from corner k to corner k+1), faces per edge (e,) and the two faces
    of each manifold edge edge_faces (e, 2) (-1 where the edge has not exactly two); notes: what
    cleaning did, one phrase each."""
    vertices: np.ndarray
    faces: np.ndarray
    normals: np.ndarray
    face_normals: np.ndarray
    edges: np.ndarray
    face_edges: np.ndarray
    edge_count: np.ndarray
    edge_faces: np.ndarray
    notes: list

    @property
    def diagonal(self) -> float:
        return float(np.linalg.norm(self.vertices.max(axis=0) - self.vertices.min(axis=0)))


def _weld(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Merge vertices that share a position (to WELD of the diagonal): seams split at texture
    coordinates or normals close up.  Returns the used vertices and the faces over them."""
    used = np.unique(faces)
    v = vertices[used]
    lo = v.min(axis=0)
    step = max(float(np.linalg.norm(v.max(axis=0) - lo)) * WELD, 1e-300)
    keys = np.floor((v - lo) / step + 0.5).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    remap = np.full(len(vertices), -1, dtype=np.int64)
    remap[used] = inverse.reshape(-1)
    return v[first], remap[faces]


def _clean_faces(vertices: np.ndarray, faces: np.ndarray, notes: list) -> tuple[np.ndarray, np.ndarray]:
    """Faces without a repeated corner, with a non-zero area, each once. Returns faces and their
    (m, 3) unnormalised normals (twice the area long)."""
    f = faces[(faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 2] != faces[:, 0])]
    cross = np.cross(vertices[f[:, 1]] - vertices[f[:, 0]], vertices[f[:, 2]] - vertices[f[:, 0]])
    area = np.linalg.norm(cross, axis=1)
    keep = area > 1e-12 * max(float(area.max(initial=0.0)), 1e-300)
    corners = np.sort(f[keep], axis=1)
    n = int(faces.max()) + 1
    _, once = np.unique((corners[:, 0] * n + corners[:, 1]) * n + corners[:, 2], return_index=True)
    once = np.sort(once)
    dropped = len(faces) - len(once)
    if dropped:
        notes.append(f"{dropped} degenerate or repeated face(s) dropped")
    return f[keep][once], cross[keep][once]


def _edges(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Unique edges (e, 2), face_edges (m, 3), faces per edge (e,), edge_faces (e, 2)."""
    sides = np.sort(np.stack([faces, np.roll(faces, -1, axis=1)], axis=2).reshape(-1, 2), axis=1)   # (3m, 2)
    n = int(faces.max()) + 1
    keys, inverse = np.unique(sides[:, 0] * n + sides[:, 1], return_inverse=True)   # one integer per edge
    edges = np.stack([keys // n, keys % n], axis=1)
    inverse = inverse.reshape(-1)
    count = np.bincount(inverse, minlength=len(edges))
    order = np.argsort(inverse, kind="stable")
    start = np.concatenate([[0], np.cumsum(count)[:-1]])
    edge_faces = np.full((len(edges), 2), -1, dtype=np.int64)
    two = count == 2
    edge_faces[two, 0] = order[start[two]] // 3
    edge_faces[two, 1] = order[start[two] + 1] // 3
    return edges, inverse.reshape(-1, 3), count, edge_faces


def _orient(faces: np.ndarray, face_edges: np.ndarray, edge_faces: np.ndarray) -> np.ndarray:
    """(m,) bool: the faces to turn over so that every two faces sharing a manifold edge run it
    in opposite directions (consistent winding within each connected piece; a piece that cannot
    be made consistent, a Moebius band, keeps what the walk found first)."""
    m = len(faces)
    ahead = faces < np.roll(faces, -1, axis=1)             # (m, 3): side k runs low -> high vertex
    e = np.flatnonzero(edge_faces[:, 0] >= 0)
    f, g = edge_faces[e, 0], edge_faces[e, 1]
    kf = np.argmax(face_edges[f] == e[:, None], axis=1)
    kg = np.argmax(face_edges[g] == e[:, None], axis=1)
    same = ahead[f, kf] == ahead[g, kg]                    # one direction in both: one must turn
    # CSR neighbour lists over both directions of each shared edge
    src, dst, par = np.concatenate([f, g]), np.concatenate([g, f]), np.concatenate([same, same])
    order = np.argsort(src, kind="stable")
    start = np.concatenate([[0], np.cumsum(np.bincount(src, minlength=m))]).tolist()
    dst, par = dst[order].tolist(), par[order].tolist()
    flip = [False] * m
    seen = [False] * m
    for root in range(m):
        if seen[root]:
            continue
        seen[root] = True
        stack = [root]
        while stack:
            a = stack.pop()
            for k in range(start[a], start[a + 1]):
                b = dst[k]
                if not seen[b]:
                    seen[b] = True
                    flip[b] = flip[a] ^ par[k]
                    stack.append(b)
    return np.array(flip, dtype=bool)


def _unit(a: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(a, axis=-1, keepdims=True)
    return a / np.where(n > 0, n, 1.0)


def prepare(vertices, faces) -> Surface:
    """The Surface of a raw mesh: finite vertices only, faces welded and cleaned; MeshError when
    no face is left."""
    v = np.asarray(vertices, dtype=float).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    notes: list = []
    inside = np.all((f >= 0) & (f < len(v)), axis=1)
    if not inside.all():
        notes.append(f"{int((~inside).sum())} face(s) with vertex indices outside 0..{len(v) - 1} dropped")
    f = f[inside]
    finite = np.all(np.isfinite(v), axis=1)
    if not finite.all():
        notes.append(f"{int((~finite).sum())} non-finite vertex(es) dropped with their faces")
        f = f[np.all(finite[f], axis=1)]
    if len(f) == 0:
        raise MeshError("the mesh has no faces with finite vertices")
    if np.abs(v[f]).max() > MAX_COORDINATE:
        raise MeshError(f"the mesh has coordinates beyond {MAX_COORDINATE:g}")
    v, f = _weld(v, f)
    # normals and areas from coordinates scaled to about one, whatever the mesh's units
    lo, hi = v.min(axis=0), v.max(axis=0)
    f, cross = _clean_faces((v - lo) / max(float(np.max(hi - lo)), 1e-300), f, notes)
    if len(f) == 0:
        raise MeshError("the mesh has no face of non-zero area")
    _, face_edges, _, edge_faces = _edges(f)
    flip = _orient(f, face_edges, edge_faces)
    if flip.any():
        # the smaller share is the one out of line
        flip = flip if flip.sum() <= len(f) / 2 else ~flip
        notes.append(f"{int(flip.sum())} face(s) wound against their neighbours turned over")
        f[flip] = f[flip][:, ::-1]
        cross[flip] = -cross[flip]
    normals = np.zeros_like(v)
    for k in range(3):
        np.add.at(normals, f[:, k], cross)       # area-weighted vertex normals
    edges, face_edges, count, edge_faces = _edges(f)
    if np.any(count > 2):
        notes.append(f"{int((count > 2).sum())} non-manifold edge(s)")
    return Surface(v, f, _unit(normals), _unit(cross), edges, face_edges, count, edge_faces, notes)


@dataclass
class Lines:
    """points (P, 3) mesh units; segments (S, 2) point indices; kinds (S,) codes into KINDS."""
    points: np.ndarray
    segments: np.ndarray
    kinds: np.ndarray

    @classmethod
    def empty(cls) -> "Lines":
        return cls(np.zeros((0, 3)), np.zeros((0, 2), dtype=np.int64), np.zeros(0, dtype=np.int64))

    def concat(self, other: "Lines") -> "Lines":
        off = len(self.points)
        return Lines(np.vstack([self.points, other.points]), np.vstack([self.segments, other.segments + off]),
                     np.concatenate([self.kinds, other.kinds]))


def _nonzero(values: np.ndarray) -> np.ndarray:
    return np.where(values == 0.0, 1e-12, values)          # no corner exactly on the zero set


def _side_crossings(surface: Surface, gc: np.ndarray, labels: np.ndarray, faces: np.ndarray):
    """Where the corner values gc (m, 3) change sign along the sides of `faces`: per crossing its
    key (edge, label at the edge's first vertex, label at its second), its point, and the face
    and side it lies on.  Faces whose corners share labels at both ends of an edge share its
    crossing; a facet edge has one crossing on each side."""
    f = faces[:, None].repeat(3, axis=1)
    k = np.arange(3)[None, :].repeat(len(faces), axis=0)
    sign = gc[faces] > 0
    hit = sign != np.roll(sign, -1, axis=1)                # side k: corner k -> k+1
    f, k = f[hit], k[hit]
    e = surface.face_edges[f, k]
    a = surface.faces[f, k]
    lo_first = a == surface.edges[e, 0]
    ga, gb = gc[f, k], gc[f, (k + 1) % 3]
    la, lb = labels[f, k], labels[f, (k + 1) % 3]
    g0, g1 = np.where(lo_first, ga, gb), np.where(lo_first, gb, ga)
    l0, l1 = np.where(lo_first, la, lb), np.where(lo_first, lb, la)
    t = (g0 / (g0 - g1))[:, None]
    v = surface.vertices
    points = (1.0 - t) * v[surface.edges[e, 0]] + t * v[surface.edges[e, 1]]
    return np.column_stack([np.zeros_like(e), e, l0, l1]), points, f


def _keyed(keys: np.ndarray, points: np.ndarray, pairs: np.ndarray, kind: int) -> Lines:
    """Lines from segments given as pairs of rows into `keys` (one point per distinct key)."""
    if len(pairs) == 0:
        return Lines.empty()
    used, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    seg = inverse.reshape(-1)[pairs]
    seg = seg[seg[:, 0] != seg[:, 1]]
    return Lines(points[first], seg, np.full(len(seg), kind, dtype=np.int64))


def corner_zero_set(surface: Surface, gc: np.ndarray, labels: np.ndarray, faces: np.ndarray) -> tuple:
    """The zero set of corner values gc (m, 3), linear over each face listed in `faces`: keys,
    points and (s, 2) rows pairing the two crossings of each face whose corners change sign."""
    keys, points, owner = _side_crossings(surface, _nonzero(gc), labels, faces)
    # a face's corners change sign on none or on two of its sides
    return keys, points, np.argsort(owner, kind="stable").reshape(-1, 2)


def zero_set(surface: Surface, values: np.ndarray, faces: np.ndarray, kind: int) -> Lines:
    """The zero set of (n,) per-vertex `values`, linear over each face listed in `faces` (indices):
    one segment per face whose corners change sign, between the crossings on its two changing
    sides; a crossing is one point per edge, shared by the faces on both sides."""
    f = surface.faces
    keys, points, rows = corner_zero_set(surface, values[f], f, np.asarray(faces, dtype=np.int64))
    return _keyed(keys, points, rows, kind)


def facet_edges(surface: Surface, camera) -> np.ndarray:
    """(e,) bool: the manifold edges whose faces part by an angle theta over FACET_MIN_DEG and
    along which a smooth curve would bulge past the edge by more than FACET_SAG_PX (an arc of
    angle theta over a chord of L px bulges L theta / 8)."""
    ef = surface.edge_faces
    two = ef[:, 0] >= 0
    cos = np.ones(len(ef))
    cos[two] = np.einsum("ij,ij->i", surface.face_normals[ef[two, 0]], surface.face_normals[ef[two, 1]])
    theta = np.arccos(np.clip(cos, -1.0, 1.0))
    a, b = surface.vertices[surface.edges[:, 0]], surface.vertices[surface.edges[:, 1]]
    pixel = camera.pixel_size(np.abs(camera.distance(0.5 * (a + b))))
    length_px = np.linalg.norm(a - b, axis=1) / np.maximum(pixel, 1e-300)
    return two & (theta > math.radians(FACET_MIN_DEG)) & (length_px * theta / 8.0 > FACET_SAG_PX)


def _corner_ids(surface: Surface, faces: np.ndarray, vertex: np.ndarray) -> np.ndarray:
    """3 f + k of the corner of each face f at `vertex`."""
    return 3 * faces + np.argmax(surface.faces[faces] == vertex[:, None], axis=1)


def corner_labels(surface: Surface, facet: np.ndarray) -> np.ndarray:
    """(m, 3) a label per face corner, shared by the corners of one vertex whose faces connect
    around it across manifold edges that are not in `facet` (smoothing groups); every corner of
    a vertex on a facet edge keeps its face's own normal (a smooth contour there would run
    on from flat faces whose outline it misses)."""
    ef, edges = surface.edge_faces, surface.edges
    on_facet = np.zeros(len(surface.vertices), dtype=bool)
    on_facet[edges[facet].reshape(-1)] = True
    e = np.flatnonzero((ef[:, 0] >= 0) & ~facet)
    ends = [e[~on_facet[edges[e, j]]] for j in (0, 1)]
    c1 = np.concatenate([_corner_ids(surface, ef[k, 0], edges[k, j]) for j, k in enumerate(ends)])
    c2 = np.concatenate([_corner_ids(surface, ef[k, 1], edges[k, j]) for j, k in enumerate(ends)])
    labels = np.arange(3 * len(surface.faces))
    while True:                                  # the least id of each group, spread along the pairs
        new = labels.copy()
        np.minimum.at(new, c1, labels[c2])
        np.minimum.at(new, c2, labels[c1])
        new = new[new]
        if np.array_equal(new, labels):
            return labels.reshape(-1, 3)
        labels = new


def corner_normals(surface: Surface, labels: np.ndarray) -> np.ndarray:
    """(m, 3, 3) unit normal at each face corner: the area-weighted mean of its group's faces."""
    v, f = surface.vertices, surface.faces
    cross = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])       # twice the area long
    total = np.zeros((labels.size, 3))
    np.add.at(total, labels.reshape(-1), np.repeat(cross / max(float(np.abs(cross).max()), 1e-300), 3, axis=0))
    return _unit(total[labels.reshape(-1)]).reshape(-1, 3, 3)


def _facet_runs(g0: np.ndarray, g1: np.ndarray) -> list[tuple[float, float, int, int]]:
    """Along an edge (t from 0 to 1) with the values g0 = (at t 0, at t 1) on one face and g1 on
    the other: the runs (t0, t1, end0, end1) where the two have opposite signs; an end is 0 for
    the edge's first vertex, 1 for its second, 2 and 3 for the crossing of g0, g1."""
    cuts = [(0.0, 0), (1.0, 1)]
    for code, g in ((2, g0), (3, g1)):
        if (g[0] > 0) != (g[1] > 0):
            cuts.append((g[0] / (g[0] - g[1]), code))
    cuts.sort()
    runs = []
    for (t0, a), (t1, b) in zip(cuts[:-1], cuts[1:]):
        mid = 0.5 * (t0 + t1)
        if t1 > t0 and (g0[0] + mid * (g0[1] - g0[0])) * (g1[0] + mid * (g1[1] - g1[0])) < 0:
            runs.append((t0, t1, a, b))
    return runs


def along_facets(surface: Surface, gc: np.ndarray, labels: np.ndarray) -> tuple:
    """The contour where it runs along edges: manifold edges whose two faces carry other corner
    labels (so other values of g) and where their g differ in sign.  Keys, points and rows of
    segments, in the keys of `corner_zero_set` for the crossings and (1, vertex, 0, 0) for the
    edges' ends."""
    ef, edges, v = surface.edge_faces, surface.edges, surface.vertices
    e = np.flatnonzero(ef[:, 0] >= 0)
    ends = [[_corner_ids(surface, ef[e, side], edges[e, j]) for j in (0, 1)] for side in (0, 1)]
    lab, g = labels.reshape(-1), gc.reshape(-1)
    split = (lab[ends[0][0]] != lab[ends[1][0]]) | (lab[ends[0][1]] != lab[ends[1][1]])
    keys, points, rows = [], [], []
    for i in np.flatnonzero(split):
        side_g = [(g[ends[s][0][i]], g[ends[s][1][i]]) for s in (0, 1)]
        a, b = edges[e[i]]
        code_key = [(1, a, 0, 0), (1, b, 0, 0)] + [(0, e[i], lab[ends[s][0][i]], lab[ends[s][1][i]]) for s in (0, 1)]
        for t0, t1, c0, c1 in _facet_runs(*side_g):
            rows.append((len(keys), len(keys) + 1))
            keys += [code_key[c0], code_key[c1]]
            points += [(1.0 - t0) * v[a] + t0 * v[b], (1.0 - t1) * v[a] + t1 * v[b]]
    return (np.array(keys, dtype=np.int64).reshape(-1, 4), np.array(points, dtype=float).reshape(-1, 3),
            np.array(rows, dtype=np.int64).reshape(-1, 2))


def contours(surface: Surface, camera) -> Lines:
    """Occluding contours: zeros of g = n . v over every face, n the corners' normals, and the
    facet edges whose two faces' g differ in sign."""
    labels = corner_labels(surface, facet_edges(surface, camera))
    to_eye = camera.to_eye(surface.vertices)[surface.faces]
    gc = _nonzero(np.einsum("fkj,fkj->fk", corner_normals(surface, labels), to_eye))
    keys, points, rows = corner_zero_set(surface, gc, labels, np.arange(len(surface.faces)))
    k2, p2, r2 = along_facets(surface, gc, labels)
    return _keyed(np.vstack([keys, k2]), np.vstack([points, p2]), np.vstack([rows, r2 + len(keys)]), SILHOUETTE)


def _edge_lines(surface: Surface, mask: np.ndarray, kind: int) -> Lines:
    """The mesh edges where `mask` (e,) holds, as segments over the surface's vertices."""
    edges = surface.edges[mask]
    used, seg = np.unique(edges, return_inverse=True)
    return Lines(surface.vertices[used], seg.reshape(-1, 2), np.full(len(edges), kind, dtype=np.int64))


def boundaries(surface: Surface) -> Lines:
    """Edges with one face: the borders of an open mesh."""
    return _edge_lines(surface, surface.edge_count == 1, BOUNDARY)


def creases(surface: Surface, angle_deg: float, camera=None) -> Lines:
    """Manifold edges whose two face normals part by more than `angle_deg`; with a camera, not
    those between a face toward it and a face away (the outline runs there)."""
    ef = surface.edge_faces
    two = ef[:, 0] >= 0
    cos = np.ones(len(ef))
    cos[two] = np.einsum("ij,ij->i", surface.face_normals[ef[two, 0]], surface.face_normals[ef[two, 1]])
    keep = two & (cos < math.cos(math.radians(angle_deg)))
    if camera is not None:
        f = surface.faces
        facing = np.einsum("ij,ij->i", surface.face_normals, camera.to_eye(surface.vertices[f].mean(axis=1))) > 0
        keep &= facing[ef[:, 0]] == facing[ef[:, 1]]
    return _edge_lines(surface, keep, CREASE)


def _face_gradients(surface: Surface, values: np.ndarray) -> np.ndarray:
    """(m, 3) gradient of the per-vertex `values`, linear over each face, in the face's plane."""
    v, f, n = surface.vertices, surface.faces, surface.face_normals
    grad = np.zeros((len(f), 3))
    area2 = np.maximum(np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1), 1e-300)
    for k in range(3):
        # grad = sum_k values_k (n x e_k) / (2 A), e_k the side opposite corner k
        e = v[f[:, (k + 2) % 3]] - v[f[:, (k + 1) % 3]]
        grad += values[f[:, k], None] * np.cross(n, e)
    return grad / area2[:, None]


def _to_vertices(surface: Surface, face_values: np.ndarray) -> np.ndarray:
    """(n, d) average over each vertex's faces of (m, d) face values."""
    out = np.zeros((len(surface.vertices), face_values.shape[1]))
    count = np.zeros(len(surface.vertices))
    for k in range(3):
        np.add.at(out, surface.faces[:, k], face_values)
        np.add.at(count, surface.faces[:, k], 1.0)
    return out / np.maximum(count, 1.0)[:, None]


def suggestive(surface: Surface, camera) -> Lines:
    """Suggestive contours: zeros of D_w g on front faces near grazing, where D_w g rises along w."""
    view = camera.to_eye(surface.vertices)
    g = np.einsum("ij,ij->i", surface.normals, view)
    w = view - g[:, None] * surface.normals                 # (n, 3) view projected on the tangent plane
    dwg = np.einsum("ij,ij->i", _to_vertices(surface, _face_gradients(surface, g)), w)
    f = surface.faces
    front = np.all(g[f] > 0, axis=1) & (g[f].min(axis=1) < SUGGESTIVE_GRAZING)
    rise = np.einsum("ij,ij->i", _face_gradients(surface, dwg), w[f].mean(axis=1))
    steady = rise > SUGGESTIVE_RISE / max(surface.diagonal, 1e-300)
    return zero_set(surface, dwg, np.flatnonzero(front & steady), SUGGESTIVE)


def extract(surface: Surface, camera, kinds=("silhouette", "boundary", "crease"), crease_deg: float = 60.0) -> Lines:
    """The feature lines of `kinds` (names from KINDS) seen by `camera`."""
    outline_camera = camera if "silhouette" in kinds else None
    makers = {"silhouette": lambda: contours(surface, camera), "boundary": lambda: boundaries(surface),
              "crease": lambda: creases(surface, crease_deg, outline_camera),
              "suggestive": lambda: suggestive(surface, camera)}
    lines = Lines.empty()
    for name in kinds:
        lines = lines.concat(makers[name]())
    return lines
