"""The brush demo: a pressed, dragged brush and its footprints, drawn to one PNG.

This is the README's main job until the renderer lands: it exercises the whole core (pressing,
lateral spreading, a tilted drag with the tip trailing, a turn, the lift) and shows it.
"""
from __future__ import annotations

import os
import sys
import tempfile

import numpy as np

from ._core import BrushModel, MeshOptions
from .brush import Brush
from .extras import install_hint
from .recorded import press_drag_turn_lift


def _draw_brush_3d(ax, brush: Brush, title: str) -> None:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    verts, faces, _ = brush.surface_mesh(MeshOptions(6, 24))
    tris = verts[faces]                                  # (F, 3, 3) mm
    # shade each triangle by its normal against a light from the upper left
    nrm = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True) + 1e-12
    light = np.array([-0.4, -0.5, 0.77])
    shade = 0.35 + 0.65 * np.clip(nrm @ light, 0, 1)
    below = tris[:, :, 2].mean(axis=1) < 0
    colors = np.stack([0.55 * shade, 0.42 * shade, 0.32 * shade, np.full_like(shade, 0.9)], axis=1)
    colors[below] = [0.1, 0.1, 0.1, 0.9]
    ax.add_collection3d(Poly3DCollection(tris, facecolors=colors, linewidths=0))
    sk = brush.skeleton()
    ax.plot(sk[:, 0], sk[:, 1], sk[:, 2], "o-", color="crimson", ms=3, lw=1.2, zorder=10)
    lat = brush.lateral_nodes()
    ax.scatter(lat[:, :, 0].ravel(), lat[:, :, 1].ravel(), lat[:, :, 2].ravel(), s=6, c="navy")
    for loop in brush.footprint():
        p = np.vstack([loop, loop[:1]])
        ax.plot(p[:, 0], p[:, 1], np.zeros(len(p)), color="k", lw=1.5)
    c = sk.mean(axis=0)
    r = 0.6 * np.ptp(np.vstack([verts, sk]), axis=0).max()
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(0, 2 * r)
    xx, yy = np.meshgrid([c[0] - r, c[0] + r], [c[1] - r, c[1] + r])
    ax.plot_surface(xx, yy, np.zeros_like(xx), color="wheat", alpha=0.35)
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("x (mm)", fontsize=7)
    ax.set_ylabel("y (mm)", fontsize=7)
    ax.set_zlabel("z (mm)", fontsize=7)
    ax.tick_params(labelsize=6)
    ax.view_init(elev=18, azim=-60)


PLOT_HINT = f"the demo's figure needs matplotlib: {install_hint('plot')}"


def _pyplot():
    """matplotlib's pyplot on the Agg backend; ModuleNotFoundError saying how to get it when missing."""
    try:
        import matplotlib
    except ModuleNotFoundError:
        raise ModuleNotFoundError(PLOT_HINT, name="matplotlib") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def render_demo(path: str, preset: str = "medium", frames: int = 320) -> dict:
    """Simulate press_drag_turn_lift with `preset` and write the figure to `path` (PNG).

    Returns a summary: frames, mean iterations, footprint areas (mm^2) at the snapshots.
    """
    plt = _pyplot()
    from matplotlib.patches import Polygon

    model = BrushModel.preset(preset)
    poses = press_drag_turn_lift(model, frames)
    brush = Brush(model)
    snaps = {int(frames * 0.12) - 1: "pressed", int(frames * 0.35): "dragged (+x)",
             int(frames * 0.62): "turning", int(frames * 0.85): "lifting"}
    fig = plt.figure(figsize=(13, 8.5), dpi=110)
    gs = fig.add_gridspec(2, 4, height_ratios=[1.0, 1.0])
    top = fig.add_subplot(gs[1, :3])
    area_ax = fig.add_subplot(gs[1, 3])
    iters, areas, summary = [], [], {"snapshots": {}}
    k_panel = 0
    for k, pose in enumerate(poses):
        s = brush.step(pose)
        iters.append(s.iterations)
        area = brush.footprint_area()
        areas.append(area)
        # every footprint, filled: the stroke this brush would leave without the ink model
        for loop in brush.footprint():
            top.add_patch(Polygon(loop, closed=True, fc=(0, 0, 0, 0.08), ec="none"))
        if k % 8 == 0:
            sk = brush.skeleton()
            top.plot(sk[:, 0], sk[:, 1], color="crimson", lw=0.5, alpha=0.6)
        if k in snaps:
            ax = fig.add_subplot(gs[0, k_panel], projection="3d")
            _draw_brush_3d(ax, brush, f"{snaps[k]}: frame {k}, {s.iterations} it, "
                                      f"footprint {area:.1f} mm$^2$")
            summary["snapshots"][snaps[k]] = area
            k_panel += 1
            for loop in brush.footprint():
                top.add_patch(Polygon(loop, closed=True, fc="none", ec="k", lw=0.8))
    top.set_aspect("equal")
    top.autoscale_view()
    top.set_title("footprints of every frame (grey), snapshots outlined, spine every 8th frame (red)",
                  fontsize=9)
    top.set_xlabel("x (mm)")
    top.set_ylabel("y (mm)")
    area_ax.plot(areas, color="k", lw=1)
    area_ax.set_xlabel("frame")
    area_ax.set_ylabel("footprint area (mm$^2$)")
    ax2 = area_ax.twinx()
    ax2.plot(iters, color="tab:blue", lw=0.6, alpha=0.7)
    ax2.set_ylabel("SQP iterations", color="tab:blue")
    area_ax.set_title(f"mean {np.mean(iters):.1f} iterations / frame", fontsize=9)
    fig.suptitle(f"brushwork: the '{preset}' brush pressed, dragged, turned and lifted "
                 f"({len(poses)} frames)", fontsize=11)
    fig.tight_layout()
    # write atomically: a reader never sees half a PNG
    d = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(suffix=".png", dir=d)
    os.close(fd)
    try:
        fig.savefig(tmp)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes it private; a picture is for everyone
        os.replace(tmp, path)
    finally:
        plt.close(fig)
        if os.path.exists(tmp):
            os.remove(tmp)
    summary.update(frames=len(poses), mean_iterations=float(np.mean(iters)),
                   max_area=float(np.max(areas)))
    return summary


def main(path: str = "brush_demo.png") -> int:
    try:
        summary = render_demo(path)
    except ModuleNotFoundError as exc:
        if exc.name != "matplotlib":
            raise
        print(f"brushwork: error: {PLOT_HINT}", file=sys.stderr)
        return 2
    print(f"wrote {path}: {summary['frames']} frames, mean {summary['mean_iterations']:.2f} "
          f"SQP iterations per frame, largest footprint {summary['max_area']:.1f} mm^2",
          file=sys.stderr)
    return 0
