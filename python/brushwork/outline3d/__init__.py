"""3-D outlines in brush style: a triangle mesh and a camera to brush strokes on the paper.

camera (the view and its pixel matrix), lines (contours, boundaries, creases, suggestive
contours), visibility (the depth buffer through the EGL context), chains (linking, visibility
runs, smoothing), strokes (styles and brush motions), draw (the whole pipeline).
"""
from .camera import Camera, fit
from .draw import Drawing, View, draw, load_mesh
from .lines import KINDS, MeshError, Surface, prepare
from .strokes import OutlineStyle

__all__ = ["Camera", "Drawing", "KINDS", "MeshError", "OutlineStyle", "Surface", "View", "draw", "fit",
           "load_mesh", "prepare"]
