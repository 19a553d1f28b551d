"""Work-precision benchmark: the Markdown report and the plot."""
from __future__ import annotations

import numpy as np

from .config import INK_NOTE, OURS, TUFTS_NOTE


def table(result: dict) -> str:
    """The Markdown report: the main table, the verdicts, Table 1 and the reference summary."""
    from ..report import format_value, markdown_table

    rows = [dict(r, default="**yes**" if r["default"] else "") for r in result["rows"]]
    for r in rows:
        if r["solver"] == OURS and r["family"] != "float":
            r["extra"] = (f"{format_value(r['mean_iterations'])} it/frame, "
                          f"{100 * r['unconverged_frac']:.0f}% unconverged")
        elif r["family"] == "peer":
            r["extra"] = (f"{100 * r['failed_frac']:.0f}% reported failure" if r.get("failed_frac") is not None
                          else "") + (f"; {r['frames']} frames" if r["frames"] else "")
        else:
            r["extra"] = r.get("note", "")
    out = [f"Machine: {result['machine']}.", ""]
    out.append(markdown_table(
        rows, ["solver", "setting", "default", "ms_per_frame_median", "ms_per_frame_p95",
               "kkt_median", "energy_gap_median", "skeleton_error_mm_median",
               "skeleton_error_frac_median", "footprint_error_median", "ink_mask_iou_median", "extra"],
        ["solver", "setting", "default", "ms/frame p50", "ms/frame p95", "KKT p50", "energy gap p50",
         "skeleton err p50 (mm)", "skeleton err p50 (/L)", "footprint 1-IoU p50", "character ink IoU", "notes"]))
    out.append("")
    out.append(f"Character ink IoU: {INK_NOTE}.")
    out.append(f"Footprint IoU by: {result['footprint_iou']}.")
    for n in result["notes"]:
        out.append(f"Note: {n}.")
    f = result["front"]
    out.append("")
    out.append("Shipped default on the front of our settings: " + (
        "yes (no setting of ours is both faster and more accurate)" if f["on_front"]
        else "NO, dominated by " + ", ".join(f["dominated_by"])) + ".")
    for s in result["speed_ratios"]:
        line = (f"{s['peer']} at {s['peer_setting']}: {format_value(s['time_ratio'])}x our default's "
                f"time per frame; our default {'is' if s['ours_as_accurate'] else 'is NOT'} at least "
                f"as accurate (KKT residual and energy gap medians)")
        if s["cheapest_as_accurate_setting"]:
            line += (f"; its cheapest setting as accurate as our default ({s['cheapest_as_accurate_setting']}) "
                     f"takes {format_value(s['cheapest_as_accurate_time_ratio'])}x")
        else:
            line += "; none of its settings is as accurate as our default"
        out.append(line + ".")
    out.append("")
    out.append("Seed Table 1, redone (six-segment tufts, `medium`, press-drag-turn-lift):")
    out.append("")
    out.append(markdown_table(
        result["table1"], ["tufts", "q_max", "fresh_mean_q", "fresh_fps", "carried_mean_q", "carried_fps"],
        ["tufts", "q_max", "fresh Hessian: mean q", "frames/s", "carried Hessian: mean q", "frames/s"]))
    out.append("")
    out.append(f"{TUFTS_NOTE}.")
    out.append("")
    out.append("References (core at tolerance 1e-10, then the Newton polish):")
    out.append("")
    out.append(markdown_table(
        result["reference"], ["motion", "rate", "frames", "posable_frames", "valid_frames",
                              "reference_failed_at", "core_kkt_median", "core_kkt_max",
                              "polished_kkt_max", "probe_resyncs"],
        ["motion", "rate", "frames", "posable", "valid", "first failed frame",
         "core KKT p50", "core KKT max", "polished KKT max (valid)", "probe resyncs"]))
    return "\n".join(out)


PLOT_FLOOR = 1e-12   # errors of exactly 0 are drawn at this height of the log axis
PLOT_METRICS = (("skeleton_error_mm_median", "skeleton error, median over frames (mm)",
                 "against the reference: ours along our own trajectory, peers over one frame\n"
                 "from the reference's previous frame (not head to head)"),
                ("energy_gap_median", "relative energy gap, median over frames",
                 "on the frame problem each solver was given, against its exact minimum\n"
                 "(head to head)"))
FAMILY_STYLES = {"q_max": ("tab:blue", "o"), "tolerance": ("tab:green", "s"), "hessian": ("tab:purple", "D"),
                 "rate": ("tab:brown", "^")}
PEER_COLORS = ["tab:red", "tab:orange", "tab:gray"]


def _curve_style(solver: str, family: str, peer_index: int) -> tuple[str, str, str]:
    """(colour, marker, legend name) of one curve; `peer_index` counts the peer curves drawn so far."""
    if solver == OURS:
        color, marker = FAMILY_STYLES.get(family, ("black", "o"))
        return color, marker, f"ours: {family} sweep" if family != "hessian" else "ours: fresh Hessian"
    return PEER_COLORS[peer_index % len(PEER_COLORS)], "x", solver


def _point_tag(r: dict) -> str:
    """The text beside one point: its setting, short (q20 for q_max=20), none for the default."""
    if r["default"]:
        return ""
    tag = r["setting"].split(" (")[0]
    return tag.replace("q_max=", "q") if r["solver"] == OURS and r["family"] == "q_max" else tag


def _plot_metric(ax, curves: dict, default_row: dict, metric: tuple) -> None:
    """Draw on `ax` one error `metric` (key, axis label, title) against the time per frame: one
    curve per (solver, family) in `curves`, the shipped default starred."""
    key, label, title = metric
    peer_index = 0
    for (solver, family), rs in curves.items():
        rs = sorted(rs, key=lambda r: r["ms_per_frame_median"])
        x = [r["ms_per_frame_median"] for r in rs]
        y = [max(r[key] if r[key] is not None else np.nan, PLOT_FLOOR) for r in rs]
        color, marker, name = _curve_style(solver, family, peer_index)
        peer_index += solver != OURS
        ax.plot(x, y, marker=marker, color=color, label=name, lw=1.2, ms=6)
        for r, xi, yi in zip(rs, x, y):
            ax.annotate(_point_tag(r), (xi, yi), textcoords="offset points", xytext=(4, 4), fontsize=7,
                        color=color)
    ax.plot([default_row["ms_per_frame_median"]], [max(default_row[key], PLOT_FLOOR)], marker="*", ms=18,
            color="gold", mec="black", ls="none", label="shipped default", zorder=5)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("time per frame, median (ms)")
    ax.set_ylabel(label)
    ax.grid(True, which="both", alpha=0.3)


PLOT_HINT = "plot skipped: it needs matplotlib (pip install 'brushwork[plot]')"


def plot(result: dict, path: str) -> bool:
    """Log-log plot of the error medians against the median time per frame, one curve per
    solver and setting family, the shipped default starred; written atomically to `path` (PNG).
    False, and nothing written, when matplotlib is not installed."""
    try:
        import matplotlib
    except ImportError:
        return False
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..report import write_atomic

    rows = [r for r in result["rows"] if r["ms_per_frame_median"] is not None]
    curves: dict = {}
    for r in rows:
        curves.setdefault((r["solver"], r["family"]), []).append(r)
    default_row = next(r for r in rows if r["default"])
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5))
    for ax, metric in zip(axes, PLOT_METRICS):
        _plot_metric(ax, curves, default_row, metric)
    axes[0].legend(fontsize=8, loc="best")
    fig.suptitle("brushwork: error against time per frame (" + result["machine"].split(",")[0] + ")",
                 fontsize=10)
    fig.tight_layout()
    try:
        write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"), suffix=".png")
    finally:
        plt.close(fig)
    return True
