"""Character sets: GB2312's hanzi, whole or by level, decoded through Python's gb2312 codec, and
charset files (the characters of a text, whitespace ignored)."""
from __future__ import annotations

import os
from pathlib import Path

# built-in charsets: name -> GB2312 level (None: both)
CHARSETS = {"gb2312": None, "gb2312-1": 1, "gb2312-2": 2}
_ROWS = {1: range(0xB0, 0xD8), 2: range(0xD8, 0xF8), None: range(0xB0, 0xF8)}   # first byte of a hanzi
_CELLS = range(0xA1, 0xFF)                                                       # its second byte


def gb2312(level: int | None = None) -> str:
    """GB2312's hanzi in code order: level 1 (3,755, by pinyin), level 2 (3,008, by radical), or
    both (6,763) when level is None."""
    out = []
    for hi in _ROWS[level]:
        for lo in _CELLS:
            try:
                out.append(bytes((hi, lo)).decode("gb2312"))
            except UnicodeDecodeError:
                pass            # the unassigned tail of row 0xD7
    return "".join(out)


def named(name: str) -> str | None:
    """The characters of the built-in charset called name (any case), or None when none is."""
    key = name.lower()
    return gb2312(CHARSETS[key]) if key in CHARSETS else None


def parse_charset(text: str) -> str:
    """The characters of a charset: every non-space character, in order, duplicates dropped."""
    return "".join(dict.fromkeys(c for c in text if not c.isspace()))


def read_charset(path: str | os.PathLike) -> str:
    """A charset file's characters; the names gb2312, gb2312-1 and gb2312-2 are built in."""
    builtin = None if Path(path).exists() else named(str(path))
    if builtin is not None:
        return builtin
    try:
        text = Path(path).read_text(encoding="utf-8")
    except UnicodeDecodeError as err:
        raise ValueError(f"{path}: not UTF-8 text: {err}") from None
    chars = parse_charset(text)
    if not chars:
        raise ValueError(f"{path}: no characters in the charset file")
    return chars
