"""load_source: glyphs for some characters from a named source."""
from __future__ import annotations

from pathlib import Path

from ..extras import install_hint
from . import kanjivg, medians, mmah
from .jsonfmt import load_glyph
from .model import Glyph, GlyphError

SPECS = ("default, kanjivg, kanjivg:DIR, mmah:PATH (graphics.txt or a folder of <char>.json), glyphs:DIR, "
         "medians (the bundled ones) or medians:PATH, or several joined by + (each character from the "
         "first that has it)")
DEFAULT = "default"
KINDS = ("default", "kanjivg", "mmah", "glyphs", "medians")


def split_sources(spec: str) -> list[str]:
    """'kanjivg+mmah:PATH' -> ['kanjivg', 'mmah:PATH']. A '+' starts another source only where a
    source's kind follows it (default, kanjivg, mmah, glyphs or medians), so a path may hold a '+'."""
    parts: list[str] = []
    for piece in spec.split("+"):
        kind = piece.split(":", 1)[0].split("#", 1)[0]
        if parts and kind not in KINDS:
            parts[-1] += "+" + piece
        else:
            parts.append(piece)
    return parts


def bundled_dir() -> Path:
    """The glyph files that ship with brushwork (our format): the wheel's brushwork/data/glyphs,
    or the repository's glyphs/ folder when running from a source tree."""
    here = Path(__file__).resolve().parent.parent           # .../brushwork
    for folder in (here / "data" / "glyphs", here.parent.parent / "glyphs"):
        if folder.is_dir():
            return folder
    raise GlyphError("default", "the bundled glyph files are missing from this installation")


def outlines_path() -> Path:
    """Five characters with their stroke outlines (Make Me a Hanzi's graphics.txt format) that ship
    with brushwork: the default source of `brushwork bench glyphs`."""
    path = bundled_dir() / "outlines" / "graphics.txt"
    if not path.is_file():
        raise GlyphError("outlines", "the bundled outlines are missing from this installation")
    return path


def _kanjivg_installed() -> bool:
    try:
        kanjivg.package_dir()
    except GlyphError:
        return False
    return True


def default_chain() -> list[str]:
    """The default source as a chain: the bundled glyph files, the bundled medians (all of
    GB2312, Make Me a Hanzi's Kai centrelines), then KanjiVG when it is installed."""
    return [f"glyphs:{bundled_dir()}", "medians"] + (["kanjivg"] if _kanjivg_installed() else [])


def _load_default(chars, variant, errors) -> dict[str, Glyph]:
    """The default source: a character in none of default_chain()'s sources is its miss, named
    "default"; a file that cannot be read stays its own error."""
    parts = default_chain()
    wanted = _distinct(chars)
    out, bad, todo = _chain(parts, wanted, variant)
    if "kanjivg" in parts:
        detail = "among the bundled glyphs and medians or in KanjiVG"
    else:
        detail = f"among the bundled glyphs and medians (KanjiVG's: {install_hint('kanjivg')})"
    bad += [_unknown(DEFAULT, c, detail) for c in todo or []]
    return _finish(out, wanted, bad, errors)


def add_source_hint(spec: str = "default") -> str:
    """What to tell a user whose characters `spec` does not have: the bundled ones after it, or,
    when they are in the chain already, a glyph file of one's own (glyphs/README.md)."""
    if DEFAULT in split_sources(spec):
        return (f"write its strokes as a glyph file (glyphs/README.md) and add its folder: "
                f"--source glyphs:DIR+{spec}")
    return f"add the bundled glyphs and medians (all of GB2312) after it: --source {spec}+default"


def glyph_file_name(char: str) -> str:
    """Our format's file name for char: U+XXXX.json (upper-case hex, at least 4 digits)."""
    return f"U+{ord(char):04X}.json"


def _unknown(where, char: str, detail: str = "") -> GlyphError:
    err = GlyphError(where, f"no glyph for {char!r} (U+{ord(char):04X})" + (f" {detail}" if detail else ""))
    err.char = char                      # a chain of sources looks for these in the next one
    err.unknown = True
    return err


def _distinct(chars) -> list[str] | None:
    """The requested characters in order, each once; None (every glyph a source has) stays None."""
    return None if chars is None else list(dict.fromkeys(chars))


def _finish(out: dict[str, Glyph], wanted, bad: list, errors) -> dict[str, Glyph]:
    """Raise the first of `bad`, or hand them all to `errors` when it is a list; then out, in the
    order of `wanted` when characters were asked for."""
    if bad:
        if errors is None:
            raise bad[0]
        errors.extend(bad)
    return out if wanted is None else {c: out[c] for c in wanted if c in out}


def _chain(parts: list[str], wanted, variant) -> tuple[dict[str, Glyph], list, list | None]:
    """(glyphs, errors, characters no source had) of a chain of sources: each character from the
    first source that has it. A character a source has but cannot read (a malformed file) is
    reported, not looked up further."""
    out: dict[str, Glyph] = {}
    bad: list = []
    todo = wanted
    for part in parts:
        if todo is not None and not todo:
            break
        missing: list = []
        got = load_source(part, todo, variant=variant, errors=missing)
        out.update({c: g for c, g in got.items() if c not in out})
        failed = [e for e in missing if not getattr(e, "unknown", False)]
        bad += failed
        if todo is not None:
            gone = {getattr(e, "char", None) for e in failed}
            todo = [c for c in todo if c not in out and c not in gone]
    return out, bad, todo


def _load_chain(spec: str, parts: list[str], chars, variant, errors) -> dict[str, Glyph]:
    """Sources joined by '+'; a character in none of them is the chain's miss, named by spec."""
    wanted = _distinct(chars)
    out, bad, todo = _chain(parts, wanted, variant)
    bad += [_unknown(spec, c, f"in any of {', '.join(parts)}") for c in todo or []]
    return _finish(out, wanted, bad, errors)


def _from_folder(folder: Path, wanted, name_of, read):
    """(char, Glyph | GlyphError) for files named name_of(char) in folder; all such files if wanted is None."""
    if wanted is None:
        by_name = {}
        for p in sorted(folder.glob("*.json")):
            char = _char_of(p.name, name_of)
            if char is not None:
                by_name[char] = p
        items = list(by_name.items())
    else:
        items = [(c, folder / name_of(c)) for c in wanted]
    for char, path in items:
        yield char, _try(read, path, char) if path.is_file() else _unknown(folder, char)


def _char_of(file_name: str, name_of) -> str | None:
    stem = file_name[:-len(".json")]
    candidates = [stem] if len(stem) == 1 else []
    if stem.startswith("U+"):
        try:
            candidates.append(chr(int(stem[2:], 16)))
        except (ValueError, OverflowError):
            pass
    return next((c for c in candidates if name_of(c) == file_name), None)


def _read_ours(path: Path, char: str) -> Glyph:
    glyph = load_glyph(path)
    if glyph.char != char:
        raise GlyphError(path, f"holds {glyph.char!r}, but its name says {char!r}")
    return glyph


def _try(read, path, char):
    try:
        return read(path, char)
    except GlyphError as e:
        return e


# -- one source: each kind yields (char, Glyph | GlyphError) for the wanted characters (all when None)
def _kanjivg_items(path: Path | None, wanted, variant):
    folder = path or kanjivg.package_dir()
    if wanted is None:
        stems = sorted({p.name.split("-")[0].split(".")[0] for p in folder.glob("*.svg")})
        wanted = [chr(int(s, 16)) for s in stems if all(ch in "0123456789abcdef" for ch in s)]

    def read_kvg(p, char):
        return kanjivg.read_svg(p, source="kanjivg")
    for c in wanted:
        p = kanjivg.file_for(folder, c, variant)
        yield c, _unknown(folder if path else "kanjivg", c) if p is None else _try(read_kvg, p, c)


def _glyphs_items(path: Path, wanted, variant):
    if not path.is_dir():
        raise GlyphError(path, "glyphs: needs a folder of U+XXXX.json files")
    return _from_folder(path, wanted, glyph_file_name, _read_ours)


def _mmah_items(path: Path, wanted, variant):
    if path.is_dir():
        return _from_folder(path, wanted, lambda c: f"{c}.json", mmah.read_char_file)
    return mmah.read_graphics(path, None if wanted is None else set(wanted))


def _medians_items(path: Path | None, wanted, variant):
    return medians.read_medians(path or medians.bundled_path(), wanted)


_ITEMS = {"kanjivg": _kanjivg_items, "glyphs": _glyphs_items, "mmah": _mmah_items, "medians": _medians_items}
_OPTIONAL_ARG = ("kanjivg", "medians")          # kinds that name an installed source without a path


def _one_source(spec: str, variant):
    """(the items of a single source spec, the place its misses are named after)."""
    base, _, hashed = spec.rpartition("#") if spec.startswith("kanjivg") and "#" in spec else (spec, "", "")
    kind, _, arg = base.partition(":")
    if kind not in _ITEMS or (kind not in _OPTIONAL_ARG and not arg):
        raise GlyphError(spec, f"unknown source; expected {SPECS}")
    path = Path(arg) if arg else None
    if path is not None and not path.exists():
        raise GlyphError(path, "no such file or folder")
    return _ITEMS[kind], path, hashed or variant


def _gather(items, wanted, where) -> tuple[dict[str, Glyph], list]:
    """The glyphs and errors of one source's items; a wanted character it never answered for is unknown."""
    out: dict[str, Glyph] = {}
    bad: list = []
    handled = set()
    for char, got in items:
        handled.add(char)
        if isinstance(got, GlyphError):
            got.char = char                  # which character it was, for a batch's report
            bad.append(got)
        elif char not in out:
            out[char] = got
    bad += [_unknown(where, c) for c in wanted or [] if c not in handled]
    return out, bad


def load_source(spec: str, chars: str | None = None, *, variant: str | None = None,
                errors: list | None = None) -> dict[str, Glyph]:
    """{char: Glyph} for the requested chars (every glyph the source has when chars is None).

    spec: "default" (the bundled glyph files, then the bundled medians, then KanjiVG when
    installed), "kanjivg" (the installed kanjivg package), "kanjivg:DIR" (a folder of KanjiVG
    SVGs), "mmah:PATH" (a graphics.txt file, or a folder of hanzi-writer-data <char>.json files),
    "glyphs:DIR" (our format, files named U+XXXX.json), "medians" (the bundled medians) or
    "medians:PATH" (a file of {"character", "medians"} lines, gzipped or not), or several of these
    joined by "+" (each character from the first that has it: "kanjivg+mmah:PATH" fills
    KanjiVG's gaps). variant: a KanjiVG variant such as "Kaisho", used where a character has one
    (the plain file otherwise); "kanjivg#Kaisho" says the same.
    A bad or unknown character raises GlyphError naming the file or source; pass a list as errors
    to collect those errors there and go on with the other characters instead.
    """
    if not isinstance(spec, str):
        raise GlyphError(repr(spec), f"unknown source; expected {SPECS}")
    parts = split_sources(spec)
    if len(parts) > 1:
        return _load_chain(spec, parts, chars, variant, errors)
    if spec == DEFAULT:
        return _load_default(chars, variant, errors)
    wanted = _distinct(chars)
    items, path, variant = _one_source(spec, variant)
    where = path if path is not None else spec.partition("#")[0]
    out, bad = _gather(items(path, wanted, variant), wanted, where)
    return _finish(out, wanted, bad, errors)
