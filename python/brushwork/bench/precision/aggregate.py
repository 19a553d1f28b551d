"""Work-precision benchmark: the rows of the report from the runs (medians and percentiles per
setting), the Pareto front, speed ratios against the peers."""
from __future__ import annotations

from typing import Optional

import numpy as np

from .config import ENERGY_FLOOR, FASTER_MARGIN, FLOAT_NOTE, OURS
from .errors import footprint_error, skeleton_error
from .motions import Motion, Setting, default_label
from .peers import Peer
from .running import Reference, Trajectory


def _median(xs) -> Optional[float]:
    xs = np.asarray([x for x in np.ravel(xs) if x is not None and np.isfinite(x)], float)
    return float(np.median(xs)) if len(xs) else None


def _p95(xs) -> Optional[float]:
    xs = np.asarray(xs, float)
    return float(np.percentile(xs, 95)) if len(xs) else None


def _mean(xs) -> Optional[float]:
    return float(np.mean(xs)) if len(xs) else None


def _one_minus_mean(xs) -> Optional[float]:
    return 1.0 - float(np.mean(xs)) if len(xs) else None


def _row(solver: str, setting: str, family: str, default: bool, times, gaps, skel_mm, skel_frac,
         fp_err, **extra) -> dict:
    """One table row (times in s per frame; the other arrays per frame)."""
    times = np.asarray(times, float)
    row = {
        "solver": solver,
        "setting": setting,
        "default": default,
        "family": family,
        "frames": int(len(times)),
        "ms_per_frame_median": 1e3 * _median(times) if len(times) else None,
        "ms_per_frame_p95": 1e3 * _p95(times) if len(times) else None,
        "energy_gap_median": _median(gaps),
        "skeleton_error_mm_median": _median(skel_mm),
        "skeleton_error_frac_median": _median(skel_frac),
        "footprint_error_median": _median(fp_err),
        "ink_mask_iou_median": None,
    }
    row.update(extra)
    return row


def _pool_our_motion(pool: dict, motion: Motion, tr: Trajectory, ref: Reference) -> None:
    """Append to `pool` (key -> list, one entry per frame) the valid frames of our trajectory
    `tr` on `motion` against its reference `ref`."""
    model = motion.model()
    L = model.tuft_length
    e_floor = ENERGY_FLOOR * model.bend_stiffness
    v = ref.valid
    pool["t"] += list(tr.times[v])
    pool["its"] += list(tr.iterations[v])
    pool["conv"] += list(tr.converged[v])
    pool["kk"] += list(tr.kkt[v])
    pool["gaps"] += list(np.abs(tr.gaps[v]))
    for k in np.flatnonzero(v):
        d = skeleton_error(tr.skeletons[k], ref.skeletons[k])
        pool["sk"].append(d)
        pool["skf"].append(d / L)
        pool["fe"].append(footprint_error(tr.footprints[k], ref.footprints[k]))
        # the energy of our frame's own problem against the reference's (posable: polished)
        e_ref = ref.energies[k] if ref.posable[k] else ref.core_energies[k]
        pool["drift"].append(abs(tr.energies[k] - e_ref) / max(abs(e_ref), e_floor))


def _our_row(st: Setting, results: list) -> dict:
    """The row of our setting `st`, its per-frame errors pooled over the motions run at its rate."""
    if st.family == "float":
        return _row(OURS, st.label, st.family, False, [], [], [], [], [], kkt_median=None,
                    note=FLOAT_NOTE)
    pool = {key: [] for key in ("t", "gaps", "sk", "skf", "fe", "its", "conv", "kk", "drift")}
    for motion, rate, ours, ref in results:
        if rate == st.rate and st.label in ours:
            _pool_our_motion(pool, motion, ours[st.label], ref)
    label = default_label() if st.default else st.label
    gaps = pool["gaps"]
    return _row(OURS, label, st.family, st.default, pool["t"], gaps, pool["sk"], pool["skf"], pool["fe"],
                kkt_median=_median(pool["kk"]), energy_drift_median=_median(pool["drift"]),
                gap_unmeasured_frac=_mean(~np.isfinite(np.asarray(gaps, float))),
                mean_iterations=_mean(pool["its"]),
                unconverged_frac=_one_minus_mean(pool["conv"]),
                note="")


def _peer_row(p: Peer, tol: float, results: list) -> dict:
    """The row of peer `p` at tolerance `tol`, its one-frame errors pooled over the 1x motions."""
    pool = {key: [] for key in ("t", "gaps", "sk", "skf", "fe", "ok", "kk")}
    for motion, rate, _ours, ref in results:
        if rate != 1.0:
            continue
        rec = ref.peers[(p.name, tol)]
        L = motion.model().tuft_length
        v = ref.valid[rec["frame"].astype(int)] if len(rec["frame"]) else np.zeros(0, bool)
        for key, column in (("t", "times"), ("gaps", "gap"), ("sk", "skel_err"), ("fe", "fp_err"),
                            ("ok", "ok"), ("kk", "kkt")):
            pool[key] += list(rec[column][v])
        pool["skf"] += list(rec["skel_err"][v] / L)
    own = p.own_default is not None and tol == p.own_default
    note = "one-frame errors from the reference's previous frame"
    if p.stride > 1:
        note += f"; 1 posable frame in {p.stride}"
    return _row(p.name, f"{p.option}={tol:.0e}" + (" (its default)" if own else ""), "peer", False,
                pool["t"], pool["gaps"], pool["sk"], pool["skf"], pool["fe"],
                kkt_median=_median(pool["kk"]), failed_frac=_one_minus_mean(pool["ok"]), note=note)


def build_rows(results: list, setting_list: list, peer_runs: list) -> list[dict]:
    """Pool the per-frame errors of every motion into one row per solver and setting.

    results: (motion, rate, ours: label -> Trajectory, Reference) tuples."""
    return ([_our_row(st, results) for st in setting_list]
            + [_peer_row(p, tol, results) for p, tol in peer_runs])


def _err_key(row: dict) -> tuple:
    return (row["skeleton_error_mm_median"], row["energy_gap_median"], row["footprint_error_median"])


def _dominates(r: dict, d: dict) -> bool:
    """Row `r` is faster than row `d` by more than FASTER_MARGIN, no worse on the skeleton error,
    the energy gap and the footprint error medians, and better on at least one."""
    if r["ms_per_frame_median"] is None:
        return False
    faster = r["ms_per_frame_median"] < (1.0 - FASTER_MARGIN) * d["ms_per_frame_median"]
    pairs = [(a, b) for a, b in zip(_err_key(r), _err_key(d)) if a is not None and b is not None]
    return faster and all(a <= b for a, b in pairs) and any(a < b for a, b in pairs)


def front_check(rows: list[dict]) -> dict:
    """Is the default on the front of our settings at 1x poses (q_max, tolerance, Hessian)?  It is
    when no other such row dominates it (`_dominates`)."""
    d = next(r for r in rows if r["default"])
    rivals = [r for r in rows if r["solver"] == OURS and not r["default"]
              and r["family"] in ("q_max", "tolerance", "hessian")]
    dominated_by = [r["setting"] for r in rivals if _dominates(r, d)]
    return {"on_front": not dominated_by, "dominated_by": dominated_by}


def _at_least_as_accurate(r: dict, d: dict) -> bool:
    """Row `r`'s KKT residual and energy gap medians are no worse than row `d`'s."""
    return (r["kkt_median"] is not None and r["kkt_median"] <= d["kkt_median"]
            and r["energy_gap_median"] <= d["energy_gap_median"])


def _peer_ratio(prs: list[dict], d: dict) -> dict:
    """The speed verdict of one peer's rows `prs` against our default row `d`."""
    own = next((r for r in prs if "(its default)" in r["setting"]), None)
    if own is None:  # no default of its own: the 1e-6 setting, as SciPy's
        own = next((r for r in prs if "1e-06" in r["setting"]), prs[0])
    matching = [r for r in prs if _at_least_as_accurate(r, d)]
    cheapest = min(matching, key=lambda r: r["ms_per_frame_median"]) if matching else None
    return {
        "peer": own["solver"],
        "peer_setting": own["setting"],
        "time_ratio": own["ms_per_frame_median"] / d["ms_per_frame_median"],
        "ours_as_accurate": (d["kkt_median"] <= own["kkt_median"]
                             and d["energy_gap_median"] <= own["energy_gap_median"]),
        "cheapest_as_accurate_setting": cheapest["setting"] if cheapest else None,
        "cheapest_as_accurate_time_ratio": (cheapest["ms_per_frame_median"] / d["ms_per_frame_median"]
                                            if cheapest else None),
    }


def speed_ratios(rows: list[dict]) -> list[dict]:
    """Per peer: its own-default time / ours (default row), whether our default is at least as
    accurate (KKT residual on the problem each was given, and energy gap, medians: the skeleton and
    footprint errors are not head-to-head, ours along a trajectory, theirs over one frame), and
    the time ratio of the cheapest peer setting at least as accurate as our default."""
    d = next(r for r in rows if r["default"])
    names = dict.fromkeys(r["solver"] for r in rows if r["family"] == "peer")
    return [_peer_ratio([r for r in rows if r["solver"] == name], d) for name in names]
