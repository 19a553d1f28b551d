"""Work-precision benchmark: the whole run: every motion at every rate, then the rows, the verdicts and the notes."""
from __future__ import annotations

import os
import platform
import sys
import time
from typing import Callable, Optional

import numpy as np

from .aggregate import build_rows, front_check, speed_ratios
from .config import INK_MASK_IOU, INK_NOTE, OURS, TUFTS_NOTE
from .errors import footprint_backend
from .motions import Motion, default_label, motions, settings
from .peers import available_peers
from .running import Reference, _model_for, own_problem_gaps, run_ours, run_reference
from .table1 import table1


def machine_note() -> str:
    """One line: the machine and the solver versions of this run."""
    import importlib

    vers = []
    for mod, name in (("scipy", "SciPy"), ("nlopt", "NLopt"), ("cyipopt", "cyipopt")):
        try:
            vers.append(f"{name} {importlib.import_module(mod).__version__}")
        except ImportError:
            pass
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return (f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, "
            f"NumPy {np.__version__}" + (", " + ", ".join(vers) if vers else ""))


def _posable_kkt(ref: Reference) -> tuple[Optional[float], Optional[float]]:
    """(max, fraction <= 1e-10) of the polished KKT residuals over the valid posable frames."""
    kept = ref.posable & ref.valid
    if not kept.any():
        return None, None
    return float(np.nanmax(ref.kkt[kept])), float(np.mean(ref.kkt[kept] <= 1e-10))


def _reference_summary(motion: Motion, rate: float, frames: int, ref: Reference) -> dict:
    """One line of the reference table: how many frames were posable and valid, and how tight."""
    kkt_max, kkt_tight = _posable_kkt(ref)
    return {
        "motion": motion.name, "rate": rate, "frames": frames,
        "posable_frames": int(ref.posable.sum()),
        # over the valid frames (every statistic uses only those)
        "polished_kkt_max": kkt_max,
        "polished_kkt_le_1e-10_frac": kkt_tight,
        "core_kkt_median": float(np.median(ref.core_kkt)),
        "core_kkt_max": float(np.max(ref.core_kkt)),
        "probe_resyncs": ref.resyncs,
        "valid_frames": int(ref.valid.sum()),
        "reference_failed_at": (int(np.argmin(ref.valid)) if not ref.valid.all() else None),
        "failed_frames": int((~ref.valid).sum()),
    }


def _run_at_rate(motion: Motion, rate: float, setting_list: list, peer_runs: list, repeats: int,
                 say: Callable[[str], None]) -> tuple[dict, Reference, int]:
    """Replay `motion` at `rate` with every setting of ours at that rate, then its reference (and
    the peers, at 1x).  Returns (label -> Trajectory, the Reference, the number of frames)."""
    poses = motion.poses(rate)
    ours = {}
    for st in setting_list:
        if st.family == "float" or st.rate != rate:
            continue
        model = _model_for(motion, st.overrides)
        ours[st.label] = run_ours(model, poses, repeats)
        ours[st.label].gaps = own_problem_gaps(model, poses)
    say(f"{motion.name} at {rate:g}x ({len(poses)} frames): {len(ours)} settings of ours run")
    ref = run_reference(motion, poses, peer_runs if rate == 1.0 else [], say)
    return ours, ref, len(poses)


def _add_ink_iou(rows: list[dict], setting_list: list) -> None:
    """Fill in the ink-mask IoU column of our 1x q_max, tolerance and Hessian rows."""
    ink_iou = INK_MASK_IOU()
    # (the default's row carries the spelled-out label, default_label(), not its own)
    by_label = {(default_label() if st.default else st.label): st for st in setting_list}
    for row in rows:
        st = by_label.get(row["setting"]) if row["solver"] == OURS else None
        if st is not None and st.family in ("q_max", "tolerance", "hessian") and st.rate == 1.0:
            row["ink_mask_iou_median"] = ink_iou(dict(st.overrides))


def run(quick: bool = False, repeats: Optional[int] = None, peers: bool = True,
        progress: bool = True) -> dict:
    """Run the whole benchmark; returns {"rows", "front", "speed_ratios", "table1", "reference",
    "notes", "machine", ...} (see module docstring)."""
    def say(msg: str) -> None:
        if progress:
            print(f"[precision] {msg}", file=sys.stderr, flush=True)

    t_start = time.perf_counter()
    repeats = repeats if repeats is not None else (1 if quick else 3)
    setting_list = settings(quick)
    peer_runs, notes = available_peers(quick) if peers else ([], ["peers: skipped (--no-peers)"])
    for n in notes:
        say(n)
    results, ref_summary = [], []
    rates = sorted({s.rate for s in setting_list if s.family != "float"})
    for motion in motions(quick):
        for rate in rates:
            ours, ref, frames = _run_at_rate(motion, rate, setting_list, peer_runs, repeats, say)
            results.append((motion, rate, ours, ref))
            ref_summary.append(_reference_summary(motion, rate, frames, ref))
    rows = build_rows(results, setting_list, peer_runs)
    if INK_MASK_IOU is not None and not quick:
        say("ink-mask IoU of a written character per setting (the reference render takes a minute)")
        _add_ink_iou(rows, setting_list)
    say("Table 1")
    t1 = table1(quick)
    return {
        "benchmark": "precision",
        "quick": quick,
        "machine": machine_note(),
        "default_setting": default_label(),
        "footprint_iou": footprint_backend(),
        "rows": rows,
        "front": front_check(rows),
        "speed_ratios": speed_ratios(rows),
        "table1": t1,
        "table1_note": TUFTS_NOTE,
        "reference": ref_summary,
        "ink_mask_iou": {"available": INK_MASK_IOU is not None and not quick, "note": INK_NOTE},
        "notes": notes,
        "wall_seconds": time.perf_counter() - t_start,
    }
