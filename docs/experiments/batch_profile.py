"""One process's time a 1024 px character, as a batch worker spends it (session 13).

    PYTHONPATH=python LP_NUM_THREADS=0 OPENBLAS_NUM_THREADS=1 python3 docs/experiments/batch_profile.py [N]

writes N GB2312 characters (default 30, spread over the set, those the default source has) on
one paper, cleared for each, and prints seconds a character by part (`bench batch`'s breakdown,
over more characters than its 4). Under callgrind (deposit_instructions.sh) it gives the
deposit's instruction count, which does not move with this machine's load as its times do.
"""
import sys

import numpy as np

from brushwork import batch as bt
from brushwork.bench.glyphs import breakdown
from brushwork.glyphs.sources import load_source

n = int(sys.argv[1]) if len(sys.argv) > 1 else 30
pool = bt.gb2312()
spread = "".join(pool[int(i)] for i in np.linspace(0, len(pool) - 1, 3 * n))
have = load_source("default", spread, errors=[])
glyphs = [have[c] for c in list(have)[:n]]
b = breakdown(glyphs, 1024, "kai")
parts = ", ".join(f"{k} {v / n:.4f}" for k, v in b["parts"].items())
print(f"{b['seconds'] / n:.3f} s a character, {b['frames'] / n:.0f} frames a character ({parts})")
