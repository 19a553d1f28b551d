"""A contact sheet of 3-D outlines: every mesh of a folder (rows) in each style (columns).

    python -m brushwork.outline3d.sheet --meshes DIR [--styles baimiao,xieyi] [--size N] -o FILE
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from .meshfile import mesh_files



def contact_sheet(meshes: list, styles: list, path: str, size: int = 512, azimuth: float = 30.0) -> str:
    """Draw each mesh in each style at `size` px and tile them, labelled; returns the path."""
    import cv2

    from ..files import write_image
    from .draw import View, draw, load_mesh
    from .lines import prepare
    from .strokes import OutlineStyle

    looks = [OutlineStyle.load(s) for s in styles]
    rows = []
    for mesh in meshes:
        surface = prepare(*load_mesh(mesh)[:2])
        cells = []
        for style in looks:
            img = cv2.cvtColor(draw(surface, View(azimuth, 20.0, 30.0, (size, size)), style).paper.image(),
                               cv2.COLOR_RGB2BGR)
            cv2.putText(img, f"{Path(mesh).stem} / {style.name}", (10, 28), cv2.FONT_HERSHEY_SIMPLEX,
                        0.7 * size / 512, (110, 110, 110), 1, cv2.LINE_AA)
            cv2.rectangle(img, (0, 0), (size - 1, size - 1), (210, 210, 210), 1)
            cells.append(img)
        rows.append(np.hstack(cells))
    return write_image(path, np.vstack(rows))


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m brushwork.outline3d.sheet", description=__doc__.splitlines()[0])
    p.add_argument("--meshes", metavar="DIR", required=True, help="folder of meshes (OBJ, PLY, STL, OFF, GLB, glTF)")
    p.add_argument("--styles", default="baimiao,xieyi", help="comma-separated styles (default baimiao,xieyi)")
    p.add_argument("--size", type=int, default=512, help="px per cell (default 512)")
    p.add_argument("-o", "--output", required=True, help="the PNG to write")
    args = p.parse_args(argv)
    try:
        meshes = [str(f) for f in mesh_files(args.meshes)]
        print(f"wrote {contact_sheet(meshes, args.styles.split(','), args.output, args.size)}")
    except (ValueError, OSError) as err:
        print(f"brushwork: error: {' '.join(str(err).split())}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
