"""`brushwork paint`: the WebSocket protocol and its safety, undo, the motion log and its replay,
the command line, and the page itself in headless Chromium."""
import asyncio
import json
import random
import shutil

import cv2
import numpy as np
import pytest

pytest.importorskip("aiohttp", reason="brushwork paint needs aiohttp (the paint extra)")
from aiohttp.test_utils import TestClient, TestServer  # noqa: E402

from brushwork import cli  # noqa: E402
from brushwork.paint import server  # noqa: E402
from brushwork.paint.replay import read_log, replay  # noqa: E402

W, H = 320, 240          # px of the test paper (5 px/mm: 64 x 48 mm)


def _paint(body, **app_kw):
    """Run `await body(client)` against a fresh app; its result."""
    async def main():
        app = server.make_app(size=(W, H), **app_kw)
        async with TestClient(TestServer(app, host="127.0.0.1")) as client:
            return await body(Client(client, app))
    return asyncio.run(main())


class Client:
    """A page: its WebSocket, and HTTP requests naming its painting once it has one."""

    def __init__(self, client, app):
        self.http, self.app, self.ws, self.seq, self.painting = client, app, None, 0, None

    def another(self):
        """A second page on the same server."""
        return Client(self.http, self.app)

    async def connect(self):
        self.ws = await self.http.ws_connect("/ws")
        hello = await self.ws.receive_json()
        assert hello["type"] == "hello" and (hello["width"], hello["height"]) == (W, H)
        self.painting = hello["painting"]
        assert (await self.ws.receive_json())["type"] == "tile"
        assert (await self.ws.receive_json())["type"] == "view"
        return self

    def named(self, query=""):
        """`query` with this page's painting added."""
        if self.painting is None:
            return query
        return query + ("&" if query else "?") + f"painting={self.painting}"

    async def answer(self, seq):
        """Messages up to the tile answering `seq`: (tile, errors)."""
        errors = []
        while True:
            m = await self.ws.receive_json(timeout=30)
            if m["type"] == "error":
                errors.append(m["message"])
            if m["type"] == "tile" and m["seq"] == seq:
                return m, errors

    async def send(self, msg):
        self.seq += 1
        await self.ws.send_str(json.dumps({**msg, "seq": self.seq}))
        return await self.answer(self.seq)

    async def stroke(self, y, pressures, x0=40.0, x1=280.0, tilt=(20.0, 0.0)):
        n = len(pressures)
        samples = [{"x": x0 + (x1 - x0) * k / (n - 1), "y": y, "pressure": p, "tiltX": tilt[0], "tiltY": tilt[1]}
                   for k, p in enumerate(pressures)]
        for k in range(0, n, 8):
            await self.send({"type": "samples", "samples": samples[k:k + 8]})
        return await self.send({"type": "up"})

    async def image(self, query=""):
        r = await self.http.get("/image.png" + self.named(query))
        assert r.status == 200 and r.content_type == "image/png", await r.text()
        return cv2.imdecode(np.frombuffer(await r.read(), np.uint8), cv2.IMREAD_COLOR)

    async def log(self):
        r = await self.http.get("/log.json" + self.named())
        assert r.status == 200
        return await r.json()


def _ink(bgr):
    """Ink coverage per pixel, 0..1."""
    return 1.0 - bgr.astype(float).mean(axis=2) / 255.0


def test_samples_ink_along_the_path_heavier_where_pressed():
    async def body(c):
        await c.connect()
        tile, errors = await c.stroke(120, [0.25] * 20 + [0.85] * 20)
        return await c.image(), tile, errors

    img, tile, errors = _paint(body)
    assert not errors
    ink = _ink(img)
    band = ink[60:180]
    assert ink[:60].max() < 0.05 and ink[180:].max() < 0.05, "ink only near the path (y = 120)"
    covered = (band > 0.5).any(axis=0)
    assert covered[80:260].all(), "ink all along the stroke"
    light, heavy = band[:, 80:150].sum(), band[:, 180:250].sum()
    assert heavy > 1.3 * light, f"the pressed half carries more ink ({heavy:.0f} against {light:.0f})"
    assert tile["type"] == "tile" and not tile["down"]


def test_tiles_paint_the_pages_image():
    async def body(c):
        await c.connect()
        canvas = np.full((H, W, 3), 255, np.uint8)
        for k in range(12):
            tile, _ = await c.send({"type": "samples", "samples": [
                {"x": 60 + 15 * k, "y": 100 + 3 * k, "pressure": 0.6, "tilt": 15, "azimuth": 0}]})
            if "png" in tile:
                part = cv2.imdecode(np.frombuffer(__import__("base64").b64decode(tile["png"]), np.uint8), 1)
                canvas[tile["y"]:tile["y"] + tile["h"], tile["x"]:tile["x"] + tile["w"]] = part
        return canvas, await c.image()

    canvas, image = _paint(body)
    assert _ink(image).sum() > 100
    assert np.array_equal(canvas, image), "the tiles put together are the paper"


def test_undo_removes_the_last_pen_stroke_and_clear_is_undone():
    async def body(c):
        await c.connect()
        blank = await c.image()
        await c.stroke(70, [0.6] * 16)
        one = await c.image()
        await c.stroke(170, [0.6] * 16)
        two = await c.image()
        await c.send({"type": "undo"})
        undone = await c.image()
        await c.send({"type": "clear"})
        cleared = await c.image()
        await c.send({"type": "undo"})
        return blank, one, two, undone, cleared, await c.image()

    blank, one, two, undone, cleared, back = _paint(body)
    assert (blank == 255).all() and _ink(one).sum() > 100 and _ink(two).sum() > _ink(one).sum() * 1.5
    assert np.array_equal(undone, one), "undo puts back the paper before the last pen stroke"
    assert np.array_equal(cleared, blank) and np.array_equal(back, one), "clear empties; undo brings it back"


def _session_with_everything(c):
    """A painting with strokes, a dip, a change of scene and of brush, undo and clear."""
    async def run():
        await c.connect()
        await c.stroke(60, [0.3, 0.5, 0.7, 0.8, 0.6, 0.4] * 3, tilt=(30.0, -10.0))
        await c.send({"type": "dip", "ink": 0.5, "wetness": 0.6})
        await c.send({"type": "settings", "scene": {"split_map": True, "dry_map": True, "grain": True,
                                                    "depletion": True}})
        await c.stroke(120, [0.7] * 14, x0=260, x1=50)
        await c.stroke(200, [0.5] * 10)
        await c.send({"type": "undo"})
        await c.send({"type": "settings", "preset": "small"})
        await c.send({"type": "samples", "samples": [{"x": 100 + 6 * k, "y": 180 - 4 * k, "pressure": 0.9,
                                                     "tilt": 10, "azimuth": 45, "twist": 30} for k in range(10)]})
        return await c.image(), await c.log()
    return run()


def test_the_log_replays_to_what_the_page_showed(tmp_path):
    image, log = _paint(_session_with_everything)
    names = {ev[0] for ev in log["events"]}
    assert {"pose", "up", "dip", "settings", "undo"} <= names
    path = tmp_path / "log.json"
    path.write_text(json.dumps(log), encoding="utf-8")
    assert cli.main(["replay", str(path), "-o", str(tmp_path / "out.png")]) == 0
    replayed = cv2.imread(str(tmp_path / "out.png"), cv2.IMREAD_COLOR)
    assert _ink(image).sum() > 200
    assert np.array_equal(replayed, image), "replay at the painted size equals the page pixel for pixel"
    # at twice the size: the same picture, finer
    big = replay(read_log(path), size=2 * W).paper.image()
    assert big.shape == (2 * H, 2 * W, 3)
    small = cv2.resize(big, (W, H), interpolation=cv2.INTER_AREA)
    a, b = _ink(small[..., ::-1]), _ink(image)
    assert np.corrcoef(a.ravel(), b.ravel())[0, 1] > 0.9


def test_the_image_endpoint_rerenders_at_a_size():
    async def body(c):
        await c.connect()
        await c.stroke(120, [0.6] * 10)
        big = await c.image("?size=640")
        bad = [(await c.http.get(f"/image.png?size={v}")).status for v in ("9999", "x", "-1")]
        return big, bad

    big, bad = _paint(body)
    assert big.shape == (480, 640, 3) and _ink(big).sum() > 400
    assert bad == [400, 400, 400]


def _junk(rng):
    """A malformed message: random bytes, JSON of the wrong shape, or numbers out of range."""
    kinds = [
        lambda: bytes(rng.getrandbits(8) for _ in range(rng.randint(0, 64))).decode("latin-1"),
        lambda: json.dumps(rng.choice([None, 1, [], "samples", {"type": 3}, {"type": "paint"}])),
        lambda: json.dumps({"type": "samples", "samples": rng.choice([[], "x", [1], [{"x": "a", "y": 1}]])}),
        lambda: json.dumps({"type": "samples", "samples": [{"x": rng.choice([1e9, -1e9]), "y": 10}]}),
        lambda: '{"type": "samples", "samples": [{"x": NaN, "y": 1}]}',
        lambda: json.dumps({"type": "samples", "samples": [{"x": 5, "y": 5, "pressure": rng.choice([2, -1, True])}]}),
        lambda: json.dumps({"type": "samples", "samples": [{"x": 5, "y": 5, "tiltX": 400}]}),
        lambda: json.dumps({"type": "dip", "ink": rng.choice([-1, 3, "full"])}),
        lambda: json.dumps({"type": "settings", "preset": rng.choice(["huge", 7, None])}),
        lambda: json.dumps({"type": "settings", "scene": rng.choice([{"grain": 1}, {"fog": True}, []])}),
        lambda: json.dumps({"type": "undo", "seq": rng.choice([-1, "a", 1.5, 2 ** 60])}),
        lambda: json.dumps({"type": "samples", "samples": [{"x": 1, "y": 1}] * 300}),
        lambda: "[" * 50000,
        lambda: json.dumps({"type": "samples", "samples": [{"x": 1, "y": 1, "pad": "x" * 70000}]}),
    ]
    return rng.choice(kinds)()


def test_malformed_oversized_and_flooding_messages_are_refused_and_harm_nothing():
    async def body(c):
        await c.connect()
        await c.stroke(120, [0.6] * 10)
        prior, log_prior = await c.image(), await c.log()
        rng = random.Random(7)
        for _ in range(300):
            await c.ws.send_str(_junk(rng))
        await c.ws.send_bytes(b"\x00\x01binary")
        refused = 0
        while refused < 301:
            m = await c.ws.receive_json(timeout=30)
            refused += m["type"] == "error"
        assert await c.log() == log_prior, "refused messages leave no trace in the painting"
        # a flood: more messages than the rate allows are refused, not queued
        for _ in range(1500):
            await c.ws.send_str(json.dumps({"type": "samples", "samples": [{"x": 300, "y": 235, "pressure": 0}]}))
        await asyncio.sleep(1.0)          # (the rate's budget refills)
        tile, errors = await c.send({"type": "dip"})
        flood_errors = [e for e in errors if "too many" in e]
        # a frame beyond aiohttp's limit closes that connection and its painting only
        other = await c.another().connect()
        await other.stroke(60, [0.6] * 10)
        others = await other.image()
        await c.ws.send_str("x" * (server.MAX_FRAME + 10))
        closed = await c.ws.receive()
        while closed.type.name == "TEXT":
            closed = await c.ws.receive()
        gone = (await c.http.get("/image.png" + c.named())).status
        tile, errors = await other.stroke(200, [0.6] * 10)
        return prior, others, await other.image(), flood_errors, errors, closed, gone

    prior, others, after, flood_errors, errors, closed, gone = _paint(body)
    assert _ink(prior).sum() > 100
    assert flood_errors, "a flood is answered with errors"
    assert closed.type.name in ("CLOSE", "CLOSED", "CLOSING") and gone == 404
    assert not errors, "the other page still paints"
    ink_prior, ink_after = _ink(others), _ink(after)
    assert np.abs(ink_after[:160] - ink_prior[:160]).max() < 0.02 and ink_after[180:].sum() > 100


def _band(img, y, half=50):
    """Ink of `img` outside rows y - half .. y + half."""
    ink = _ink(img)
    return ink[:max(y - half, 0)].sum() + ink[y + half:].sum()


def test_each_page_paints_its_own_painting_at_the_same_time():
    """Three pages drawing at once in their own bands: each painting holds its own strokes and no
    other ink; one page's undo, clear and pen lift act on its painting alone."""
    bands = (50, 120, 190)

    async def body(c):
        pages = [c] + [c.another() for _ in bands[1:]]
        for p in pages:
            await p.connect()
        assert len({p.painting for p in pages}) == len(pages)
        await asyncio.gather(*(p.stroke(y, [0.6] * 24) for p, y in zip(pages, bands)))
        first = await pages[0].image()
        await asyncio.gather(*(p.stroke(y + 8, [0.8] * 16, x0=60, x1=250, tilt=(0, 30)) for p, y in zip(pages, bands)))
        await pages[0].send({"type": "undo"})
        await pages[1].send({"type": "clear"})
        unnamed = await c.http.get("/image.png")
        unknown = await c.http.get("/image.png?painting=feedbeef")
        return first, [await p.image() for p in pages], (unnamed.status, await unnamed.text()), unknown.status

    first, images, unnamed, unknown = _paint(body)
    assert _band(images[0], bands[0]) == 0.0 and _band(images[2], bands[2]) == 0.0, "no ink outside a page's band"
    assert _ink(first).sum() > 100 and np.array_equal(images[0], first), "the first page's undo took its own stroke"
    assert not np.array_equal(images[2][:, :, 0], first[:, :, 0]) and _ink(images[2]).sum() > 100
    assert _ink(images[1]).max() == 0.0, "the second page's clear emptied its own painting only"
    assert unnamed[0] == 400 and "painting" in unnamed[1] and unknown == 404


def _zigzag(n, far):
    """n samples alternating between (20, 20) and (20 + far, 20 + far) px at full pressure."""
    return [{"x": 20 + far * (k % 2), "y": 20 + far * (k % 2), "pressure": 1.0} for k in range(n)]


def test_pings_are_answered_while_another_page_floods_its_painter():
    """The event loop does no painting: a ping sent after another page's heaviest admissible work
    is answered before that work's tile; a message asking for more frames than the budget is
    refused with an error, not queued."""
    import time

    async def next_of(ws, kind):
        m = await ws.receive_json(timeout=60)
        while m["type"] == "view":
            m = await ws.receive_json(timeout=60)
        assert m["type"] == kind, m
        return m, time.monotonic()

    async def body(c):
        await c.connect()
        other = await c.another().connect()
        await c.ws.send_str(json.dumps({"type": "samples", "samples": _zigzag(250, 280)}))
        refused, _ = await next_of(c.ws, "error")
        await c.ws.send_str(json.dumps({"type": "samples", "seq": 1, "samples": _zigzag(140, 60)}))
        await other.ws.send_str(json.dumps({"type": "ping", "seq": 5}))
        (pong, t_pong), (tile, t_tile) = await asyncio.gather(next_of(other.ws, "pong"), next_of(c.ws, "tile"))
        return refused, pong, tile, t_pong < t_tile

    refused, pong, tile, pong_first = _paint(body)
    assert "simulated frames" in refused["message"], refused
    assert pong == {"type": "pong", "seq": 5} and tile["seq"] == 1 and "png" in tile
    assert pong_first, "the ping is answered while the other painting works"


def test_rerenders_keep_to_their_budget_and_stop_when_cancelled(monkeypatch):
    import threading

    from brushwork.paint.replay import Cancelled

    async def body(c):
        await c.connect()
        await c.stroke(120, [0.6] * 10)
        sizes = {}
        for v in ("abc", "8192", "1e3", "-5", "9" * 400):
            r = await c.http.get("/image.png" + c.named(f"?size={v}"))
            sizes[v] = (r.status, await r.text())
        monkeypatch.setattr(server, "RERENDER_MAX_FRAMES", 5)
        big = await c.http.get("/image.png" + c.named("?size=320"))
        return sizes, (big.status, await big.text()), await c.log()

    sizes, big, log = _paint(body)
    for v, (status, text) in sizes.items():
        assert status == 400 and text.startswith("size = ") and len(text) < 200, (v, text)
    assert "4096" in sizes["8192"][1] and "brushwork replay" in sizes["8192"][1]
    assert big[0] == 413 and "frames" in big[1]
    stop = threading.Event()
    stop.set()
    with pytest.raises(Cancelled):
        replay(log, 640, cancel=stop)


def test_the_host_is_checked_against_the_served_address():
    """DNS rebinding: a page on another name that resolves to 127.0.0.1 is refused, on every path."""
    async def body(c):
        statuses = {}
        for host in ("evil.example", "evil.example:80", "localhost:1", "127.0.0.1", "[::1]:80", "paint.example"):
            statuses[host] = [(await c.http.get(p, headers={"Host": host})).status for p in ("/", "/log.json", "/ws")]
        return statuses

    got = _paint(body, allow_hosts=("paint.example",))
    assert got["evil.example"] == got["evil.example:80"] == [403, 403, 403]
    for host in ("localhost:1", "127.0.0.1", "[::1]:80", "paint.example"):
        assert got[host][0] == 200 and 403 not in got[host], (host, got[host])


def test_undo_keeps_a_bounded_number_of_bytes():
    from brushwork.paint.painting import UNDO_BYTES, Painting

    p = Painting({"width_mm": 204.8, "height_mm": 204.8, "px_per_mm": 5.0})   # 1024 x 1024 px: 16 MiB
    full = p.paper.width_px * p.paper.height_px * 16
    kept = []
    for k in range(25):
        for x in (40.0 + 4 * k, 60.0 + 4 * k):
            p.apply(p.sample_pose(x, 500.0, 0.7, 10.0, 0.0, 0.0))
        p.apply(["up"])
        kept.append(p.image())
        p.apply(["clear"])
        assert p.undo_bytes() <= max(UNDO_BYTES, full)
    clears = [kept for _, kept in p.undo_stack if kept.nbytes == full]
    assert 2 <= len(clears) <= UNDO_BYTES // full < 25, "the newest clears are kept, as many as the bytes allow"
    p.apply(["undo"])
    assert np.array_equal(p.image(), kept[-1]) and _ink(kept[-1]).sum() > 100, "the last clear is undone"


def test_log_names_never_collide(tmp_path):
    """Logs made in the same second by two servers (or two paintings) get names of their own."""
    from brushwork.paint.connection import create_log

    (tmp_path / "paint-20260101-000000-abcd.json").write_text("{}", encoding="utf-8")
    names = [create_log(str(tmp_path), "20260101-000000", "abcd") for _ in range(3)]
    assert len(set(names)) == 3 and (tmp_path / "paint-20260101-000000-abcd.json").read_text() == "{}"

    async def body(c):
        await c.connect()
        other = await c.another().connect()
        await c.stroke(60, [0.5] * 6)
        await other.stroke(160, [0.5] * 6)
    _paint(body, log_dir=str(tmp_path))
    logs = sorted(tmp_path.glob("paint-2*.json"))
    assert len(logs) == 6 and all(read_log(p)["events"] for p in logs if "abcd" not in p.name)


def test_malformed_values_are_short_errors_never_tracebacks():
    async def token(c):
        return (await c.http.get("/image.png?token=%C3%A9t%C3%A9-s3cret")).status

    async def body(c):
        await c.connect()
        texts = ['{"type": "samples", "samples": [{"x": 1' + "0" * 400 + ', "y": 1}]}',
                 '{"type": "samples", "samples": [{"x": ' + "9" * 5000 + ', "y": 1}]}',
                 '{"type": "dip", "ink": ' + "7" * 400 + '}',
                 '{"type": "settings", "preset": "' + "p" * 5000 + '"}',
                 '{"type": "' + "t" * 5000 + '"}',
                 '{"type": "undo", "seq": ' + "1" * 400 + '}']
        errors = []
        for text in texts:
            await c.ws.send_str(text)
            m = await c.ws.receive_json(timeout=30)
            errors.append(m)
        tile, more = await c.stroke(120, [0.6] * 6)
        return errors, tile, more

    assert _paint(token, token="s3cret-token") == 403, "a token of any characters is compared, not a 500"
    errors, tile, more = _paint(body)
    assert all(m["type"] == "error" and len(m["message"]) < 160 for m in errors), errors
    assert "png" in tile and not more, "the connection paints on"


def test_a_token_guards_every_request_and_other_sites_are_refused():
    async def body(c):
        no = [(await c.http.get(p)).status for p in ("/", "/image.png", "/log.json", "/ws")]
        yes = [(await c.http.get(p + "?token=s3cret-token")).status for p in ("/", "/static/paint.js")]
        cross = await c.http.get("/ws?token=s3cret-token", headers={"Origin": "http://evil.example"})
        return no, yes, cross.status

    no, yes, cross = _paint(body, token="s3cret-token")
    assert no == [403] * 4 and yes == [200, 200] and cross == 403


@pytest.mark.parametrize("argv, says", [
    (["replay", "{tmp}/missing.json", "-o", "{tmp}/o.png"], "missing.json"),
    (["replay", "{tmp}/bad.json", "-o", "{tmp}/o.png"], "not a JSON log"),
    (["replay", "{tmp}/event.json", "-o", "{tmp}/o.png"], "event"),
    (["replay", "{tmp}/deep.json", "-o", "{tmp}/o.png"], "nested too deeply"),
    (["replay", "{tmp}/event.json", "-o", "{tmp}/o.png", "--size", "9000"], "--size"),
    (["replay", "{tmp}/good.json", "-o", "{tmp}/o.xyz"], "o.xyz"),
    (["paint", "--host", "0.0.0.0"], "--token"),
    (["paint", "--size", "10", "10"], "--size"),
    (["paint", "--preset", "huge"], "preset"),
    (["paint", "--port", "70000"], "--port"),
    (["bench", "paint", "--samples", "1"], "--samples"),
])
def test_command_line_errors_are_one_line(tmp_path, capsys, argv, says):
    (tmp_path / "bad.json").write_text("{not json", encoding="utf-8")
    (tmp_path / "deep.json").write_text("[" * 100000, encoding="utf-8")
    good = {"format": "brushwork-paint", "version": 1, "events": [],
            "settings": {"width_mm": 20, "height_mm": 20, "px_per_mm": 2}}
    (tmp_path / "good.json").write_text(json.dumps(good), encoding="utf-8")
    (tmp_path / "event.json").write_text(json.dumps({**good, "events": [["pose", 1, 2]]}), encoding="utf-8")
    rc = cli.main([a.format(tmp=tmp_path) for a in argv])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and err.startswith("brushwork: error:") and says in err, err
    assert not (tmp_path / "o.png").exists() and not (tmp_path / "o.xyz").exists()


# --- the page in headless Chromium

STROKE_JS = """
const [pts, done] = [arguments[0], arguments[arguments.length - 1]];
const c = document.getElementById("paper"), r = c.getBoundingClientRect();
const ev = (type, p) => new PointerEvent(type, {bubbles: true, cancelable: true, pointerId: 7,
  pointerType: "pen", isPrimary: true, button: type === "pointermove" ? -1 : 0,
  buttons: type === "pointerup" ? 0 : 1, clientX: r.left + p[0] * r.width / c.width,
  clientY: r.top + p[1] * r.height / c.height, pressure: p[2], tiltX: p[3], tiltY: p[4], twist: p[5]});
c.dispatchEvent(ev("pointerdown", pts[0]));
for (const p of pts.slice(1)) c.dispatchEvent(ev("pointermove", p));
c.dispatchEvent(ev("pointerup", pts[pts.length - 1]));
const wait = () => window.paint.drawnSeq >= window.paint.seq ? done(window.paint.seq) : setTimeout(wait, 20);
wait();
"""
WAIT_JS = """
const done = arguments[arguments.length - 1];
const wait = () => window.paint.drawnSeq >= window.paint.seq ? done(window.paint.seq) : setTimeout(wait, 20);
wait();
"""


@pytest.fixture
def page(tmp_path):
    """(driver, url, log folder): `brushwork paint` in a process of its own, its page in Chromium."""
    webdriver = pytest.importorskip("selenium.webdriver", reason="the page test needs selenium (the paint extra)")
    for tool in ("chromium", "chromedriver"):
        if shutil.which(tool) is None:
            pytest.skip(f"the page test needs {tool} (Debian: apt-get install chromium chromium-driver)")
    import os
    import subprocess
    import sys

    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    proc = subprocess.Popen([sys.executable, "-m", "brushwork", "paint", "--port", "0", "--size", "480", "320",
                             "--log-dir", str(tmp_path)], env=env, stdout=subprocess.PIPE, text=True)
    url = proc.stdout.readline().split()[2]
    opts = webdriver.ChromeOptions()
    opts.binary_location = shutil.which("chromium")
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1100,620"):
        opts.add_argument(a)
    driver = webdriver.Chrome(service=webdriver.ChromeService(executable_path=shutil.which("chromedriver")),
                              options=opts)
    driver.set_script_timeout(60)
    try:
        driver.get(url)
        driver.execute_async_script("""const done = arguments[0];
            const wait = () => window.paint.ws && document.getElementById("paper").width === 480 ?
              done() : setTimeout(wait, 20);
            wait();""")
        yield driver, url, tmp_path
    finally:
        driver.quit()
        proc.terminate()
        proc.wait(timeout=30)
        proc.stdout.close()


def _canvas(driver):
    url = driver.execute_script('return document.getElementById("paper").toDataURL("image/png")')
    import base64

    return cv2.imdecode(np.frombuffer(base64.b64decode(url.split(",", 1)[1]), np.uint8), cv2.IMREAD_COLOR)


def _pen(x0, x1, y, pressure, tilt=(25, -10), n=40, wave=0.0):
    return [[x0 + (x1 - x0) * k / (n - 1), y + wave * np.sin(6.3 * k / (n - 1)), p, tilt[0], tilt[1], 0]
            for k, p in enumerate(np.broadcast_to(pressure, (n,)).tolist())]


def test_the_page_paints_with_a_pen_undoes_and_its_log_replays(page):
    driver, url, folder = page
    driver.execute_async_script(STROKE_JS, _pen(60, 420, 90, 0.3))
    driver.execute_async_script(STROKE_JS, _pen(60, 420, 200, 0.8))
    two = _ink(_canvas(driver))
    light, heavy = two[50:130, 100:380], two[150:250, 100:380]
    assert (light > 0.5).any(axis=0).all() and (heavy > 0.5).any(axis=0).all(), "ink along both paths"
    assert heavy.sum() > 1.5 * light.sum(), "heavier where the pen pressed harder"
    driver.find_element("id", "undo").click()
    driver.execute_async_script(WAIT_JS)
    one = _ink(_canvas(driver))
    assert one[150:250].max() < 0.05 and np.array_equal(one[:130], two[:130]), "undo removes the last stroke"
    # the paper's dry map and grain on, a swelling wave across the page
    for flag in ("dry_map", "grain"):
        driver.find_element("id", f"flag-{flag}").click()
    driver.execute_async_script(STROKE_JS, _pen(40, 440, 220, np.sin(np.linspace(0.3, 2.8, 60)) * 0.9,
                                                tilt=(30, 10), n=60, wave=40.0))
    shown = _canvas(driver)
    import os
    import urllib.request

    log = folder / "page-log.json"
    log.write_bytes(urllib.request.urlopen(url.replace("/?", "/log.json?") if "?" in url else url + "log.json").read())
    replayed = replay(read_log(log)).paper.image()[..., ::-1]
    assert _ink(shown)[150:].sum() > 200 and np.array_equal(replayed, shown), "the log replays to the page's image"
    assert [p.name for p in folder.glob("paint-*.json")], "the motion log is written to --log-dir"
    shot = os.environ.get("BRUSHWORK_SCREENSHOT")
    driver.execute_script("window.scrollTo(0, 0)")
    import time

    time.sleep(0.3)                            # (the brush view's last image)
    driver.save_screenshot(shot or str(folder / "page.png"))


def test_the_pages_tuft_count_reaches_the_brush_and_the_log(page):
    """The Brush box's tufts menu splits the brush: the change is a settings event in the log, and
    the log of a stroke painted with it replays to the page's image."""
    import urllib.request

    driver, url, folder = page
    options = driver.find_elements("css selector", "#tufts option")
    assert [o.get_attribute("value") for o in options] == [str(k) for k in range(1, 10)]
    options[4].click()                                  # 5 tufts: the main one and four children
    driver.execute_async_script(WAIT_JS)
    driver.execute_async_script(STROKE_JS, _pen(60, 420, 160, 0.9))
    shown = _canvas(driver)
    log = folder / "tufts-log.json"
    log.write_bytes(urllib.request.urlopen(url.replace("/?", "/log.json?") if "?" in url else url + "log.json").read())
    doc = read_log(log)
    assert ["settings", {"tufts": 5}] in doc["events"]
    assert _ink(shown).sum() > 200 and np.array_equal(replay(doc).paper.image()[..., ::-1], shown)


def test_a_port_in_use_is_one_line_and_leaves_no_log(tmp_path, capsys):
    import socket

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        rc = cli.main(["paint", "--port", str(port), "--log-dir", str(tmp_path)])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and err.startswith("brushwork: error:"), err
    assert list(tmp_path.iterdir()) == [], "no log of a server that never served"


def test_sigterm_ends_the_server_while_it_works_and_logs_go_to_the_data_folder(tmp_path):
    """With no --log-dir the logs go to brushwork's folder in the user's data directory (printed);
    SIGTERM while one page floods its painter and asks for a large re-render still ends the
    server, each painting's log written."""
    import os
    import signal
    import subprocess
    import sys
    import time

    import aiohttp

    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path), XDG_DATA_HOME=str(tmp_path / "data"))
    proc = subprocess.Popen([sys.executable, "-m", "brushwork", "paint", "--port", "0", "--size", "640", "480"],
                            env=env, stdout=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline()
        url, folder = line.split()[2], tmp_path / "data" / "brushwork" / "paint"
        assert str(folder) in line and folder.is_dir(), line

        async def work():
            async with aiohttp.ClientSession() as http:
                ws = await http.ws_connect(url + "ws")
                hello = await ws.receive_json()
                strokes = [{"type": "samples", "seq": k, "samples": _zigzag(140, 60)} for k in range(3)]
                for msg in strokes:
                    await ws.send_str(json.dumps(msg))
                image = asyncio.ensure_future(http.get(f"{url}image.png?size=4096&painting={hello['painting']}"))
                await asyncio.sleep(1.5)
                t0 = time.monotonic()
                proc.send_signal(signal.SIGTERM)
                while proc.poll() is None and time.monotonic() - t0 < 15:
                    await asyncio.sleep(0.05)
                image.cancel()
                return proc.poll()

        rc = asyncio.run(work())
    finally:
        proc.kill()
        proc.wait()
        proc.stdout.close()
    assert rc is not None, "the server ended after SIGTERM"
    logs = list(folder.glob("paint-*.json"))
    assert len(logs) == 1 and read_log(logs[0])["events"], "the painting's log is written on the way out"


def test_the_load_benchmark_keeps_each_page_to_its_band():
    """`bench paint --clients` at a tiny size: each page's painting holds ink in its band only, the
    pings are answered through a flood and a re-render, an oversized re-render is refused, and
    SIGTERM ends the server."""
    from brushwork.paint.load import run_clients, table

    r = run_clients(clients=3, samples=12, seconds=0.5, sizes=(8192, 320))
    assert r["outside_px"] == [0, 0, 0] and min(r["inside_px"]) > 100, r
    assert r["flood_ping_ms"]["n"] > 0 and r["rerender_ping_ms"]["n"] > 0
    assert r["refused_rerender"]["status"] == 400 and r["rerender"]["status"] == 200
    assert r["exit_code"] is not None and "SIGTERM" in table(r)


def test_the_latency_benchmark_measures_its_painting():
    """`bench paint` on a short stroke: every sample is answered, with ink, and the painting it
    reads the simulated frames from is the connection's own (frames counted, none left over from the
    warm-up stroke). Its timings are the bench's to report, not asserted here."""
    from brushwork.paint.bench import run, table

    r = run(n=8, tufts=(1,))
    assert r["samples"] == 8 and r["inked_samples"] == 8, r
    assert r["frames"] > 0 and r["frames"] < 8 * 50, r
    assert "1 tuft at most" in table(r)
