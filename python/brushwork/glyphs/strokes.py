"""Stroke types: normalising a source's label, and inferring one from a centreline's shape.

The inference reads a centreline as a few straight legs (Douglas-Peucker, then merging legs that
run on in nearly the same direction), names each leg by its compass direction, marks a short sharp
turn at the very end as a hook or a rising tick, and looks the sequence up in a table of the
standard strokes. Nothing in it knows any character.
"""
from __future__ import annotations

import math

import numpy as np

from .model import STROKE_TYPES, GlyphError

# Aliases some sources use for a stroke: CJK unified ideographs that look like one.
_ALIASES = {"一": "㇐", "丨": "㇑", "丿": "㇒", "丶": "㇔", "乙": "㇈", "亅": "㇚", "乚": "㇟"}


def normalise_kind(label: str | None) -> str | None:
    """A source's stroke label ("㇔/㇀", "㇐a", "丶") -> its first CJK stroke char, or None if it has none."""
    for ch in label or "":
        if ch in STROKE_TYPES:
            return ch
        if ch in _ALIASES:
            return _ALIASES[ch]
    return None


# -- shape analysis (all lengths in em units, angles in degrees, y up) --------------------------------
SIMPLIFY_FRAC = 0.06    # Douglas-Peucker tolerance, fraction of the stroke's length
SIMPLIFY_MIN = 0.008    # ... but at least this (em)
MERGE_DEG = 32.0        # consecutive legs turning less than this are one leg
ENTRY_FRAC = 0.08       # a first leg shorter than this fraction of the stroke is the brush's entry,
ENTRY_SOFT_FRAC = 0.25  # ... and so is one shorter than this that turns less than
ENTRY_TURN_DEG = 80.0   # ... this into the next leg
EXIT_FRAC = 0.12        # a last leg shorter than this fraction that is no hook is the brush's exit
HOOK_FRAC = 0.3         # a last leg shorter than this fraction of the stroke that turns at least
HOOK_TURN_DEG = 80.0    # ... this much is a hook, or a tick when it rises to the right
HOOK_DOWN_REL = 0.3     # after a horizontal, a leg heading down is a hook only when shorter than this
HOOK_SLANT_REL = 0.45   # ... times the horizontal, or this when it slants down-left (the hook of 冖)
FOLD_DEG = -122.0       # after a horizontal, a leg down steeper than this is the vertical of a turn (㇕)
CORNER_FRAC = 0.2       # a middle leg shorter than this and its neighbours, heading between them, rounds a corner
DOT_LEN = 0.2           # a stroke shorter than this (em) that falls right is a dot
SHORT_DOT_LEN = 0.11    # any falling stroke shorter than this (em) is a dot


def _rdp(p: np.ndarray, eps: float) -> np.ndarray:
    """Indices of the Douglas-Peucker simplification of polyline p (k, 2) at tolerance eps."""
    keep = np.zeros(len(p), bool)
    keep[[0, -1]] = True
    stack = [(0, len(p) - 1)]
    while stack:
        i, j = stack.pop()
        if j <= i + 1:
            continue
        a, b = p[i], p[j]
        ab = b - a
        n = math.hypot(*ab)
        q = p[i + 1:j] - a
        dist = np.abs(ab[0] * q[:, 1] - ab[1] * q[:, 0]) / n if n > 0 else np.hypot(q[:, 0], q[:, 1])
        k = int(np.argmax(dist))
        if dist[k] > eps:
            keep[i + 1 + k] = True
            stack += [(i, i + 1 + k), (i + 1 + k, j)]
    return np.flatnonzero(keep)


def _angle(v) -> float:
    return math.degrees(math.atan2(v[1], v[0]))


def _turn(a: float, b: float) -> float:
    """Unsigned turn from direction a to direction b, degrees in [0, 180]."""
    return abs((b - a + 180.0) % 360.0 - 180.0)


def _direction(theta: float) -> str:
    """Compass class of a leg: H right, T rising right, U up, B up-left (back), L left,
    P falling left, S down, N falling right."""
    for hi, name in ((-157.5, "L"), (-112.0, "P"), (-68.0, "S"), (-22.5, "N"), (22.5, "H"), (75.0, "T"),
                     (105.0, "U"), (157.5, "B"), (180.1, "L")):
        if theta < hi:
            return name
    return "L"


def _unit(theta: float) -> np.ndarray:
    return np.array([math.cos(math.radians(theta)), math.sin(math.radians(theta))])


def _length(v) -> float:
    return float(np.hypot(*v))


def _simplified_legs(p: np.ndarray, total: float) -> list[np.ndarray]:
    """The legs (vectors, em) of polyline p's Douglas-Peucker simplification, consecutive legs
    that turn less than MERGE_DEG joined into one."""
    idx = _rdp(p, max(SIMPLIFY_MIN, SIMPLIFY_FRAC * total))
    vec: list[np.ndarray] = []
    for a, b in zip(idx[:-1], idx[1:]):
        if vec and _turn(_angle(vec[-1]), _angle(p[b] - p[a])) < MERGE_DEG:
            vec[-1] = vec[-1] + (p[b] - p[a])
        else:
            vec.append(p[b] - p[a])
    return vec


def _drop_entry(vec: list[np.ndarray], total: float) -> None:
    """Remove the brush's entry: a very short first leg, or a short one turning gently into the next."""
    while len(vec) > 1 and (_length(vec[0]) < ENTRY_FRAC * total or (
            _length(vec[0]) < ENTRY_SOFT_FRAC * total and _turn(_angle(vec[0]), _angle(vec[1])) < ENTRY_TURN_DEG)):
        vec.pop(0)


def _round_corners(vec: list[np.ndarray], total: float) -> bool:
    """Remove short legs heading between their neighbours (a rounded corner); whether there was one."""
    rounded = False
    i = 1
    while i < len(vec) - 1:
        a, b, c = _angle(vec[i - 1]), _angle(vec[i]), _angle(vec[i + 1])
        short = _length(vec[i]) < min(CORNER_FRAC * total, _length(vec[i - 1]), _length(vec[i + 1]))
        if short and abs(_turn(a, b) + _turn(b, c) - _turn(a, c)) < 1e-6:
            vec.pop(i)
            rounded = True
        else:
            i += 1
    return rounded


def _is_hook(before: np.ndarray, last: np.ndarray) -> bool:
    """Whether a short last leg turning sharply from `before` is a hook (or tick) rather than the
    next leg of a turn: after a horizontal, a leg heading down must be short against it."""
    theta = _angle(last)
    if _turn(_angle(before), theta) < HOOK_TURN_DEG:
        return False
    rel = _length(last) / _length(before)
    down_after_h = _direction(_angle(before)) == "H" and -170.0 < theta < -60.0
    return not down_after_h or rel < HOOK_DOWN_REL or (theta <= FOLD_DEG and rel < HOOK_SLANT_REL)


def _take_hook(vec: list[np.ndarray], total: float) -> tuple[str, float, float] | None:
    """Remove a final short leg: a hook ("G") or rising tick ("T") leg when it is one (returned),
    or the exit flick when it is very short."""
    if len(vec) < 2 or _length(vec[-1]) >= HOOK_FRAC * total:
        return None
    if _is_hook(vec[-2], vec[-1]):
        last = _angle(vec[-1])
        return ("T" if -15.0 < last < 75.0 else "G", _length(vec.pop()), last)
    if _length(vec[-1]) < EXIT_FRAC * total:
        vec.pop()
    return None


def _named_legs(vec: list[np.ndarray]) -> list[tuple[str, float, float]]:
    """Legs as (class, length, angle), a turn's vertical that leans in named S, and consecutive
    legs of the same class joined into one."""
    legs = [(_direction(_angle(v)), _length(v), _angle(v)) for v in vec]
    for i in range(1, len(legs)):   # the vertical of a turn may lean in: 口's right side
        if legs[i - 1][0] == "H" and legs[i][0] == "P" and legs[i][2] > FOLD_DEG:
            legs[i] = ("S",) + legs[i][1:]
    out: list[tuple[str, float, float]] = []
    for name, n, theta in legs:
        if out and out[-1][0] == name:   # the same class again: one leg
            v = _unit(out[-1][2]) * out[-1][1] + _unit(theta) * n
            out[-1] = (name, _length(v), _angle(v))
        else:
            out.append((name, n, theta))
    return out


def stroke_legs(points_em: np.ndarray) -> tuple[list[tuple[str, float, float]], bool]:
    """The centreline as legs [(class, length em, angle deg)], classes as in _direction, the last one
    "G" for a hook or "T" for a rising tick when the stroke ends in a short sharp turn; and whether a
    corner was rounded (a short leg between two others, heading between them)."""
    p = np.asarray(points_em, dtype=np.float64)
    p = p[np.r_[True, np.any(np.diff(p, axis=0) != 0, axis=1)]]
    total = float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())
    vec = _simplified_legs(p, total)
    _drop_entry(vec, total)
    rounded = _round_corners(vec, total)
    hook = _take_hook(vec, total)
    return _named_legs(vec) + ([hook] if hook else []), rounded


# Leg sequences -> stroke type (after entries and rounded corners are gone).
_PATTERNS = {
    # one leg
    "H": "㇐", "T": "㇀", "S": "㇑", "P": "㇒", "N": "㇏", "U": "㇀",
    # two
    "HS": "㇕", "HP": "㇇", "HN": "㇕", "HG": "㇖", "HT": "㇐",
    "SH": "㇗", "ST": "㇙", "SG": "㇚", "SP": "㇓", "SN": "㇑", "SL": "㇘",
    "PH": "㇜", "PT": "㇜", "PN": "㇛", "PG": "㇢", "PS": "㇒",
    "NG": "㇂", "NH": "㇏", "NS": "㇑", "NP": "㇒", "TN": "㇝", "TH": "㇐", "LP": "㇒",
    # three
    "HSG": "㇆", "HPG": "㇆", "HST": "㇊", "HPT": "㇊", "HSH": "㇅", "HSP": "㇕", "HSL": "㇕",
    "HNG": "㇠", "HNS": "㇕", "HNP": "㇕", "HSN": "㇕",
    "SHG": "㇟", "SHU": "㇟", "SNG": "㇟", "SHS": "㇞", "SHT": "㇟", "SPG": "㇚", "NSG": "㇚",
    "NHG": "㇃", "NHT": "㇃", "NHU": "㇃", "NSP": "㇓",
    # four and more
    "HSHG": "㇈", "HPHG": "㇈", "HSHT": "㇈", "HSHU": "㇈", "HSNG": "㇈", "HPNG": "㇌", "HPSG": "㇌",
    "HSHS": "㇎", "HSHP": "㇋", "HPHP": "㇋", "HSHSG": "㇡", "HPHPG": "㇡", "HPHSG": "㇡",
    "SHSG": "㇉", "SHPG": "㇉",
}
_ROUNDED = {"㇗": "㇄"}   # the same legs, turning in a curve rather than a corner


def _checked_length(p: np.ndarray) -> float:
    """The length of centreline p (k, 2) em; GlyphError when it is not finite points or has none."""
    if p.ndim != 2 or p.shape[1:] != (2,) or not np.all(np.isfinite(p)):
        raise GlyphError("stroke", f"points: expected finite (k, 2) coordinates, got shape {p.shape}")
    total = float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())
    if not total > 0:
        raise GlyphError("stroke", "points: empty stroke (fewer than 2 distinct points)")
    return total


def _is_dot(seq: str, legs, total: float) -> bool:
    """A falling stroke that is very short, or short and falling right."""
    return all(name in "NSP" for name in seq) and (
        total < SHORT_DOT_LEN or (total < DOT_LEN and legs[0][0] == "N"))


_MAIN = {"H": "㇐", "T": "㇀", "U": "㇀", "B": "㇒", "L": "㇐", "P": "㇒", "S": "㇑", "N": "㇏", "G": "㇚"}


def infer_stroke_type(points_em: np.ndarray) -> str:
    """A CJK stroke char for a centreline (k, 2) in em units (y up), from its directions, corners
    and hooks; a sequence the table does not know falls back to the stroke's main direction."""
    p = np.asarray(points_em, dtype=np.float64)
    total = _checked_length(p)
    legs, rounded = stroke_legs(p)
    seq = "".join(name for name, _, _ in legs)
    if _is_dot(seq, legs, total):
        return "㇔"
    if seq in _PATTERNS:
        kind = _PATTERNS[seq]
        return _ROUNDED.get(kind, kind) if rounded else kind
    # unknown sequence: the longest leg decides, keeping a final hook after a vertical
    main = max((leg for leg in legs if leg[0] != "G"), key=lambda leg: leg[1], default=legs[0])[0]
    return "㇚" if seq.endswith("G") and main in "SP" else _MAIN[main]
