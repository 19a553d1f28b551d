"""`brushwork bench paint`: how long a pen sample takes to become ink in the page's image.

A client of the app (aiohttp's test client, over a real WebSocket on 127.0.0.1) sends one sample
of a wavy, pressure-varying stroke at a time and waits for the tile that answers it: the time
from sending to the tile's arrival is the pen-to-ink latency the page sees (less the browser's
PNG decode). The simulated frames per second count the core's work alone (Brush.step and
Paper.deposit) over the same stroke.
"""
from __future__ import annotations

import asyncio
import json
import math
import time

import numpy as np

P95_TARGET_MS = {1: 50.0, 5: 80.0}  # ms: the pen-to-ink targets of one tuft and of five


def stroke(n: int, width: int, height: int) -> list:
    """n pen samples of a wave across the paper, pressure 0.2..0.9 and the pen tilted 25 deg."""
    out = []
    for k in range(n):
        t = k / max(n - 1, 1)
        out.append({"x": width * (0.1 + 0.8 * t), "y": height * (0.5 + 0.25 * math.sin(6.0 * t)),
                    "pressure": 0.55 + 0.35 * math.sin(9.0 * t), "tiltX": 25.0, "tiltY": -8.0, "twist": 0.0})
    return out


async def _answer(ws, seq: int) -> dict:
    while True:
        msg = json.loads((await ws.receive()).data)
        if msg["type"] == "tile" and msg["seq"] == seq:
            return msg
        if msg["type"] == "error":
            raise RuntimeError(msg["message"])


async def _measure(n: int, progress, tufts: int = 1) -> dict:
    from aiohttp.test_utils import TestClient, TestServer

    from .server import SERVER, make_app

    app = make_app(tufts=tufts)
    async with TestClient(TestServer(app, host="127.0.0.1")) as client:
        ws = await client.ws_connect("/ws")
        hello = json.loads((await ws.receive()).data)
        await ws.receive()                                   # the whole paper
        lat, inked = [], 0
        # a stroke to warm up (the shaders' first compilation), then undone
        for seq, s in enumerate(stroke(20, hello["width"], hello["height"]), start=n + 1):
            await ws.send_str(json.dumps({"type": "samples", "seq": seq, "samples": [s]}))
            await _answer(ws, seq)
        for seq, kind in enumerate(("up", "undo"), start=n + 21):
            await ws.send_str(json.dumps({"type": kind, "seq": seq}))
            await _answer(ws, seq)
        painting = next(iter(app[SERVER].connections.values())).painting
        painting.frames, painting.sim_s, painting.split_frames = 0, 0.0, 0
        progress(f"{n} samples, one at a time, on a {hello['width']} x {hello['height']} px paper")
        for seq, s in enumerate(stroke(n, hello["width"], hello["height"])):
            t0 = time.perf_counter()
            await ws.send_str(json.dumps({"type": "samples", "seq": seq, "samples": [s]}))
            inked += "png" in await _answer(ws, seq)
            lat.append(time.perf_counter() - t0)
        await ws.send_str(json.dumps({"type": "up", "seq": n}))
        await _answer(ws, n)
        await ws.close()
    lat_ms = np.array(lat) * 1e3
    return {"tufts": tufts, "samples": n, "inked_samples": inked, "size_px": list(painting.size_px),
            "preset": painting.settings["preset"], "scene": painting.settings["scene"],
            "p50_ms": float(np.percentile(lat_ms, 50)), "p95_ms": float(np.percentile(lat_ms, 95)),
            "max_ms": float(lat_ms.max()), "frames": painting.frames, "split_frames": painting.split_frames,
            "simulated_fps": painting.frames / painting.sim_s if painting.sim_s > 0 else 0.0,
            "samples_per_s": n / float(np.sum(lat))}


def run(n: int = 300, progress=lambda m: None, tufts=(1,)) -> dict:
    """The measurement for the first tuft count at the top level, every count's in "rows"."""
    rows = []
    for k in tufts:
        progress(f"a brush of {k} tuft{'s' if k > 1 else ''}")
        rows.append(asyncio.run(_measure(n, progress, k)))
    return {**rows[0], "rows": rows}


def table(r: dict) -> str:
    """One block per tuft count measured."""
    return "\n\n".join(_block(row) for row in r.get("rows", [r]))


def _block(r: dict) -> str:
    target = P95_TARGET_MS.get(r["tufts"])
    rows = [("brush", f"{r['preset']}, {r['tufts']} tuft{'s' if r['tufts'] > 1 else ''} at most"),
            ("paper", f"{r['size_px'][0]} x {r['size_px'][1]} px, {', '.join(k for k, v in r['scene'].items() if v)}"),
            ("pen sample to ink in the page's image, p50 / p95 / max",
             f"{r['p50_ms']:.1f} / {r['p95_ms']:.1f} / {r['max_ms']:.1f} ms"
             + (f" (target p95 <= {target:g} ms)" if target else "")),
            ("samples answered with ink", f"{r['inked_samples']} of {r['samples']}"),
            ("simulated frames per second (step + deposit)",
             f"{r['simulated_fps']:.0f} ({r['frames']} frames, {r['split_frames']} of them split)"),
            ("samples per second, one at a time", f"{r['samples_per_s']:.0f}")]
    w = max(len(a) for a, _ in rows)
    return "\n".join(f"{a:<{w}}  {b}" for a, b in rows)
