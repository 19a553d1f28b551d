"""`brushwork demo`: the brush's demo figure (brushwork.demo, imported only when asked for)."""
from __future__ import annotations

import argparse
import sys


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("-o", "--output", metavar="FILE", default=None,
                   help="the image the demo writes (default: the demo's own, brush_demo.png)")


def handle(args: argparse.Namespace) -> int:
    try:
        from .. import demo
    except ModuleNotFoundError as exc:
        if exc.name not in ("brushwork.demo",):
            raise
        print("brushwork: error: the demo is not available in this build (no brushwork.demo)",
              file=sys.stderr)
        return 2
    # without -o the demo picks its own file name
    rc = demo.main(args.output) if args.output else demo.main()
    return rc if isinstance(rc, int) else 0
