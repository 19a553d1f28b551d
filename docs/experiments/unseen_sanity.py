"""A sweep for catastrophic glitches on characters without reference outlines (session 7).

Writes n GB2312 characters spread over the set, from the default source (KanjiVG when installed),
at 256 px with a style, and prints the outliers of ink area per millimetre of centreline (a flung
tuft sweeping a band would be far above the rest), any ink within 3 px of the image border, and
broken strokes.  A study script, not part of the package:

    PYTHONPATH=python python3 docs/experiments/unseen_sanity.py kai 600
"""
import sys
from multiprocessing import Pool

import numpy as np

from brushwork import batch
from brushwork.glyphs.sources import load_source
from brushwork.motion import Style, Writer, writing_paper

GLYPHS: dict = {}


def measure(char: str, style: str = "kai") -> tuple:
    glyph = GLYPHS[char]
    st = Style.load(style)
    paper = writing_paper(st, 256)
    writer = Writer(paper, st, 0)
    writer.write(glyph)
    ink = paper.ink()                                           # (256, 256) coverage
    length = sum(float(np.linalg.norm(np.diff(np.asarray(s.points), axis=0), axis=1).sum())
                 for s in glyph.strokes)                        # em
    border = float(ink[:3].sum() + ink[-3:].sum() + ink[:, :3].sum() + ink[:, -3:].sum())
    return char, float((ink > 0.5).mean()) / max(length, 1e-6), border, writer.breaks


def main(style: str, n: int) -> None:
    GLYPHS.update(load_source("default", batch.gb2312(), errors=[]))
    chars = list(GLYPHS)
    picked = [chars[int(i)] for i in np.linspace(0, len(chars) - 1, n)]
    with Pool(2) as pool:
        rows = pool.starmap(measure, [(c, style) for c in picked])
    med = float(np.median([r[1] for r in rows]))
    rows.sort(key=lambda r: r[1])
    print(f"{style}: {len(rows)} characters; ink per centreline length from {rows[0][1] / med:.2f} "
          f"({rows[0][0]}) to {rows[-1][1] / med:.2f} ({rows[-1][0]}) times the median; ink at the "
          f"border in {sum(r[2] > 1.0 for r in rows)}; broken strokes {sum(r[3] for r in rows)}")


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]))
