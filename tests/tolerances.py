"""Named tolerances for the test suite, and a comparison that says which entry failed and by how much."""
from __future__ import annotations

import numpy as np

GRADIENT_REL = 1e-5          # normalised relative error of analytic vs finite-difference derivatives
PENETRATION_FRAC = 0.01      # shrunk sections below the paper, as a fraction of the tuft length
MERIT_SLACK = 1e-12          # relative round-off allowed when checking the merit never rises
STRAIGHT_ANGLE = 1e-6        # rad: "straight" bend angles of an untouched brush
CARRIED_HESSIAN_RATIO = 0.85  # mean iterations carried / fresh on a recorded stroke (seed: 7.4 / 14.6);
                              # 0.36 while only the tip touched, 0.81 since the belly lies on the paper
FOOTPRINT_DEPTHS = (0.05, 0.1, 0.2, 0.3, 0.4)  # press depths below first contact, fractions of L
DRAG_WIDTH_PER_DIAMETER = 1.0  # dragged footprint width / belly diameter at a 0.3 L press, at least


def assert_rel_close(name: str, got: np.ndarray, want: np.ndarray, rel: float) -> None:
    """Normalised relative error |got - want|_inf / max(|want|_inf, |got|_inf, tiny) <= rel."""
    got, want = np.asarray(got, float), np.asarray(want, float)
    scale = max(np.abs(want).max(initial=0.0), np.abs(got).max(initial=0.0), 1e-300)
    diff = np.abs(got - want)
    err = diff.max(initial=0.0) / scale
    if not err <= rel:
        k = int(np.argmax(diff))
        raise AssertionError(f"{name}: normalised error {err:.3e} > {rel:.1e}; worst entry {k}: "
                             f"got {got.flat[k]:.9g}, want {want.flat[k]:.9g}")

# rendering
INK_AREA_REL = 0.02          # ink area vs the core's footprint polygon at 2048 px
INK_CONSERVATION_REL = 0.03  # ink on the paper (its pixels) vs ink the brush lost (0.1 mm cells of the
                             # core's footprints, WetArea): 1.5-2.1% measured
MASK_IOU_RESOLUTION = 0.98   # one ink at two resolutions, downsampled: 1024 vs 4096 px; a 6 px stroke at 5 vs 20 px/mm, one sample a pixel (0.989)
MASK_THRESHOLD = 0.5         # ink coverage above which a pixel counts as inked
MESH_INK_REL = 0.03          # ink of the default render mesh vs a 16 x 128 one at 1024 px (caps: -2.2%)
ARC_EDGE_ROUGHNESS_PX = 0.3  # an arc's contour against its smoothed copy at 10 px/mm (0.22 measured; saw teeth a frame apart: 0.44)
MESH_L1_REL = 0.03           # its L1 ink error vs a 16 x 128 one, relative (2.3% measured, caps 1.6%: flattened sections are thin ellipses; 0.8% / 0.55% with round ones)
FOOTPRINT_DIP = 0.1          # a static press may lose this fraction of area or width at one deeper step
                             # (path-dependent buckling of the soft tail)
