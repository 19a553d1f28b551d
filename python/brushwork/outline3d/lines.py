"""Feature lines of a triangle mesh seen from a camera: occluding contours of the smooth surface,
boundaries, creases and (optionally) suggestive contours.

Contours are the zero set of g = n . v interpolated linearly over each face from the vertex
normals n and the unit vectors v toward the eye (Bénard & Hertzmann 2019, "interpolated
contours"), on the mesh welded across texture seams, so they run smooth and unbroken across
coarse faces.  Suggestive contours are zeros of the radial curvature, taken as zeros of
D_w g (the derivative of g along w, the view vector projected on the tangent plane) where it
rises along w, on front faces (DeCarlo et al. 2003).

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


def zero_set(surface: Surface, values: np.ndarray, faces: np.ndarray, kind: int) -> Lines:
    """The zero set of (n,) per-vertex `values`, linear over each face listed in `faces` (indices):
    one segment per face whose corners change sign, between the crossings on its two changing
    sides; a crossing is one point per edge, shared by the faces on both sides."""
    g = np.where(values == 0.0, 1e-12, values)            # no corner exactly on the zero set
    f = surface.faces[faces]
    sign = g[f] > 0                                        # (k, 3)
    crosses = sign != np.roll(sign, -1, axis=1)            # side k: corner k -> k+1
    hit = crosses.sum(axis=1) == 2
    f, crosses, fe = f[hit], crosses[hit], surface.face_edges[faces[hit]]
    if len(f) == 0:
        return Lines.empty()
    edge_ids = fe[crosses].reshape(-1, 2)                  # the two crossing sides of each face
    used, seg = np.unique(edge_ids, return_inverse=True)
    a, b = surface.edges[used, 0], surface.edges[used, 1]
    t = (g[a] / (g[a] - g[b]))[:, None]
    points = (1.0 - t) * surface.vertices[a] + t * surface.vertices[b]
    return Lines(points, seg.reshape(-1, 2), np.full(len(edge_ids), kind, dtype=np.int64))


def contours(surface: Surface, camera) -> Lines:
    """Occluding contours: zeros of g = n . v over every face."""
    g = np.einsum("ij,ij->i", surface.normals, camera.to_eye(surface.vertices))
    return zero_set(surface, g, np.arange(len(surface.faces)), SILHOUETTE)


def _edge_lines(surface: Surface, mask: np.ndarray, kind: int) -> Lines:
    """The mesh edges where `mask` (e,) holds, as segments over the surface's vertices."""
    edges = surface.edges[mask]
    used, seg = np.unique(edges, return_inverse=True)
    return Lines(surface.vertices[used], seg.reshape(-1, 2), np.full(len(edges), kind, dtype=np.int64))


def boundaries(surface: Surface) -> Lines:
    """Edges with one face: the borders of an open mesh."""
    return _edge_lines(surface, surface.edge_count == 1, BOUNDARY)


def creases(surface: Surface, angle_deg: float) -> Lines:
    """Manifold edges whose two face normals part by more than `angle_deg`."""
    ef = surface.edge_faces
    two = ef[:, 0] >= 0
    cos = np.ones(len(ef))
    cos[two] = np.einsum("ij,ij->i", surface.face_normals[ef[two, 0]], surface.face_normals[ef[two, 1]])
    return _edge_lines(surface, two & (cos < math.cos(math.radians(angle_deg))), CREASE)


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
    makers = {"silhouette": lambda: contours(surface, camera), "boundary": lambda: boundaries(surface),
              "crease": lambda: creases(surface, crease_deg), "suggestive": lambda: suggestive(surface, camera)}
    lines = Lines.empty()
    for name in kinds:
        lines = lines.concat(makers[name]())
    return lines
