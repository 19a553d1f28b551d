"""The command-line face of `brushwork paint`, `brushwork replay` and `brushwork bench paint`
(registered in brushwork.cli)."""
from __future__ import annotations

import argparse
import asyncio
import os
import sys
import time

from .painting import MAX_PX, check_change


def _aiohttp() -> None:
    try:
        import aiohttp  # noqa: F401
    except ImportError:
        raise ValueError("brushwork paint needs aiohttp: pip install 'brushwork[paint]'") from None


def paint_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--port", type=int, default=8765, help="TCP port (default 8765; 0: any free port)")
    p.add_argument("--host", default="127.0.0.1", help="address to serve on (default 127.0.0.1; "
                                                         "any other needs --token)")
    p.add_argument("--token", default=None, help="a secret every request must carry (?token=...)")
    p.add_argument("--size", type=int, nargs=2, metavar=("W", "H"), default=(960, 640),
                   help="the paper on the page, px (default 960 640, at 5 px/mm)")
    p.add_argument("--preset", default="medium", help="brush preset (default medium)")
    p.add_argument("--tufts", type=int, default=1, help="tufts the brush may split into, the main one "
                   "included (1..9, default 1: a single tuft)")
    p.add_argument("--allow-host", metavar="NAME", action="append", default=[],
                   help="a further Host name the server answers to (repeatable; default: the --host "
                        "address, and localhost on loopback)")
    p.add_argument("--log-dir", metavar="DIR", default=None,
                   help="folder of each painting's motion log paint-YYYYMMDD-HHMMSS-ID.json (default: "
                        "brushwork's folder in the user's data directory, printed at the start)")


def check_paint(args: argparse.Namespace) -> None:
    """The options of `paint`, checked (ValueError in one line)."""
    from .. import BrushModel
    from .painting import MAX_TUFTS

    if not all(64 <= v <= 4096 for v in args.size):
        raise ValueError(f"--size {args.size[0]} {args.size[1]}: expected 64..4096 px each")
    if args.preset not in BrushModel.presets():
        raise ValueError(f"--preset {args.preset!r}: choose from {', '.join(BrushModel.presets())}")
    if not 1 <= args.tufts <= MAX_TUFTS:
        raise ValueError(f"--tufts {args.tufts}: expected 1..{MAX_TUFTS}")
    _check_serving(args)
    if args.log_dir is not None and (not os.path.isdir(args.log_dir) or not os.access(args.log_dir, os.W_OK)):
        raise ValueError(f"--log-dir {args.log_dir}: not a writable folder")


def _check_serving(args: argparse.Namespace) -> None:
    """--port, --host, --token and --allow-host, checked."""
    from .server import is_loopback

    if not 0 <= args.port <= 65535:
        raise ValueError(f"--port {args.port}: expected 0..65535")
    if not is_loopback(args.host) and not args.token:
        raise ValueError(f"--host {args.host}: serving beyond this machine needs --token SECRET")
    if args.token is not None and not (8 <= len(args.token) <= 256 and args.token.isascii() and args.token.isprintable()):
        raise ValueError("--token: expected 8..256 printable ASCII characters")
    for name in args.allow_host:
        if not 1 <= len(name) <= 253 or not name.isascii() or not name.isprintable() or " " in name:
            raise ValueError(f"--allow-host {name[:40]!r}: expected a host name or address")


def default_log_dir() -> str:
    """brushwork's paint folder in the user's data directory (platformdirs), made if missing."""
    try:
        from platformdirs import user_data_dir
    except ImportError:
        raise ValueError("brushwork paint needs platformdirs for its default --log-dir: "
                         "pip install 'brushwork[paint]', or give --log-dir DIR") from None
    folder = os.path.join(user_data_dir("brushwork", appauthor=False), "paint")
    os.makedirs(folder, exist_ok=True)
    return folder


def paint(args: argparse.Namespace) -> int:
    _aiohttp()
    check_paint(args)
    from .server import make_app, serve

    log_dir = args.log_dir if args.log_dir is not None else default_log_dir()
    app = make_app(tuple(args.size), args.preset, args.token, log_dir, tufts=args.tufts, host=args.host,
                   allow_hosts=tuple(args.allow_host))

    def announce(port: int) -> None:
        host = f"[{args.host}]" if ":" in args.host else args.host
        query = f"?token={args.token}" if args.token else ""
        print(f"brushwork paint: http://{host}:{port}/{query}  (a painting per page; motion logs: "
              f"{os.path.join(log_dir, 'paint-*.json')}; Ctrl-C stops)", flush=True)

    try:
        asyncio.run(serve(app, args.host, args.port, announce))
    except KeyboardInterrupt:
        pass
    return 0


def replay_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("log", help="a motion log of `brushwork paint` (its page's Save log, or the file in --log-dir)")
    p.add_argument("-o", "--output", metavar="FILE", required=True, help="the image to write (.png .jpg ...)")
    p.add_argument("--size", type=int, default=None,
                   help=f"the longer side of the image, 16..{MAX_PX} px (default: as painted)")


def replay(args: argparse.Namespace) -> int:
    from .replay import replay_file

    if args.size is not None and not 16 <= args.size <= MAX_PX:
        raise ValueError(f"--size {args.size}: expected 16..{MAX_PX} px")
    t0 = time.perf_counter()
    w, h, n = replay_file(args.log, args.output, args.size)
    print(f"wrote {args.output} ({w} x {h} px, {n} events, {time.perf_counter() - t0:.1f} s)")
    return 0


def bench_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")
    p.add_argument("--samples", type=int, default=300, help="pen samples of the measured stroke (default 300)")
    p.add_argument("--tufts", type=int, nargs="+", default=[1], metavar="K",
                   help="measure a brush of K tufts (the main one and its children), each K in turn (default 1)")
    p.add_argument("--clients", type=int, default=None, metavar="N",
                   help="instead: the server under load in a process of its own, N pages painting at once in "
                        "their own bands, pings while one floods or asks for re-renders, SIGTERM's exit time")
    p.add_argument("--flood-seconds", type=float, default=5.0, help="with --clients: the flood's length (default 5)")


def _bench_clients(args: argparse.Namespace) -> int:
    from ..bench import report
    from .load import run_clients, table

    if not 1 <= args.clients <= 16:
        raise ValueError(f"--clients {args.clients}: expected 1..16 (the paintings a server holds at once)")
    if not 0.5 <= args.flood_seconds <= 120:
        raise ValueError(f"--flood-seconds {args.flood_seconds}: expected 0.5..120")
    result = run_clients(args.clients, min(args.samples, 2000), args.flood_seconds,
                         progress=lambda m: print(f"  {m}", file=sys.stderr))
    print(table(result))
    if args.json:
        report.write_json(args.json, {"benchmark": "paint-clients", **result})
    return 0


def bench(args: argparse.Namespace) -> int:
    _aiohttp()
    from ..bench import report
    from .bench import run, table

    if not 10 <= args.samples <= 100000:
        raise ValueError(f"--samples {args.samples}: expected 10..100000")
    if args.json:
        report.check_writable(args.json)
    if args.clients is not None:
        return _bench_clients(args)
    for k in args.tufts:
        check_change({"tufts": k})
    result = run(args.samples, progress=lambda m: print(f"  {m}", file=sys.stderr), tufts=args.tufts)
    print(table(result))
    if args.json:
        report.write_json(args.json, {"benchmark": "paint", **result})
    return 0
