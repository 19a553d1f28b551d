"""3-D outlines in brush style: a triangle mesh and a camera to brush strokes on the paper.

camera (the view and its pixel matrix), lines (contours, boundaries, creases, suggestive
contours), visibility (the depth buffer through the EGL context), chains (linking, visibility
runs, smoothing), style (the outline style's fields), strokes (brush motions), draw (the whole
pipeline), vector (strokes as SVG paths).
"""
from .camera import Camera, fit
from .draw import Drawing, View, draw, load_mesh
from .lines import KINDS, MeshError, Surface, prepare
from .style import OutlineStyle

__all__ = ["Camera", "Drawing", "KINDS", "MeshError", "OutlineStyle", "Surface", "View", "draw", "fit",
           "load_mesh", "prepare"]
