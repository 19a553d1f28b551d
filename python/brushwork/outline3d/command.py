"""`brushwork outline MESH -o out.png ...`: the command line of the 3-D outlines."""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time

from .lines import KINDS

OUTPUTS = (".png", ".svg", ".pdf")


def finite(text: str) -> float:
    """argparse type: a finite number."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"not a finite number: {text!r}")
    return value


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("mesh", help="a triangle mesh: OBJ, PLY, STL, OFF, GLB or glTF")
    p.add_argument("-o", "--output", metavar="FILE", required=True, help="the PNG, or SVG or PDF (each stroke a "
                   "filled path, the SVG grouped by kind), to write (with --frames: FILE's name numbered, out_000.png ...)")
    p.add_argument("--size", type=int, default=1024, help="image side in px, 64..4096 (default 1024)")
    p.add_argument("--azimuth", type=finite, default=30.0, help="degrees about the mesh's y axis (default 30)")
    p.add_argument("--elevation", type=finite, default=20.0, help="degrees above the horizon, -89..89 (default 20)")
    lens = p.add_mutually_exclusive_group()
    lens.add_argument("--fov", type=finite, default=30.0, help="vertical field of view, 1..120 degrees (default 30)")
    lens.add_argument("--orthographic", action="store_true", help="an orthographic camera")
    p.add_argument("--camera-from", metavar="SCENE", help="the camera of a glTF/GLB scene (its first perspective "
                   "camera, or --camera's; the mesh may be the same file) instead of --azimuth, --elevation and --fov")
    p.add_argument("--camera", metavar="NAME", help="with --camera-from: the scene's camera of that name (its node's "
                   "name, else its camera's)")
    p.add_argument("--lines", default="silhouette,boundary,crease",
                   help=f"kinds of line, comma-separated from {','.join(KINDS)} (default silhouette,boundary,crease)")
    p.add_argument("--crease-angle", type=finite, default=60.0, help="dihedral angle past which an edge is a crease "
                                                                      "(degrees, default 60)")
    p.add_argument("--style", default="baimiao", help="outline style: baimiao, xieyi or a JSON file (default baimiao)")
    p.add_argument("--weight", metavar="KIND=W,...", help="line widths by kind against a line of weight 1, e.g. "
                   "silhouette=1.0,crease=0.6,suggestive=0.4,boundary=0.8, each 0..3 (default: the style's)")
    p.add_argument("--depth-weight", type=finite, metavar="K", help="nearest line's width times 1 + K/2, "
                   "farthest's times 1 - K/2, 0..1.5 (default: the style's)")
    p.add_argument("--ink", choices=("auto", "geometry", "gl"), help="how the ink is made: gl (the EGL footprint "
                   "pass; the default for PNGs), geometry (each stroke's region in mm, swept between frames; the "
                   "default for SVG and PDF, whose paths it gives) or auto (geometry unless the style's scene is "
                   "textured: xieyi's dry and grain maps, whose strokes an SVG or PDF traces)")
    p.add_argument("--hidden", choices=("none", "faint"), default="none", help="hidden lines: not drawn, or drawn faint")
    p.add_argument("--camera-json", metavar="FILE", help='write {"size": [W, H], "matrix": 4x4 row-major}: vertex v '
                   "lands on pixel (p0/p3, p1/p3) of p = M [v, 1], y down from the top-left corner")
    p.add_argument("--stats", metavar="FILE", help="write counts and the time per phase as JSON")
    p.add_argument("--frames", type=int, default=1, help="views to write (with --orbit: around the mesh)")
    p.add_argument("--orbit", action="store_true", help="turn the azimuth by 360/N degrees from frame to frame")


def _kinds(text: str) -> tuple:
    kinds = tuple(k.strip() for k in text.split(",") if k.strip())
    bad = [k for k in kinds if k not in KINDS]
    if bad or not kinds:
        raise ValueError(f"--lines {text!r}: expected names from {', '.join(KINDS)}")
    return kinds


def _weights(text: str, style) -> dict:
    """The style's weight by kind with those of `--weight KIND=W,...` put in."""
    from .style import FIELDS

    field = next(f for f in FIELDS if f.name == "weight")
    out = dict(style.weight)
    for item in (t.strip() for t in text.split(",") if t.strip()):
        name, _, value = item.partition("=")
        try:
            w = float(value)
        except ValueError:
            w = math.nan
        if name.strip() not in KINDS or not field.lo <= w <= field.hi:
            raise ValueError(f"--weight {text!r}: expected KIND=W pairs, KIND from {', '.join(KINDS)}, "
                             f"W in {field.lo:g}..{field.hi:g}")
        out[name.strip()] = w
    return out


def _style(args: argparse.Namespace):
    """The style of --style with --weight and --depth-weight put in."""
    import dataclasses

    from .style import OutlineStyle

    style = OutlineStyle.load(args.style)
    if args.weight is not None:
        style = dataclasses.replace(style, weight=_weights(args.weight, style))
    if args.depth_weight is not None:
        if not 0.0 <= args.depth_weight <= 1.5:
            raise ValueError(f"--depth-weight {args.depth_weight:g}: expected 0..1.5")
        style = dataclasses.replace(style, depth_weight=args.depth_weight)
    return style


def _check(args: argparse.Namespace) -> None:
    if not 64 <= args.size <= 4096:
        raise ValueError(f"--size {args.size}: expected 64..4096")
    if not -89.0 <= args.elevation <= 89.0:
        raise ValueError(f"--elevation {args.elevation}: expected -89..89")
    if not args.orthographic and not 1.0 <= args.fov <= 120.0:
        raise ValueError(f"--fov {args.fov}: expected 1..120")
    if not 0.0 < args.crease_angle < 180.0:
        raise ValueError(f"--crease-angle {args.crease_angle}: expected 0..180")
    if not 1 <= args.frames <= 3600:
        raise ValueError(f"--frames {args.frames}: expected 1..3600")
    if args.frames > 1 and not args.orbit:
        raise ValueError("--frames N needs --orbit")
    if args.camera_from and (args.orbit or args.orthographic):
        raise ValueError("--camera-from takes the scene's camera: not with --orbit or --orthographic")
    if args.camera is not None and not args.camera_from:
        raise ValueError("--camera NAME picks a camera of --camera-from SCENE, which is missing")
    if os.path.splitext(args.output)[1].lower() not in OUTPUTS:
        raise ValueError(f"{args.output}: the output must be a {' or '.join(OUTPUTS)} file")


def _check_ink(style, ink: str) -> None:
    """ValueError naming --ink when the style's scene cannot take that ink path."""
    from ..paper import ink_path
    from ..scene import Scene

    try:
        ink_path(Scene(**style.scene), ink)
    except ValueError as err:
        raise ValueError(f"--ink {ink}: {str(err).split(': ', 1)[-1]} (style {style.name})") from None


def numbered(path: str, k: int, frames: int) -> str:
    """`path` itself for one frame, else its name with _000, _001, ... before the suffix."""
    if frames == 1:
        return path
    stem, ext = os.path.splitext(path)
    return f"{stem}_{k:03d}{ext}"


def _write_text(path: str, text: str) -> None:
    from pathlib import Path

    from ..files import write_atomic

    write_atomic(path, lambda tmp: Path(tmp).write_text(text + "\n", encoding="utf-8"))


def run(args: argparse.Namespace) -> int:
    from ..files import check_writable
    from .draw import View, draw, load_mesh
    from .lines import prepare
    from .gltf import scene_camera
    from .vector import VECTOR_SUFFIXES, write_vector

    _check(args)
    kinds = _kinds(args.lines)
    style = _style(args)
    vector = os.path.splitext(args.output)[1].lower() in VECTOR_SUFFIXES
    ink = args.ink or ("auto" if vector else "gl")
    _check_ink(style, ink)
    for path in (args.output, args.camera_json, args.stats):
        if path:
            check_writable(path)
    t0 = time.perf_counter()
    vertices, faces, warnings = load_mesh(args.mesh)
    try:
        surface = prepare(vertices, faces)
    except ValueError as err:
        raise ValueError(f"{args.mesh}: {err}") from None
    load_s = time.perf_counter() - t0
    for note in warnings + surface.notes:
        print(f"brushwork: warning: {args.mesh}: {note}", file=sys.stderr)
    fov = 0.0 if args.orthographic else args.fov
    pose = scene_camera(args.camera_from, args.camera) if args.camera_from else None
    frames = []
    for k in range(args.frames):
        view = View(args.azimuth + 360.0 * k / args.frames, args.elevation, fov, (args.size, args.size), pose)
        drawing = draw(surface, view, style, kinds, args.crease_angle, args.hidden, vector, ink)
        drawing.stats["seconds"]["load"] = load_s if k == 0 else 0.0
        path = numbered(args.output, k, args.frames)
        out = (write_vector(path, drawing.shapes, view.size, drawing.paper.px_per_mm) if vector
               else drawing.paper.save(path))
        if args.camera_json:
            text = json.dumps(drawing.camera.to_json())
            _write_text(numbered(args.camera_json, k, args.frames), text)
        frames.append({"output": out, "azimuth": view.azimuth, **drawing.stats})
        print(f"wrote {out} ({drawing.stats['chains']} chains, {drawing.stats['strokes']} strokes)")
    if args.stats:
        text = json.dumps({"mesh": os.fspath(args.mesh), "style": style.name, "frames": frames}, indent=1)
        _write_text(args.stats, text)
    return 0
