"""The paper: float ink on a canvas of any size, images in and out (DESIGN's promised `Paper`).

x right, y up, origin at the paper's bottom-left corner, in mm; `ink()` and `rgba()` hand back
numpy arrays with row 0 at the top of the paper (the way images are stored).
"""
from __future__ import annotations

import os

import numpy as np

from . import _core
from .files import write_image
from .scene import Scene

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


def render_info() -> dict:
    """Which EGL path rendering takes (backend, device, GL renderer); opens the context."""
    return _core.RenderContext.acquire().info


class Paper(_core.Paper):
    """A canvas `width_mm` x `height_mm` sampled at `px_per_mm`, with the features of `scene`.

    ``deposit(brush)`` lays down the ink under the brush, swept from its last deposit while it
    stays on the paper; a deposit with the brush in the air ends the stroke. ``undo()`` removes
    the last stroke (one level); ``clear()`` empties the paper.
    """

    def __init__(self, width_mm: float, height_mm: float, px_per_mm: float = 10.0,
                 scene: _core.SceneFeatures | None = None, tile_px: int = 0):
        super().__init__(float(width_mm), float(height_mm), float(px_per_mm),
                         scene if scene is not None else Scene(), int(tile_px))

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
