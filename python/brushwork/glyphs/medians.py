"""Stroke medians alone: one JSON object a line, {"character": ..., "medians": [[[x, y], ...], ...]},
in Make Me a Hanzi's 1024-unit box (y up, top edge at y = 900), optionally gzipped.

brushwork bundles such a file for 9,574 characters (all of GB2312): the default source's fallback
after its glyph files. A file is read and indexed once per process (character -> its line), and a
character is parsed only when asked for, through the same reader as `mmah:PATH`, so its strokes
and inferred types are those that source gives for the same medians.
"""
from __future__ import annotations

import functools
import gzip
import json
import re
from pathlib import Path
from typing import Iterator

from .mmah import glyph_from_mmah
from .model import Glyph, GlyphError

FILE_NAME = "medians.jsonl.gz"
# the character at the start of a line, when written plainly (anything else goes through json)
_HEAD = re.compile(rb'\{\s*"character"\s*:\s*"([^"\\]+)"')


def bundled_path() -> Path:
    """The medians that ship with brushwork: in the wheel's brushwork/data/glyphs/medians, or the
    repository's glyphs/medians when running from a source tree."""
    here = Path(__file__).resolve().parent.parent           # .../brushwork
    for folder in (here / "data" / "glyphs" / "medians", here.parent.parent / "glyphs" / "medians"):
        if (folder / FILE_NAME).is_file():
            return folder / FILE_NAME
    raise GlyphError("medians", "the bundled medians are missing from this installation")


class MediansFile:
    """A medians file held in memory (its bytes, ~7 MB for the bundled one) with an index
    character -> (first byte, end byte, number) of its line."""

    def __init__(self, path: Path):
        self.path = Path(path)
        try:
            raw = self.path.read_bytes()
            self.data = gzip.decompress(raw) if raw[:2] == b"\x1f\x8b" else raw
        except (OSError, EOFError, gzip.BadGzipFile) as e:
            raise GlyphError(self.path, f"cannot read: {e}") from None
        self.index: dict[str, tuple[int, int, int]] = {}
        self.bad: list[GlyphError] = []          # lines without a readable character
        start = 0
        for n, line in enumerate(self.data.split(b"\n"), 1):
            self._add(line, n, start)
            start += len(line) + 1
        if not self.index:
            raise GlyphError(self.path, 'not a medians file: no line holds {"character": C, "medians": [...]}')

    def _add(self, line: bytes, n: int, start: int) -> None:
        if not line.strip():
            return
        char = self._char_of(line)
        if char is None:
            self.bad.append(GlyphError(f"{self.path}: line {n}", "no \"character\" with one character"))
        else:
            self.index.setdefault(char, (start, start + len(line), n))

    @staticmethod
    def _char_of(line: bytes) -> str | None:
        m = _HEAD.match(line)
        try:
            char = m.group(1).decode("utf-8") if m else json.loads(line).get("character")
        except (UnicodeDecodeError, ValueError, AttributeError, RecursionError):
            return None
        return char if isinstance(char, str) and len(char) == 1 else None

    def chars(self) -> list[str]:
        """The characters of the file, in file order."""
        return list(self.index)

    def glyph(self, char: str) -> Glyph:
        """char's Glyph (strokes in em units, types inferred); GlyphError when the file lacks it
        or its line is bad."""
        if char not in self.index:
            raise GlyphError(self.path, f"no glyph for {char!r} (U+{ord(char):04X})")
        a, b, n = self.index[char]
        where = f"{self.path}: line {n}"
        try:
            doc = json.loads(self.data[a:b])
        except (json.JSONDecodeError, UnicodeDecodeError) as e:
            raise GlyphError(where, f"malformed JSON: {e}") from None
        except RecursionError:
            raise GlyphError(where, "malformed JSON: nested too deeply") from None
        glyph = glyph_from_mmah(doc, None, where, outlines=False)
        glyph.source = f"medians:{self.path}"
        return glyph


@functools.lru_cache(maxsize=8)
def open_medians(path: str) -> MediansFile:
    """The MediansFile at path, read and indexed once per process."""
    return MediansFile(Path(path))


def read_medians(path: Path, wanted: list[str] | None) -> Iterator[tuple[str | None, Glyph | GlyphError]]:
    """(char, Glyph or GlyphError) for the wanted characters that the file has (all of them when
    wanted is None, and then also the errors of lines without a character)."""
    medians = open_medians(str(path))
    if wanted is None:
        yield from ((None, e) for e in medians.bad)
    for char in medians.chars() if wanted is None else wanted:
        if char in medians.index:
            try:
                yield char, medians.glyph(char)
            except GlyphError as e:
                yield char, e
