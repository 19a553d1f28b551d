"""Fuzzing the files brushwork reads beyond glyphs and styles: meshes (OBJ, PLY, STL, OFF bytes),
font cache entries, outline style files, and JSON nested far too deep wherever JSON is read.
Each generator takes a `random.Random` and returns one input; each check says why the input broke
the contract (a traceback, a multi-line error, a hang, a cache entry trusted), or None."""
from __future__ import annotations

import json
import random
import struct
import warnings
from pathlib import Path

from .fuzzcheck import ODD_VALUES, _load_only

MESH_SUFFIXES = (".obj", ".ply", ".stl", ".off")


# --- meshes ---
def _tetra(rng: random.Random) -> tuple[list, list]:
    """A tetrahedron's vertices and faces, a coordinate or an index sometimes made odd."""
    v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    f = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]
    for _ in range(rng.randrange(3)):
        if rng.random() < 0.5:
            v[rng.randrange(4)][rng.randrange(3)] = rng.choice([float("nan"), float("inf"), 1e300, -1e30, 5.0])
        else:
            f[rng.randrange(4)][rng.randrange(3)] = rng.choice([-1, -5, 4, 99999, 2 ** 31 - 1, 2 ** 40])
    return v, f


def _rows(v: list, f: list, face: str, one_based: bool = False) -> str:
    k = 1 if one_based else 0
    return "".join(f"{x} {y} {z}\n" for x, y, z in v) + "".join(face.format(a + k, b + k, c + k) for a, b, c in f)


def _obj(v: list, f: list) -> bytes:
    return "".join(f"v {x} {y} {z}\n" for x, y, z in v).encode() + _rows([], f, "f {} {} {}\n", True).encode()


def _off(v: list, f: list) -> bytes:
    return (f"OFF\n{len(v)} {len(f)} 0\n" + _rows(v, f, "3 {} {} {}\n")).encode()


def _ply(v: list, f: list) -> bytes:
    head = (f"ply\nformat ascii 1.0\nelement vertex {len(v)}\nproperty float x\nproperty float y\nproperty float z\n"
            f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n")
    return (head + _rows(v, f, "3 {} {} {}\n")).encode()


def _stl(v: list, f: list) -> bytes:
    tris = [[v[i] if 0 <= i < len(v) else [0.0, 0.0, 0.0] for i in face] for face in f]
    # (binary STL holds 32-bit floats: a value beyond them is written as infinity)
    coords = [[c if abs(c) < 3e38 else float("inf") for p in t for c in p] for t in tris]
    return b"\0" * 80 + struct.pack("<I", len(tris)) + b"".join(struct.pack("<12fH", 0, 0, 0, *c, 0) for c in coords)


_WRITERS = {".obj": _obj, ".off": _off, ".ply": _ply, ".stl": _stl}


def mesh_bytes(rng: random.Random) -> tuple[str, bytes]:
    """(suffix, bytes) of a mesh file: a small mesh, damaged or not, cut short, bytes flipped, or
    random bytes."""
    suffix = rng.choice(MESH_SUFFIXES)
    data = _WRITERS[suffix](*_tetra(rng))
    how = rng.randrange(5)
    if how == 1:
        data = data[:rng.randrange(len(data) + 1)]
    elif how == 2:
        data = bytearray(data)
        for _ in range(rng.randrange(1, 8)):
            data[rng.randrange(len(data))] = rng.randrange(256)
        data = bytes(data)
    elif how == 3:
        data = bytes(rng.randrange(256) for _ in range(rng.randrange(200)))
    return suffix, data


def check_mesh(suffix: str, data: bytes, folder: Path) -> str | None:
    """A mesh file: load_mesh ends in a mesh or a one-line ValueError naming the file."""
    from ..outline3d.meshfile import load_mesh

    path = folder / f"m{suffix}"
    path.write_bytes(data)

    def load():
        try:
            with warnings.catch_warnings():      # (numpy's on a degenerate triangle's normal)
                warnings.simplefilter("ignore", RuntimeWarning)
                load_mesh(path)
        except ValueError as err:
            if str(path) not in str(err):
                raise AssertionError(f"the error does not name the file: {err}") from None
            raise
    return _load_only(load, ValueError)


# --- font cache entries ---
def cache_text(rng: random.Random) -> str:
    """A font cache file: contours of cubic segments, valid, damaged, of the wrong shape or not JSON."""
    contours = [[[[rng.uniform(0, 1000), rng.uniform(0, 1000)] for _ in range(4)] for _ in range(rng.randrange(1, 4))]
                for _ in range(rng.randrange(0, 3))]
    how = rng.randrange(5)
    if how == 1 and contours and contours[0]:
        contours[0][0][rng.randrange(4)][rng.randrange(2)] = rng.choice(ODD_VALUES)
    elif how == 2:
        return json.dumps(rng.choice(ODD_VALUES + [[[]], [[[1, 2, 3]]], {"a": 1}]))
    elif how == 3:
        text = json.dumps(contours)
        return text[:rng.randrange(len(text) + 1)]
    return json.dumps(contours)


def check_cache(text: str, folder: Path) -> str | None:
    """A cache entry is read as an outline only when it is one; anything else is None (made again)."""
    import numpy as np

    from ..font.make import MAX_UNITS, load_outline

    path = folder / "U+4E00-0.json"
    path.write_text(text, encoding="utf-8")
    try:
        got = load_outline(path)
    except Exception as exc:  # noqa: BLE001 - a traceback is what the fuzz looks for
        return f"traceback: {type(exc).__name__}: {exc!s:.200}"
    if got is not None and not (got and all(len(c) and np.isfinite(c).all() and np.abs(c).max() <= MAX_UNITS
                                            for c in got)):
        return "a damaged cache entry was trusted"
    return None


# --- outline style files ---
def outline_style_text(rng: random.Random) -> str:
    """An outline style file: a bundled one with a field changed to an odd value, or cut short."""
    from .. import outline3d

    folder = Path(outline3d.__file__).with_name("styles")
    names = sorted(p.name for p in folder.glob("*.json"))
    doc = json.loads((folder / rng.choice(names)).read_text(encoding="utf-8"))
    if rng.random() < 0.8:
        doc[rng.choice(list(doc) + ["extra"])] = rng.choice(ODD_VALUES)
    text = json.dumps(doc)
    return text[:rng.randrange(len(text) + 1)] if rng.random() < 0.1 else text


def check_outline_style(text: str, folder: Path) -> str | None:
    """OutlineStyle.load (its public loader) ends in a style or a one-line ValueError."""
    from ..outline3d import OutlineStyle

    path = folder / "outline-style.json"
    path.write_text(text, encoding="utf-8")
    return _load_only(lambda: OutlineStyle.load(str(path)), ValueError)


# --- JSON nested too deeply, wherever JSON is read ---
def _readers(folder: Path) -> dict:
    """name -> (file name, load(path), the error it may end in) for every reader of JSON."""
    from ..font.make import load_outline
    from ..glyphs import GlyphError, load_glyph
    from ..glyphs.medians import MediansFile
    from ..glyphs.mmah import read_char_file, read_graphics
    from ..outline3d import OutlineStyle
    from ..paint.replay import read_log
    from ..writing import Style, StyleError

    def cache(p):
        if load_outline(p) is not None:
            raise AssertionError("a nested cache entry was trusted")

    def medians(p):
        m = MediansFile(p)
        for c in m.chars():
            m.glyph(c)

    return {"glyph": ("U+4E00.json", load_glyph, GlyphError), "style": ("s.json", lambda p: Style.load(str(p)), StyleError),
            "outline style": ("o.json", lambda p: OutlineStyle.load(str(p)), ValueError),
            "paint log": ("log.json", read_log, ValueError), "font cache": ("U+4E00-0.json", cache, ValueError),
            "medians": ("medians.txt", medians, GlyphError), "mmah graphics": ("graphics.txt",
                                                                           lambda p: list(read_graphics(p, None)), GlyphError),
            "mmah char": ("一.json", lambda p: read_char_file(p, "一"), GlyphError)}


def nested_json(rng: random.Random) -> tuple[str, str]:
    """(reader, text): JSON nested 1,000 to 200,000 deep, bare or inside a plausible document."""
    depth = rng.choice([1000, 5000, 100000, 200000])
    deep = rng.choice(["[", '{"a":']) * depth
    wrap = rng.choice(['{0}', '{{"character": "一", "medians": {0}', '{{"format": "brushwork-paint", "events": {0}'])
    reader = rng.choice(sorted(_readers(Path("."))))
    return reader, wrap.format(deep) + "\n"


def check_nested(reader: str, text: str, folder: Path) -> str | None:
    name, load, allowed = _readers(folder)[reader]
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return _load_only(lambda: load(path), allowed)
