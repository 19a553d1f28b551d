"""`brushwork bench paint --clients N`: the server under load, as a separate process on 127.0.0.1.

1. N pages paint at once, each a stroke along its own band of the paper, one sample at a time:
   each page's pen-to-ink latency, and the ink each painting holds outside its band (none: the
   paintings are apart).
2. One page floods its painter with the heaviest samples the budget admits while another pings:
   the ping's round trip (the event loop never paints).
3. One page asks for an 8192 px and a 4096 px re-render while another pings.
4. SIGTERM while a page floods and a re-render runs: the seconds until the process has ended.
Every loop is bounded and stops by itself.
"""
from __future__ import annotations

import asyncio
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

import numpy as np

BAND_PX = 64                 # px: the height of each page's band
WIDTH_PX = 640               # px: the paper's width


class Page:
    """A client of the server: its WebSocket, its painting, the answers to its messages."""

    def __init__(self, http, url: str):
        self.http, self.url, self.seq, self.ws, self.painting = http, url, 0, None, None
        self.refused = 0

    async def connect(self) -> "Page":
        self.ws = await self.http.ws_connect(self.url + "ws")
        hello = await self.ws.receive_json()
        self.painting = hello["painting"]
        return self

    async def send(self, msg: dict) -> float:
        """Send `msg` and wait for the tile answering it; the seconds it took (errors answering
        earlier messages are counted in `refused`)."""
        self.seq += 1
        t0 = time.perf_counter()
        await self.ws.send_str(json.dumps({**msg, "seq": self.seq}))
        while True:
            m = await self.ws.receive_json(timeout=120)
            if m["type"] == "tile" and m["seq"] == self.seq:
                return time.perf_counter() - t0
            self.refused += m["type"] == "error"

    async def image(self, size: int | None = None) -> tuple[int, bytes, float]:
        query = f"?painting={self.painting}" + (f"&size={size}" if size else "")
        t0 = time.perf_counter()
        async with self.http.get(self.url + "image.png" + query) as r:
            return r.status, await r.read(), time.perf_counter() - t0


async def band_stroke(page: Page, k: int, samples: int) -> list:
    """A stroke along band k, one sample at a time; the latency of each."""
    y = BAND_PX * (k + 0.5)
    lat = []
    for i in range(samples):
        x = 60 + (WIDTH_PX - 120) * i / max(samples - 1, 1)
        lat.append(await page.send({"type": "samples", "samples": [
            {"x": x, "y": y + 3 * np.sin(i / 4), "pressure": 0.35, "tiltX": 10, "tiltY": 0}]}))
    await page.send({"type": "up"})
    return lat


def ink_outside(png: bytes, k: int) -> tuple[int, int]:
    """(inked pixels outside band k, inside it) of a painting's PNG."""
    import cv2

    ink = 255 - cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_GRAYSCALE).astype(int)
    band = np.zeros(ink.shape[0], bool)
    band[BAND_PX * k:BAND_PX * (k + 1)] = True
    inked = ink > 12
    return int(inked[~band].sum()), int(inked[band].sum())


async def pings(page: Page, stop: asyncio.Event, period: float = 0.02) -> list:
    """Ping every `period` s until `stop`; each round trip, s."""
    out = []
    while not stop.is_set():
        t0 = time.perf_counter()
        await page.ws.send_str(json.dumps({"type": "ping", "seq": len(out)}))
        while (await page.ws.receive_json(timeout=60))["type"] != "pong":
            pass
        out.append(time.perf_counter() - t0)
        await asyncio.sleep(period)
    return out


async def flood(page: Page, seconds: float) -> int:
    """Messages of the heaviest samples the budget admits (zigzags of 1,680 frames), 100 a second
    for `seconds` without waiting for answers; then the pen lifted and its answer awaited. The
    messages sent."""
    zig = json.dumps({"type": "samples", "samples": [{"x": 40 + 50 * (k % 2), "y": 20 + 50 * (k % 2),
                                                      "pressure": 1.0} for k in range(120)]})
    t_end, n = time.monotonic() + seconds, 0
    while time.monotonic() < t_end:
        await page.ws.send_str(zig)
        n += 1
        await asyncio.sleep(0.01)
    await page.send({"type": "up"})
    return n


def start_server(clients: int, folder: str) -> tuple[subprocess.Popen, str]:
    height = min(4096, max(240, BAND_PX * clients))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    proc = subprocess.Popen([sys.executable, "-m", "brushwork", "paint", "--port", "0", "--size", str(WIDTH_PX),
                             str(height), "--log-dir", folder], env=env, stdout=subprocess.PIPE, text=True)
    return proc, proc.stdout.readline().split()[2]


def ms(values) -> dict:
    v = np.asarray(values, float) * 1e3
    if v.size == 0:
        return {"n": 0, "p50": 0.0, "p95": 0.0, "max": 0.0}
    return {"n": int(v.size), "p50": float(np.percentile(v, 50)), "p95": float(np.percentile(v, 95)),
            "max": float(v.max())}


async def _bands(http, url: str, clients: int, samples: int) -> dict:
    pages = [await Page(http, url).connect() for _ in range(clients)]
    lat = await asyncio.gather(*(band_stroke(p, k, samples) for k, p in enumerate(pages)))
    ink = [ink_outside((await p.image())[1], k) for k, p in enumerate(pages)]
    for p in pages:
        await p.ws.close()
    return {"latency_ms": [ms(v) for v in lat], "outside_px": [o for o, _ in ink], "inside_px": [i for _, i in ink]}


async def _under_load(http, url: str, seconds: float, samples: int, sizes: tuple) -> dict:
    """Pings while a page floods, then while another asks for re-renders of its stroke."""
    busy, pinger, artist = [await Page(http, url).connect() for _ in range(3)]
    await band_stroke(artist, 0, samples)
    stop = asyncio.Event()
    ping = asyncio.ensure_future(pings(pinger, stop))
    messages = await flood(busy, seconds)
    stop.set()
    flood_pings = await ping
    stop = asyncio.Event()
    ping = asyncio.ensure_future(pings(pinger, stop))
    big = await artist.image(sizes[0])
    large = await artist.image(sizes[1])
    stop.set()
    render_pings = await ping
    return {"flood_messages": messages, "flood_refused": busy.refused, "flood_ping_ms": ms(flood_pings),
            "refused_rerender": {"size": sizes[0], "status": big[0], "answer": big[1][:160].decode("utf-8", "replace")},
            "rerender": {"size": sizes[1], "status": large[0], "seconds": large[2]}, "rerender_ping_ms": ms(render_pings)}


async def _sigterm(http, url: str, proc: subprocess.Popen) -> float:
    """SIGTERM while a page floods and a re-render runs; seconds until the process ended."""
    page = await Page(http, url).connect()
    work = [asyncio.ensure_future(flood(page, 30.0)), asyncio.ensure_future(page.image(4096))]
    await asyncio.sleep(1.0)
    t0 = time.monotonic()
    proc.send_signal(signal.SIGTERM)
    while proc.poll() is None and time.monotonic() - t0 < 30.0:
        await asyncio.sleep(0.02)
    for w in work:
        w.cancel()
    await asyncio.gather(*work, return_exceptions=True)
    return time.monotonic() - t0


async def _run(clients: int, samples: int, seconds: float, sizes: tuple, progress) -> dict:
    import aiohttp

    with tempfile.TemporaryDirectory() as folder:
        proc, url = start_server(clients, folder)
        try:
            async with aiohttp.ClientSession() as http:
                progress(f"{clients} pages painting at once, {samples} samples each")
                out = {"clients": clients, "samples": samples, **await _bands(http, url, clients, samples)}
                progress(f"pings while a page floods for {seconds:g} s, then asks for re-renders")
                out.update(await _under_load(http, url, seconds, samples, sizes))
                progress("SIGTERM while a page floods and a re-render runs")
                out["sigterm_s"] = await _sigterm(http, url, proc)
                out["exit_code"] = proc.poll()
        finally:
            if proc.poll() is None:
                proc.kill()
            proc.wait()
            proc.stdout.close()
    return out


def run_clients(clients: int = 4, samples: int = 80, seconds: float = 5.0, sizes: tuple = (8192, 4096),
                progress=lambda m: None) -> dict:
    """The measurements of the module's four parts; `sizes`: the re-render beyond the server's
    limit and the one within it, px."""
    return asyncio.run(_run(clients, samples, seconds, sizes, progress))


def table(r: dict) -> str:
    lat = r["latency_ms"]
    rows = [("pages painting at once, samples each", f"{r['clients']}, {r['samples']}"),
            ("pen sample to ink, p50 / p95 / max (worst page)",
             f"{max(x['p50'] for x in lat):.1f} / {max(x['p95'] for x in lat):.1f} / {max(x['max'] for x in lat):.1f} ms"),
            ("inked px outside each page's band (inside)",
             f"{sum(r['outside_px'])} ({', '.join(str(v) for v in r['inside_px'])})"),
            ("ping while another page floods, p50 / p95 / max",
             f"{r['flood_ping_ms']['p50']:.1f} / {r['flood_ping_ms']['p95']:.1f} / {r['flood_ping_ms']['max']:.1f} ms "
             f"({r['flood_ping_ms']['n']} pings; {r['flood_messages']} flood messages, {r['flood_refused']} refused)"),
            (f"re-render {r['refused_rerender']['size']} px",
             f"HTTP {r['refused_rerender']['status']}: {r['refused_rerender']['answer'][:70]}"),
            (f"re-render {r['rerender']['size']} px", f"HTTP {r['rerender']['status']} in {r['rerender']['seconds']:.1f} s"),
            ("ping during the re-renders, p50 / p95 / max",
             f"{r['rerender_ping_ms']['p50']:.1f} / {r['rerender_ping_ms']['p95']:.1f} / "
             f"{r['rerender_ping_ms']['max']:.1f} ms ({r['rerender_ping_ms']['n']} pings)"),
            ("SIGTERM to exit, while flooded and re-rendering", f"{r['sigterm_s']:.2f} s (exit code {r['exit_code']})")]
    w = max(len(a) for a, _ in rows)
    return "\n".join(f"{a:<{w}}  {b}" for a, b in rows)
