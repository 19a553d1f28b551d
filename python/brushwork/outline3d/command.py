"""`brushwork outline MESH -o out.png ...`: the command line of the 3-D outlines."""
from __future__ import annotations

import argparse
import json
import os
import sys
import time

from .lines import KINDS


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("mesh", help="a triangle mesh: OBJ, PLY, STL, OFF, GLB or glTF")
    p.add_argument("-o", "--output", metavar="FILE", required=True, help="the PNG to write (with --frames: "
                   "FILE's name numbered, out_000.png ...)")
    p.add_argument("--size", type=int, default=1024, help="image side in px, 64..4096 (default 1024)")
    p.add_argument("--azimuth", type=float, default=30.0, help="degrees about the mesh's y axis (default 30)")
    p.add_argument("--elevation", type=float, default=20.0, help="degrees above the horizon, -89..89 (default 20)")
    lens = p.add_mutually_exclusive_group()
    lens.add_argument("--fov", type=float, default=30.0, help="vertical field of view, 1..120 degrees (default 30)")
    lens.add_argument("--orthographic", action="store_true", help="an orthographic camera")
    p.add_argument("--lines", default="silhouette,boundary,crease",
                   help=f"kinds of line, comma-separated from {','.join(KINDS)} (default silhouette,boundary,crease)")
    p.add_argument("--crease-angle", type=float, default=60.0, help="dihedral angle past which an edge is a crease "
                                                                    "(degrees, default 60)")
    p.add_argument("--style", default="baimiao", help="outline style: baimiao, xieyi or a JSON file (default baimiao)")
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
    if not args.output.lower().endswith(".png"):
        raise ValueError(f"{args.output}: the output must be a .png file")


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
    from .strokes import OutlineStyle

    _check(args)
    kinds = _kinds(args.lines)
    style = OutlineStyle.load(args.style)
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
    frames = []
    for k in range(args.frames):
        view = View(args.azimuth + 360.0 * k / args.frames, args.elevation, fov, (args.size, args.size))
        drawing = draw(surface, view, style, kinds, args.crease_angle, args.hidden)
        drawing.stats["seconds"]["load"] = load_s if k == 0 else 0.0
        out = drawing.paper.save(numbered(args.output, k, args.frames))
        if args.camera_json:
            text = json.dumps(drawing.camera.to_json())
            _write_text(numbered(args.camera_json, k, args.frames), text)
        frames.append({"output": out, "azimuth": view.azimuth, **drawing.stats})
        print(f"wrote {out} ({drawing.stats['chains']} chains, {drawing.stats['strokes']} strokes)")
    if args.stats:
        text = json.dumps({"mesh": os.fspath(args.mesh), "style": style.name, "frames": frames}, indent=1)
        _write_text(args.stats, text)
    return 0
