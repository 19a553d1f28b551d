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
    """Run `await body(painter)` against a fresh app; its result."""
    async def main():
        app = server.make_app(size=(W, H), **app_kw)
        async with TestClient(TestServer(app, host="127.0.0.1")) as client:
            return await body(Client(client, app))
    return asyncio.run(main())


class Client:
    def __init__(self, client, app):
        self.http, self.app, self.ws, self.seq = client, app, None, 0

    async def connect(self):
        self.ws = await self.http.ws_connect("/ws")
        hello = await self.ws.receive_json()
        assert hello["type"] == "hello" and (hello["width"], hello["height"]) == (W, H)
        assert (await self.ws.receive_json())["type"] == "tile"
        return self

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
        r = await self.http.get("/image.png" + query)
        assert r.status == 200 and r.content_type == "image/png"
        return cv2.imdecode(np.frombuffer(await r.read(), np.uint8), cv2.IMREAD_COLOR)

    async def log(self):
        r = await self.http.get("/log.json")
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
        # a frame beyond aiohttp's limit closes that connection only; the painting stays
        await c.ws.send_str("x" * (server.MAX_FRAME + 10))
        closed = await c.ws.receive()
        while closed.type.name == "TEXT":
            closed = await c.ws.receive()
        await c.connect()
        tile, errors = await c.stroke(200, [0.6] * 10)
        return prior, await c.image(), flood_errors, errors, closed

    prior, after, flood_errors, errors, closed = _paint(body)
    assert flood_errors, "a flood is answered with errors"
    assert closed.type.name in ("CLOSE", "CLOSED", "CLOSING")
    assert not errors, "the page still paints"
    ink_prior, ink_after = _ink(prior), _ink(after)
    assert np.abs(ink_after[:160] - ink_prior[:160]).max() < 0.02 and ink_after[180:].sum() > 100


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
