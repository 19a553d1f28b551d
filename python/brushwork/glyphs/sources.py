"""load_source: glyphs for some characters from a named source."""
from __future__ import annotations

from pathlib import Path

from . import kanjivg, mmah
from .jsonfmt import load_glyph
from .model import Glyph, GlyphError

SPECS = ("default, kanjivg, kanjivg:DIR, mmah:PATH (graphics.txt or a folder of <char>.json) or glyphs:DIR, "
         "or several joined by + (each character from the first that has it)")
DEFAULT = "default"
KINDS = ("default", "kanjivg", "mmah", "glyphs")


def split_sources(spec: str) -> list[str]:
    """'kanjivg+mmah:PATH' -> ['kanjivg', 'mmah:PATH']. A '+' starts another source only where a
    source's kind follows it (default, kanjivg, mmah or glyphs), so a path may hold a '+'."""
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


def _kanjivg_installed() -> bool:
    try:
        kanjivg.package_dir()
    except GlyphError:
        return False
    return True


def _load_default(chars, variant, errors) -> dict[str, Glyph]:
    """The default source: the bundled glyph files, then KanjiVG (when installed) for the rest."""
    folder = bundled_dir()
    wanted = None if chars is None else list(dict.fromkeys(chars))
    missing: list = []
    out = load_source(f"glyphs:{folder}", wanted, errors=missing)
    unknown = [e.char for e in missing if getattr(e, "char", None)]
    bad = [e for e in missing if not getattr(e, "char", None)]
    if wanted is None or unknown:
        if _kanjivg_installed():
            kv: list = []
            rest = load_source("kanjivg", unknown if wanted is not None else None, variant=variant, errors=kv)
            out.update({c: g for c, g in rest.items() if c not in out})
            # a character in neither place is the default source's miss (it said "kanjivg: no
            # glyph", which read as if the bundled glyphs had not been looked in); a KanjiVG file
            # that cannot be read stays its own error
            bad += [_unknown("default", e.char, "among the bundled glyphs or in KanjiVG")
                    if getattr(e, "unknown", False) else e for e in kv]
        else:
            bad += [_unknown("default", c, "among the bundled ones; pip install 'brushwork[kanjivg]' for "
                                           "about 6,400 more, or pass --source") for c in unknown]
    if bad:
        if errors is None:
            raise bad[0]
        errors.extend(bad)
    return out if wanted is None else {c: out[c] for c in wanted if c in out}


def add_source_hint(spec: str = "default") -> str:
    """What to tell a user whose characters `spec` does not have: chain another source after it."""
    return f"add a source after a +, e.g. --source {spec}+mmah:graphics.txt (Make Me a Hanzi has over 9,000)"


def glyph_file_name(char: str) -> str:
    """Our format's file name for char: U+XXXX.json (upper-case hex, at least 4 digits)."""
    return f"U+{ord(char):04X}.json"


def _unknown(where, char: str, detail: str = "") -> GlyphError:
    err = GlyphError(where, f"no glyph for {char!r} (U+{ord(char):04X})" + (f" {detail}" if detail else ""))
    err.char = char                      # the default source falls back to KanjiVG for these,
    err.unknown = True                   # and a chain of sources to the next one
    return err


def _load_chain(spec: str, parts: list[str], chars, variant, errors) -> dict[str, Glyph]:
    """Sources joined by '+': each character from the first source that has it. A character
    that a source has but cannot read (a malformed file) is reported, not looked up further."""
    wanted = None if chars is None else list(dict.fromkeys(chars))
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
    bad += [_unknown(spec, c, f"in any of {', '.join(parts)}") for c in todo or []]
    if bad:
        if errors is None:
            raise bad[0]
        errors.extend(bad)
    return out if wanted is None else {c: out[c] for c in wanted if c in out}


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
        if not path.is_file():
            yield char, _unknown(folder, char)
            continue
        try:
            yield char, read(path, char)
        except GlyphError as e:
            yield char, e


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


def load_source(spec: str, chars: str | None = None, *, variant: str | None = None,
                errors: list | None = None) -> dict[str, Glyph]:
    """{char: Glyph} for the requested chars (every glyph the source has when chars is None).

    spec: "default" (the bundled glyph files, then KanjiVG when installed), "kanjivg" (the installed
    kanjivg package), "kanjivg:DIR" (a folder of KanjiVG SVGs), "mmah:PATH" (a graphics.txt file, or
    a folder of hanzi-writer-data <char>.json files) or "glyphs:DIR" (our format, files named
    U+XXXX.json), or several of these joined by "+" (each character from the first that has it:
    "kanjivg+mmah:PATH" fills KanjiVG's gaps). variant: a KanjiVG variant such as "Kaisho",
    used where a character has one (the plain file otherwise); "kanjivg#Kaisho" says the same.
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
    wanted = None if chars is None else list(dict.fromkeys(chars))
    base, _, hashed = spec.rpartition("#") if spec.startswith("kanjivg") and "#" in spec else (spec, "", "")
    variant = hashed or variant
    kind, _, arg = base.partition(":")
    if kind not in ("kanjivg", "mmah", "glyphs") or (kind != "kanjivg" and not arg):
        raise GlyphError(spec, f"unknown source; expected {SPECS}")
    path = Path(arg) if arg else None
    if path is not None and not path.exists():
        raise GlyphError(path, "no such file or folder")
    if kind == "kanjivg":
        folder = path or kanjivg.package_dir()

        def read_kvg(p, char):
            return kanjivg.read_svg(p, source="kanjivg")
        if wanted is None:
            stems = sorted({p.name.split("-")[0].split(".")[0] for p in folder.glob("*.svg")})
            wanted_kvg = [chr(int(s, 16)) for s in stems if all(ch in "0123456789abcdef" for ch in s)]
        else:
            wanted_kvg = wanted
        found = ((c, kanjivg.file_for(folder, c, variant)) for c in wanted_kvg)
        items = ((c, _unknown(folder if path else "kanjivg", c) if p is None else _try(read_kvg, p, c))
                 for c, p in found)
    elif kind == "glyphs":
        if not path.is_dir():
            raise GlyphError(path, "glyphs: needs a folder of U+XXXX.json files")
        items = _from_folder(path, wanted, glyph_file_name, _read_ours)
    elif path.is_dir():
        items = _from_folder(path, wanted, lambda c: f"{c}.json", mmah.read_char_file)
    else:
        items = _mmah_file(path, wanted)
    out: dict[str, Glyph] = {}
    handled = set()
    for char, got in items:
        handled.add(char)
        if isinstance(got, GlyphError):
            got.char = char                  # which character it was, for a batch's report
            if errors is None:
                raise got
            errors.append(got)
        elif char not in out:
            out[char] = got
    if wanted is not None:
        for char in wanted:
            if char not in handled:
                e = _unknown(path, char)
                if errors is None:
                    raise e
                errors.append(e)
        out = {c: out[c] for c in wanted if c in out}
    return out


def _try(read, path, char):
    try:
        return read(path, char)
    except GlyphError as e:
        return e


def _mmah_file(path: Path, wanted):
    yield from mmah.read_graphics(path, None if wanted is None else set(wanted))
