"""A line of text set in a web font by headless Chromium (through Selenium and chromedriver),
and the same line rasterised by FreeType, for comparing the two.

    python -m brushwork.font.browser FONT.woff2 TEXT OUT.png [--px 128]

writes Chromium's screenshot of TEXT set in FONT, one em of `px` pixels per character."""
from __future__ import annotations

import base64
import os
import shutil
import sys

import numpy as np

from .outline import Em
from .web import MARGIN_PX

CHROMIUM = ("chromium", "chromium-browser", "google-chrome")
DRIVER = ("chromedriver",)


def find_chromium() -> tuple:
    """(browser path, chromedriver path), or None for either that is not on PATH."""
    browser = next((p for p in map(shutil.which, CHROMIUM) if p), None)
    driver = next((p for p in map(shutil.which, DRIVER) if p), None)
    return browser, driver


def _page(font_path: str, text: str, px: int) -> str:
    with open(font_path, "rb") as f:
        data = base64.b64encode(f.read()).decode()
    return ("<!doctype html><html><head><meta charset='utf-8'><style>"
            f"@font-face{{font-family:BrushworkTest;src:url(data:font/woff2;base64,{data}) format('woff2')}}"
            "html,body{margin:0;background:#fff}"
            f"div{{font-family:BrushworkTest;font-size:{px}px;line-height:{px}px;color:#000;white-space:nowrap;"
            f"position:absolute;left:{MARGIN_PX}px;top:{MARGIN_PX}px}}"
            f"</style></head><body><div>{text}</div></body></html>")


def chromium_shot(url: str, w: int, h: int, script: str = "return null") -> tuple:
    """(the top-left (h, w, 3) uint8 RGB of Chromium's screenshot of the page at url once its
    fonts are ready, what `script` returns run in the page then). RuntimeError when Chromium or
    its driver is missing."""
    import cv2
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    browser, driver_path = find_chromium()
    if not browser or not driver_path:
        raise RuntimeError("headless Chromium needs chromium and chromedriver on PATH")
    opts = webdriver.ChromeOptions()
    opts.binary_location = browser
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                "--force-device-scale-factor=1", f"--window-size={max(w, 800)},{max(h, 600)}",
                "--disable-dev-shm-usage"):
        opts.add_argument(arg)
    drv = webdriver.Chrome(service=Service(driver_path), options=opts)
    try:
        drv.get(url)
        drv.execute_async_script("const done = arguments[arguments.length - 1]; document.fonts.ready.then(done)")
        png = drv.get_screenshot_as_png()
        found = drv.execute_script(script)
    finally:
        drv.quit()
    bgr = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
    return np.ascontiguousarray(bgr[:h, :w, ::-1]), found


def chromium_line(font_path: str | os.PathLike, text: str, px: int = 128) -> np.ndarray:
    """(px + 2 MARGIN_PX, len(text) px + 2 MARGIN_PX, 3) uint8 RGB: Chromium's screenshot of text
    set in the font at font_path (a WOFF2), px pixels to the em, the line's box MARGIN_PX from the
    top-left corner. RuntimeError when Chromium or its driver is missing."""
    url = "data:text/html;charset=utf-8;base64," + base64.b64encode(
        _page(os.fspath(font_path), text, px).encode()).decode()
    return chromium_shot(url, len(text) * px + 2 * MARGIN_PX, px + 2 * MARGIN_PX)[0]


def css_baseline(font_path: str | os.PathLike, px: int) -> float:
    """px below the top of a line box px high (line-height equal to the font size) where a browser
    puts the baseline of the font at font_path: its hhea ascent and descent each rounded to whole
    pixels, the half-leading (what the line box has over their sum, halved) floored."""
    from fontTools.ttLib import TTFont

    with TTFont(os.fspath(font_path), lazy=True) as font:
        scale = px / font["head"].unitsPerEm
        ascent, descent = round(font["hhea"].ascent * scale), round(-font["hhea"].descent * scale)
    return float(ascent + (px - ascent - descent) // 2)


def freetype_line(font_path: str | os.PathLike, text: str, px: int = 128, wght: float | None = None) -> np.ndarray:
    """(px, len(text) px) float coverage: text rasterised by FreeType (of a variable font, at the
    instance wght), each character's em square a px x px cell, side by side (the layout of one em
    advance per glyph), the baseline where a browser puts it (css_baseline)."""
    from .check import freetype_coverage

    em = Em(size=px)
    baseline = css_baseline(font_path, px)
    return np.concatenate([freetype_coverage(font_path, c, em, baseline, wght) for c in text], axis=1)


def picture_main(prog: str, description: str, draw, argv: list | None = None, more=None) -> int:
    """The command line of a picture of a line set in a font: FONT TEXT OUTPUT [--px N] and what
    more(parser) adds; draw(args) -> (H, W, 3) uint8 BGR is written to OUTPUT. Bad input: one
    line on stderr, exit code 2."""
    import argparse

    from ..files import write_image

    p = argparse.ArgumentParser(prog=prog, description=description)
    p.add_argument("font")
    p.add_argument("text")
    p.add_argument("output")
    p.add_argument("--px", type=int, default=128)
    if more is not None:
        more(p)
    args = p.parse_args(argv)
    try:
        print(f"wrote {write_image(args.output, np.ascontiguousarray(draw(args)))}")
    except (OSError, ValueError, RuntimeError) as err:
        print(f"brushwork: error: {' '.join(str(err).split())}", file=sys.stderr)
        return 2
    return 0


def main(argv: list | None = None) -> int:
    return picture_main("python -m brushwork.font.browser", __doc__.splitlines()[0],
                        lambda a: chromium_line(a.font, a.text, a.px)[..., ::-1], argv)


if __name__ == "__main__":
    sys.exit(main())
