"""The paper: float ink on a canvas of any size, images in and out (DESIGN's promised `Paper`).

x right, y up, origin at the paper's bottom-left corner, in mm; `ink()` and `rgba()` hand back
numpy arrays with row 0 at the top of the paper (the way images are stored).
"""
from __future__ import annotations

import os

import numpy as np

from . import _core
from .files import write_image
from .scene import TEXTURED, Scene

_BACKGROUNDS = ("white", "transparent")


def _image_io():
    try:
        import cv2
    except ImportError as err:  # pragma: no cover - a declared dependency
        raise RuntimeError("PNG input/output needs OpenCV: pip install opencv-python-headless") from err
    return cv2


def _check_image(bits: int, background: str) -> None:
    if bits not in (8, 16):
        raise ValueError(f"bits = {bits}: expected 8 or 16")
    if background not in _BACKGROUNDS:
        raise ValueError(f"background = {background!r}: expected one of {_BACKGROUNDS}")


#: how a paper takes its ink: "geometry" (contours in mm, rasterised with exact coverage, no GL),
#: "gl" (the EGL footprint pass) or "auto" (geometry where the scene is opaque)
INK_PATHS = ("auto", "geometry", "gl")
_LAST_INK = {"ink": None}


def ink_path(scene: _core.SceneFeatures, ink: str = "auto") -> str:
    """The path a paper of `scene` takes for `ink`: auto picks geometry for an opaque scene (no
    split, dry or grain map, soaked tip or colour ramp), else gl; geometry refuses a textured scene."""
    if ink not in INK_PATHS:
        raise ValueError(f"ink {ink!r}: expected one of {', '.join(INK_PATHS)}")
    textured = [name for name in TEXTURED if getattr(scene, name)]
    if ink == "geometry" and textured:
        raise ValueError(f"ink 'geometry': the scene uses {', '.join(textured)}, which need ink 'gl' (or 'auto')")
    if ink == "auto":
        return "gl" if textured else "geometry"
    return ink


def render_info() -> dict:
    """Which path the last paper made in this process took (`ink`: geometry, gl or None) and, unless
    it was geometry (which needs no GL), the EGL path (backend, device, GL renderer; opens the context)."""
    if _LAST_INK["ink"] == "geometry":
        return {"ink": "geometry", "backend": "none"}
    return dict(_core.RenderContext.acquire().info, ink=_LAST_INK["ink"])


def make_paper(width_mm: float, height_mm: float, px_per_mm: float = 10.0,
               scene: _core.SceneFeatures | None = None, ink: str = "auto") -> "Paper | VectorPaper":
    """A paper of `scene` whose ink takes the path `ink` chooses (see ink_path)."""
    scene = scene if scene is not None else Scene()
    if ink_path(scene, ink) == "geometry":
        return VectorPaper(width_mm, height_mm, px_per_mm, scene)
    return Paper(width_mm, height_mm, px_per_mm, scene)


class _Faces:
    """What every paper says in Python: deposit with the brush's ink, images, PNG out."""

    def deposit(self, brush, ink: _core.Ink | None = None) -> _core.DepositStats:
        """Ink under `brush` (its own `brush.ink` unless `ink` is given)."""
        if ink is None:
            ink = getattr(brush, "ink", None)
        return super().deposit(brush, ink)

    def image(self, bits: int = 8, background: str = "white") -> np.ndarray:
        """The paper as an RGB (white background) or straight RGBA (transparent) image of
        uint8 (bits=8) or uint16 (bits=16), row 0 at the top."""
        _check_image(bits, background)
        # (one pass in the core, with numpy's float32 arithmetic: the same bytes as the chain of
        # ufuncs it replaces, without its 16 MB temporaries at 1024 px)
        return self._image(bits, background == "white", False)

    def save(self, path: str | os.PathLike, bits: int = 8, background: str = "white") -> str:
        """Write the paper as an image in the format the suffix of `path` names (PNG: 8 or 16
        bits, ink on white or on transparency); atomic: a reader never sees a partial file.
        Returns the path."""
        _check_image(bits, background)
        return write_image(path, self._image(bits, background == "white", True))

    def __repr__(self) -> str:
        return (f"{type(self).__name__}({self.width_mm} x {self.height_mm} mm, {self.width_px} x {self.height_px} px, "
                f"{self.scene!r})")


class Paper(_Faces, _core.Paper):
    """A canvas `width_mm` x `height_mm` sampled at `px_per_mm`, with the features of `scene`,
    inked by the EGL footprint pass.

    ``deposit(brush)`` lays down the ink under the brush, swept from its last deposit while it
    stays on the paper; a deposit with the brush in the air ends the stroke. ``undo()`` removes
    the last stroke (one level); ``clear()`` empties the paper.
    """

    inked_by = "gl"

    def __init__(self, width_mm: float, height_mm: float, px_per_mm: float = 10.0,
                 scene: _core.SceneFeatures | None = None, tile_px: int = 0):
        super().__init__(float(width_mm), float(height_mm), float(px_per_mm),
                         scene if scene is not None else Scene(), int(tile_px))
        _LAST_INK["ink"] = "gl"

    def load(self, path: str | os.PathLike) -> None:
        """Replace the paper by a PNG of the same pixel size. An image with alpha is taken as
        ink on transparency; without, as ink on white (black ink: coverage = 1 - grey)."""
        cv2 = _image_io()
        path = os.fspath(path)
        img = cv2.imread(path, cv2.IMREAD_UNCHANGED)
        if img is None:
            raise ValueError(f"{path}: not a readable image")
        if img.shape[:2] != (self.height_px, self.width_px):
            raise ValueError(f"{path}: image is {img.shape[1]} x {img.shape[0]} px, the paper "
                             f"{self.width_px} x {self.height_px}")
        top = 65535.0 if img.dtype == np.uint16 else 255.0
        img = img.astype(np.float32) / top
        if img.ndim == 2:
            img = img[..., None].repeat(3, axis=2)
        if img.shape[2] == 4:
            rgb = img[..., 2::-1]                      # BGRA -> RGB
            alpha = img[..., 3:4]
            rgba = np.concatenate([rgb * alpha, alpha], axis=2)
        else:
            rgb = img[..., 2::-1]
            alpha = 1.0 - rgb.min(axis=2, keepdims=True)
            premult = rgb - (1.0 - alpha)              # v = c a + (1 - a)
            rgba = np.concatenate([np.clip(premult, 0.0, 1.0), alpha], axis=2)
        self.set_rgba(np.ascontiguousarray(rgba, dtype=np.float32))

    def __repr__(self) -> str:
        return (f"Paper({self.width_mm} x {self.height_mm} mm, {self.width_px} x {self.height_px} px, "
                f"{self.tiles} tile(s), {self.scene!r})")


class VectorPaper(_Faces, _core.VectorPaper):
    """A paper whose ink is geometry: what the brush leaves, swept continuously between frames, is
    kept as closed contours in mm (``outlines()``), unioned stroke by stroke, and rasterised with
    exact area coverage when an image is asked for; no GL context. Opaque scenes only (see
    `ink_path`); deposits, strokes and undo as on a `Paper`."""

    inked_by = "geometry"

    def __init__(self, width_mm: float, height_mm: float, px_per_mm: float = 10.0,
                 scene: _core.SceneFeatures | None = None, tol_mm: float = 0.005):
        super().__init__(float(width_mm), float(height_mm), float(px_per_mm),
                         scene if scene is not None else Scene(), _core.SweepTolerance(float(tol_mm)))
        _LAST_INK["ink"] = "geometry"

    def outlines(self) -> list:
        """The ink as closed contours: a list of (k, 2) float64 arrays in mm (x right, y up, the
        paper's bottom-left corner at 0), outer loops counter-clockwise, holes clockwise, none
        overlapping; the same at any px_per_mm."""
        return super().outlines()
