"""A line of glyphs on a paper: the paper sized for them (`writing_paper`) and the glyphs written
on it left to right by one brush (`text_paper`; `render_glyph` for one), with the checks on the
numbers of such a paper and the figures of the writing."""
from __future__ import annotations

from ..paper import Paper, make_paper
from ..scene import Scene
from .driver import Writer
from .plan import load_plan
from .style import Style

MAX_SIDE = 32768     # px: the paper's largest side
MAX_SEED = 2 ** 63 - 1


def check_size(size: int) -> int:
    """px per character: 16..8192."""
    size = int(size)
    if not 16 <= size <= 8192:
        raise ValueError(f"size {size} px: expected 16..8192 px")
    return size


def check_samples(samples: int | None) -> int | None:
    """Multisampling of the stroke layer: None (the style's) or a count the core's scene takes
    (SceneFeatures.validate says which), checked before any work."""
    if samples is not None:
        try:
            Scene(samples=samples)
        except TypeError:
            raise ValueError(f"samples {samples!r}: not a count of samples") from None
    return samples


def check_seed(seed: int) -> int:
    """The seed of the style's variation: 0..2^63-1."""
    if not 0 <= seed <= MAX_SEED:
        raise ValueError(f"--seed {seed}: expected a non-negative integer (0..2^63-1)")
    return seed


def writing_paper(style: Style, size: int, chars: int = 1, samples: int | None = None, ink: str = "auto") -> Paper:
    """A paper for `chars` characters in a row, each em box a size x size px square, with the
    style's scene; `samples` overrides its multisampling (1 is ~2.5x faster on a software
    renderer, its edges stepped at the pixel); `ink` picks the ink's path (paper.ink_path:
    geometry, gl, or auto: geometry, without GL, for an opaque scene)."""
    size, samples = check_size(size), check_samples(samples)
    if chars < 1:
        raise ValueError("no characters to render")
    if chars * size > MAX_SIDE:
        raise ValueError(f"{chars} characters x {size} px = {chars * size} px wide: more than {MAX_SIDE}; "
                         "use a smaller size or `brushwork batch`")
    scene = dict(style.scene, **({"samples": samples} if samples else {}))
    return make_paper(chars * style.em_mm, style.em_mm, size / style.em_mm, Scene(**scene), ink)


def text_paper(glyphs: list, size: int = 1024, style: Style | str = "kai", seed: int = 0,
               samples: int | None = None, counts: dict | None = None, paper: Paper | None = None,
               ink: str = "auto", plans=None) -> Paper:
    """A paper (len(glyphs) * size) x size px with the glyphs written left to right, one em box
    per glyph filling a size x size square, by one brush: ink and wetness carry from character
    to character (re-dipped at each), as in a hand-written line. samples: multisampling of the
    stroke layer (None: the style's scene, 4 unless it says otherwise; 1 is ~2.5x faster on a
    software renderer, with edges stepped at the pixel). counts: a dict that receives the frames
    written, the strokes broken (the brush down again after a lift within one stroke), the
    frames held (Writer._step), the beads at exits by stroke family (Writer.beads) and the
    solver's figures (Writer.solver). paper: one made earlier by writing_paper for as many glyphs
    at this size, style and samples, cleared and written again (a batch worker keeps one: a new 1024 px
    paper allocates and clears its textures, ~12 ms, and page-faults them in again as it draws)."""
    st = style if isinstance(style, Style) else Style.load(style)
    if paper is None:
        paper = writing_paper(st, size, len(glyphs), samples, ink)
    else:
        if (paper.width_px, paper.height_px) != (len(glyphs) * size, size):
            raise ValueError(f"a {paper.width_px} x {paper.height_px} px paper cannot take {len(glyphs)} "
                             f"character(s) at {size} px")
        paper.clear()
    writer = Writer(paper, st, seed)
    writer.count_planned_beads = counts is not None
    for k, glyph in enumerate(glyphs):
        if plans is not None:       # a folder of plan files (brushwork fit): written in the source's em box
            writer.write_planned(glyph, load_plan(plans, glyph.char, len(glyph.strokes)), (k * st.em_mm, 0.0))
        else:
            writer.write(glyph, origin_mm=(k * st.em_mm, 0.0))
    if counts is not None:
        counts.update(frames=writer.frames, breaks=writer.breaks, holds=writer.holds, beads=writer.beads,
                      solver=writer.solver)
    return paper


def render_glyph(glyph, size: int = 1024, style: Style | str = "kai", seed: int = 0, ink: str = "auto") -> Paper:
    """A paper of `size` x `size` px whose em box is the whole image (so a Make Me a Hanzi glyph
    lands where its SVG recipe draws the outlines), with the glyph written on it."""
    return text_paper([glyph], size, style, seed, ink=ink)


def writing_stats(counts: dict) -> dict:
    """The figures of a writing from text_paper's `counts`: frames, frames held, strokes broken,
    solver steps and those stopped at the iteration cap q_max, SQP iterations, sub-steps, the
    deepest penetration (mm), beads at exits by stroke family ([beaded, strokes])."""
    solver = counts["solver"]
    return {"frames": counts["frames"], "frames_held": counts["holds"], "strokes_broken": counts["breaks"],
            "solver_steps": solver["steps"], "frames_at_q_max": solver["steps_at_q_max"],
            "iterations": solver["iterations"], "substeps": solver["substeps"],
            "max_penetration_mm": solver["max_penetration_mm"], "beads": counts["beads"]}
