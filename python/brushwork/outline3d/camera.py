"""The camera of a 3-D outline: where the eye is, and the one matrix that maps the mesh to pixels.

Convention (the one `--camera-json` writes): a vertex v of the mesh file maps to p = M [v, 1] and
lands on pixel (p0/p3, p1/p3), x right, y down, origin at the image's top-left corner; p2/p3 is
the depth, -1 at the near plane and 1 at the far plane, growing away from the camera.  The mesh
is y-up (the OBJ/glTF habit); azimuth turns the eye about that axis, elevation raises it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

MARGIN = 0.06          # of the image's smaller side, left free around the fitted mesh
NEAR_SLACK = 1.05      # the depth range covers the bounding sphere's radius times this


@dataclass(frozen=True)
class Camera:
    """eye, target: (3,) in mesh units; up: (3,) unit; fov_deg: vertical field of view, 0 for an
    orthographic camera; matrix: (4, 4) row-major M of the convention above; size: (W, H) px."""
    eye: np.ndarray
    target: np.ndarray
    fov_deg: float
    matrix: np.ndarray
    size: tuple[int, int]
    near: float
    far: float
    px_per_unit: float        # pixels per mesh unit at the target's distance

    @property
    def orthographic(self) -> bool:
        return self.fov_deg <= 0.0

    @property
    def forward(self) -> np.ndarray:
        """(3,) unit direction the camera looks along."""
        f = self.target - self.eye
        return f / np.linalg.norm(f)

    def homogeneous(self, points: np.ndarray) -> np.ndarray:
        """(n, 4) p = M [v, 1] of (n, 3) points."""
        pts = np.asarray(points, dtype=float)
        return pts @ self.matrix[:, :3].T + self.matrix[:, 3]

    def project(self, points: np.ndarray) -> np.ndarray:
        """(n, 3) pixel x, pixel y and depth p2/p3 of (n, 3) points."""
        p = self.homogeneous(points)
        return p[:, :3] / p[:, 3:4]

    def to_eye(self, points: np.ndarray) -> np.ndarray:
        """(n, 3) unit vectors from each point toward the eye (all -forward when orthographic)."""
        pts = np.asarray(points, dtype=float)
        if self.orthographic:
            return np.broadcast_to(-self.forward, pts.shape).copy()
        d = self.eye - pts
        return d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-300)

    def distance(self, points: np.ndarray) -> np.ndarray:
        """(n,) distance of each point from the eye along the view axis (mesh units)."""
        return (np.asarray(points, dtype=float) - self.eye) @ self.forward

    def eye_distance(self, depth: np.ndarray) -> np.ndarray:
        """Distance along the view axis (mesh units) of finite depths p2/p3 in [-1, 1]."""
        n, f = self.near, self.far
        if self.orthographic:
            return n + 0.5 * (np.asarray(depth) + 1.0) * (f - n)
        return 2.0 * f * n / (f + n - np.asarray(depth) * (f - n))

    def pixel_size(self, distance: np.ndarray) -> np.ndarray:
        """The width in mesh units of one pixel at `distance` from the eye along the view axis."""
        if self.orthographic:
            return np.full(np.shape(distance), 1.0 / self.px_per_unit)
        return np.asarray(distance) / (self.px_per_unit * float(np.linalg.norm(self.target - self.eye)))

    def to_json(self) -> dict:
        """{"size": [W, H], "matrix": 4 x 4 row-major} (see the module's convention)."""
        return {"size": [int(self.size[0]), int(self.size[1])], "matrix": self.matrix.tolist()}


def _look_at(eye: np.ndarray, target: np.ndarray, up: np.ndarray) -> np.ndarray:
    """(4, 4) right-handed view matrix: the camera looks down its -z, x right, y up."""
    f = target - eye
    f = f / np.linalg.norm(f)
    if abs(f @ up) > 0.999:                       # looking straight along the up axis
        up = np.array([0.0, 0.0, -1.0 if f @ up > 0 else 1.0])
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = s, u, -f
    view[:3, 3] = -view[:3, :3] @ eye
    return view


def _projection(fov_deg: float, near: float, far: float, half_height: float) -> np.ndarray:
    """(4, 4) OpenGL projection onto normalised device coordinates (square: aspect set later)."""
    m = np.zeros((4, 4))
    if fov_deg > 0.0:
        t = 1.0 / math.tan(math.radians(0.5 * fov_deg))
        m[0, 0] = m[1, 1] = t
        m[2, 2], m[2, 3] = (far + near) / (near - far), 2.0 * far * near / (near - far)
        m[3, 2] = -1.0
    else:
        m[0, 0] = m[1, 1] = 1.0 / half_height
        m[2, 2], m[2, 3] = -2.0 / (far - near), -(far + near) / (far - near)
        m[3, 3] = 1.0
    return m


def _to_pixels(width: int, height: int) -> np.ndarray:
    """(4, 4): normalised device coordinates to pixels, y down from the top-left corner."""
    s = 0.5 * min(width, height)                 # square pixels: the smaller side spans [-1, 1]
    return np.array([[s, 0.0, 0.0, 0.5 * width],
                     [0.0, -s, 0.0, 0.5 * height],
                     [0.0, 0.0, 1.0, 0.0],
                     [0.0, 0.0, 0.0, 1.0]])


def _centre_on(matrix: np.ndarray, points: np.ndarray, width: int, height: int, margin: float) -> np.ndarray:
    """M with a 2-D scale and shift of the image plane (p0, p1 -> a p + b p3) that puts the
    projected `points`' bounding box in the middle of the image, `margin` of the smaller side
    left free around it.  Depth is untouched."""
    p = points @ matrix[:, :3].T + matrix[:, 3]
    xy = p[:, :2] / p[:, 3:4]
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    extent = np.maximum(hi - lo, 1e-12)
    free = (1.0 - 2.0 * margin) * np.array([width, height], dtype=float)
    a = float(np.min(free / extent))
    b = 0.5 * np.array([width, height]) - a * 0.5 * (lo + hi)
    fit = np.eye(4)
    fit[0, 0] = fit[1, 1] = a
    fit[0, 3], fit[1, 3] = b
    return fit @ matrix


def fit(vertices: np.ndarray, size: tuple[int, int], azimuth_deg: float = 30.0, elevation_deg: float = 20.0,
        fov_deg: float = 30.0, margin: float = MARGIN) -> Camera:
    """A camera looking at (n, 3) `vertices` from (azimuth, elevation) about the y axis, the
    mesh filling the image but for `margin` whatever its units; fov_deg 0: orthographic."""
    pts = np.asarray(vertices, dtype=float)
    width, height = int(size[0]), int(size[1])
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    radius = max(float(np.max(np.linalg.norm(pts - centre, axis=1))), 1e-12)
    az, el = math.radians(azimuth_deg), math.radians(elevation_deg)
    direction = np.array([math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)])
    # the eye far enough that the bounding sphere fits the field of view
    dist = radius / math.sin(math.radians(0.5 * fov_deg)) if fov_deg > 0 else 3.0 * radius
    eye = centre + dist * direction
    near = max(dist - NEAR_SLACK * radius, 1e-3 * dist)
    far = dist + NEAR_SLACK * radius
    view = _look_at(eye, centre, np.array([0.0, 1.0, 0.0]))
    proj = _projection(fov_deg, near, far, radius)
    matrix = _centre_on(_to_pixels(width, height) @ proj @ view, pts, width, height, margin)
    cam = Camera(eye=eye, target=centre, fov_deg=max(float(fov_deg), 0.0), matrix=matrix, size=(width, height),
                 near=near, far=far, px_per_unit=1.0)
    return Camera(eye=eye, target=centre, fov_deg=cam.fov_deg, matrix=matrix, size=(width, height),
                  near=near, far=far, px_per_unit=_pixels_per_unit(cam, radius, view[0, :3]))


def _pixels_per_unit(cam: Camera, radius: float, across: np.ndarray) -> float:
    """Pixels per mesh unit at the target: the image of a step of one radius across the view."""
    a, b = cam.project(np.stack([cam.target, cam.target + radius * across]))
    return float(np.linalg.norm(b[:2] - a[:2])) / radius


def from_pose(vertices: np.ndarray, size: tuple[int, int], to_world: np.ndarray, yfov_deg: float) -> Camera:
    """The camera of a scene file: `to_world` (4, 4) maps the camera's frame (looking down its -z,
    y up) to the mesh's, `yfov_deg` its vertical field of view; the depth range spans the mesh.
    ValueError when the mesh lies wholly behind it."""
    pts = np.asarray(vertices, dtype=float)
    width, height = int(size[0]), int(size[1])
    eye, forward, up = to_world[:3, 3], -to_world[:3, 2], to_world[:3, 1]
    forward = forward / np.linalg.norm(forward)
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    radius = max(float(np.max(np.linalg.norm(pts - centre, axis=1))), 1e-12)
    ahead = (pts - eye) @ forward
    if ahead.max() <= 0.0:
        raise ValueError("the mesh lies behind the scene's camera")
    far = float(ahead.max()) + (NEAR_SLACK - 1.0) * radius
    near = max(float(ahead.min()) - (NEAR_SLACK - 1.0) * radius, 1e-3 * far)
    target = eye + forward * max(float((centre - eye) @ forward), near)
    view = _look_at(eye, target, up / np.linalg.norm(up))
    matrix = _to_pixels(width, height) @ _projection(yfov_deg, near, far, radius) @ view
    cam = Camera(eye=eye, target=target, fov_deg=float(yfov_deg), matrix=matrix, size=(width, height),
                 near=near, far=far, px_per_unit=1.0)
    return Camera(eye=eye, target=target, fov_deg=float(yfov_deg), matrix=matrix, size=(width, height),
                  near=near, far=far, px_per_unit=_pixels_per_unit(cam, radius, view[0, :3]))
