"""Work-precision benchmark: per-frame error against per-frame run time, ours and the peers'.

    brushwork bench precision [--json FILE] [--out DIR] [--quick]

What is measured (error against run time, one frame problem at a time):

* **References.** Every recorded motion (press-drag-turn-lift and a fast flick, on the stiffest
  and the softest preset, exponent m = 2 and 3) is replayed with the core's own solver at
  tolerance 1e-10 (REF_TOLERANCE) and q_max REF_Q_MAX.  The core's SQP usually stops before
  1e-10 on its own (its l1-merit line search hits the floating-point floor of the energy near
  1e-7), so each frame's solution is then *polished* in Python by Newton's method on the KKT
  system of the same frame problem (finite-difference Hessian of the Lagrangian from the core's
  analytic gradients, active set from the core's multipliers) until the scaled KKT residual is
  <= 1e-10.  The reference *history* (the state that poses the next frame) stays the core's
  own tight solution, so the next frame's normal forces R_i come from the core's multipliers.
  A reference frame that fails (KKT above REF_KKT_OK after the polish; the core's tight solve
  can end in a state it cannot leave, see the README) is left out of every statistic of every
  solver (``valid_frames`` counts the frames kept).
* **The frame problem.** ``Brush.prepare(pose)`` freezes frame k's problem P_k (contact set, R_i,
  friction anchors, plasticity shift rho, pore plane) from the state after frame k-1; then
  ``energy(z)``, ``energy_gradient(z)``, ``constraints(z)`` (g(z) >= 0 feasible, mm) and
  ``constraint_jacobian(z)`` evaluate it.  A *probe* brush is kept in lockstep with the
  reference brush and prepared at each frame before the reference steps, so that the polish,
  the peers and the energy gaps all see exactly the P_k that the reference's ``step()`` solved.
  ``step()`` does two things ``prepare()`` does not: continuation (a frame whose first iterate
  sinks more than 2% L is split into sub-steps; then P_k is not the problem the core solved,
  and the frame is left out of the energy gaps and the peers' runs: ``posable`` false) and the
  sleep rule (no iterations for the same pose; a step after a prepare always sees "the same
  pose").  The probe is put back in lockstep after each frame by copying the stepping brush's
  whole state (``Brush.copy_state_from``).
* **Peers** (SciPy's SLSQP, NLopt's SLSQP, IPOPT through cyipopt; each optional) solve the
  reference's P_k, warm-started from the reference's previous-frame solution (what
  ``variables()`` returns after ``prepare``), fed the core's energy, gradient, constraints and
  Jacobian.  They cannot be run on a trajectory of their own on the same physics: after
  ``set_variables(z)`` the core keeps the contact multipliers of the last solve it did itself,
  so the next frame's normal forces R_i would not follow the peer.  Their errors are therefore
  one-frame errors from a perfect start, which favours them; ours are errors along our own
  trajectory.
* **Errors per frame** against the reference frame: the scaled KKT residual (the core's measure)
  on the problem each solver was given (ours: its own frame problem, as ``step()`` reports it;
  peers: P_k, multipliers by least squares); relative energy gap
  |E - E*| / max(|E*|, ENERGY_FLOOR * kappa_root), E the energy of the frame's own problem at
  the solver's state (ours: ``stats.energy``; peers: P_k at their solution) and E* the
  reference's (P_k at the polished solution), so that it measures both the solver's error and
  how far our trajectory has drifted from the reference's; skeleton error max_i |O_i - O_i*| (mm, and as a
  fraction of the tuft length L); footprint error 1 - IoU of the footprint polygons (shapely when
  installed, else a raster of both polygon sets); and at the end of the pipeline (full runs, not
  ``--quick``) the ink-mask IoU of 永 written in kai at 512 px with each setting's
  brush against the same written with a tight solve (``INK_MASK_IOU``, ``bench.glyphs.InkMaskIoU``).
* **Time per frame**: wall time in Python around ``step()`` for ours (best of ``repeats`` runs
  per frame), around the solve call for peers (``prepare`` is not counted for them).

Float against double: the core is double only (cpp/include/brushwork/brush.hpp), so the float
row says "not built"; the peers are double only too.

The package follows the run: config (the reference, the settings swept), motions, errors, peers,
running (ours, the reference and the peers along a motion), aggregate (rows, front, ratios),
table1 (the seed's Table 1), whole (the whole run) and output (the report and the plot).
"""
from __future__ import annotations

import argparse
import os

# the peers' linear algebra on one thread, like the core (set before SciPy loads its BLAS; a
# value the user set is kept)
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

from .aggregate import front_check, speed_ratios  # noqa: E402
from .config import OURS, REF_Q_MAX, REF_TOLERANCE  # noqa: E402
from .errors import footprint_error, kkt_residual, peer_kkt, polish, skeleton_error  # noqa: E402
from .motions import Motion, Setting, default_label, motions, settings  # noqa: E402
from .output import PLOT_HINT, plot, table  # noqa: E402
from .peers import FrameProblem, available_peers  # noqa: E402
from .running import LockstepProbe, Reference, run_ours, run_reference  # noqa: E402
from .whole import run  # noqa: E402

__all__ = ["FrameProblem", "LockstepProbe", "Motion", "OURS", "PLOT_HINT", "REF_Q_MAX", "REF_TOLERANCE", "Reference",
           "Setting", "add_arguments", "available_peers", "default_label", "footprint_error", "front_check", "handle",
           "kkt_residual", "main", "motions", "peer_kkt", "plot", "polish", "run", "run_ours", "run_reference",
           "settings", "skeleton_error", "speed_ratios", "table"]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The precision benchmark's options (shared with the `brushwork` CLI)."""
    parser.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")
    parser.add_argument("--out", metavar="DIR", default="bench_out",
                        help="folder for precision.png and precision.md (default bench_out)")
    parser.add_argument("--quick", action="store_true",
                        help="one short stroke, fewer settings, one run, each peer at its default")
    parser.add_argument("--repeats", type=int, default=None,
                        help="runs per setting of ours, least time per frame kept (default 3; quick 1)")
    parser.add_argument("--no-peers", action="store_true", help="do not run the peer solvers")
    parser.add_argument("--no-progress", action="store_true", help="no progress lines on stderr")


def handle(args: argparse.Namespace) -> int:
    """Run with parsed `args`: print the Markdown, write the plot (and JSON). Returns the exit code."""
    from ..report import check_writable, write_atomic, write_json

    if args.repeats is not None and args.repeats < 1:
        raise ValueError(f"--repeats {args.repeats} must be at least 1")
    # fail on unwritable targets before the run, not after
    os.makedirs(args.out, exist_ok=True)
    png, md = os.path.join(args.out, "precision.png"), os.path.join(args.out, "precision.md")
    check_writable(png)
    if args.json:
        check_writable(args.json)
    result = run(quick=args.quick, repeats=args.repeats, peers=not args.no_peers,
                 progress=not args.no_progress)
    text = table(result)
    print(text)
    if not plot(result, png):
        print(PLOT_HINT)
        png = "none"

    def write_md(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text + "\n")

    write_atomic(md, write_md, suffix=".md")
    print(f"\nplot: {png}; table: {md} ({result['wall_seconds']:.0f} s)")
    if args.json:
        write_json(args.json, result)
    return 0


def main(argv: list[str] | None = None) -> int:
    """Command line: ``python -m brushwork.bench.precision``."""
    parser = argparse.ArgumentParser(prog="brushwork bench precision",
                                     description="Error against run time per frame, ours and peers.")
    add_arguments(parser)
    return handle(parser.parse_args(argv))
