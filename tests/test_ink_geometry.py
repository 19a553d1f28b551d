"""Ink as geometry: union, exact coverage, the swept footprint and the paper made of them."""
import math

import numpy as np
import pytest

import brushwork as bw
from brushwork import _core
from brushwork.paper import VectorPaper, ink_path, make_paper


def area(loops):
    return sum(0.5 * float(np.sum(l[:, 0] * np.roll(l[:, 1], -1) - np.roll(l[:, 0], -1) * l[:, 1])) for l in loops)


def disc(cx, cy, r, n=720):
    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    return np.c_[cx + r * np.cos(t), cy + r * np.sin(t)]


def test_the_union_of_two_overlapping_footprints_has_their_known_area():
    a = disc(0.0, 0.0, 2.0)
    b = disc(2.0, 0.0, 2.0)
    u = _core.union_loops([a, b])
    # two discs of radius r = 2 at distance d = 2: 2 pi r^2 less the lens 2 r^2 acos(d / 2r) - d/2 sqrt(4 r^2 - d^2)
    r, d = 2.0, 2.0
    lens = 2 * r * r * math.acos(d / (2 * r)) - 0.5 * d * math.sqrt(4 * r * r - d * d)
    assert len(u) == 1
    assert area(u) == pytest.approx(2 * math.pi * r * r - lens, rel=2e-4)


def test_a_discs_coverage_is_pi_r_squared():
    r, ppm = 3.3, 10.0
    cov = _core.coverage([disc(5.0, 5.2, r, 4000)], ppm, 100, 100)
    assert cov.min() >= 0.0 and cov.max() <= 1.0
    assert abs(cov.sum() / ppm**2 - math.pi * r * r) < 1e-4 * math.pi * r * r
    # a pixel wholly inside is 1, one far outside 0; the edge is partial
    assert cov[100 - 52, 50] == pytest.approx(1.0) and cov[0, 0] == 0.0
    assert 0 < np.count_nonzero((cov > 0) & (cov < 1))


def test_coverage_clips_at_the_papers_sides_and_takes_holes():
    square = np.array([[-5.0, -5.0], [5.0, -5.0], [5.0, 5.0], [-5.0, 5.0]])       # ccw, past the corner
    hole = np.array([[1.0, 1.0], [1.0, 2.0], [2.0, 2.0], [2.0, 1.0]])               # cw
    cov = _core.coverage([square, hole], 4.0, 40, 40)
    assert cov.sum() / 16.0 == pytest.approx(25.0 - 1.0, abs=1e-6)


def test_empty_degenerate_and_self_touching_loops():
    assert _core.union_loops([]) == []
    assert _core.coverage([], 10.0, 8, 8).sum() == 0.0
    line = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]])                           # no area
    assert _core.union_loops([line]) == []
    assert _core.coverage([line], 10.0, 30, 30).sum() == 0.0
    # two squares touching at a corner, as one loop through the shared point
    bow = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [2.0, 1.0], [2.0, 2.0], [1.0, 2.0], [1.0, 1.0], [0.0, 1.0]])
    assert area(_core.union_loops([bow])) == pytest.approx(2.0, abs=1e-9)
    assert _core.coverage([bow], 10.0, 25, 25).sum() / 100.0 == pytest.approx(2.0, abs=1e-6)
    with pytest.raises(ValueError):
        _core.union_loops([np.array([[0.0, 0.0], [np.nan, 1.0], [1.0, 1.0]])])


def pressed_brush(depth=0.25):
    from brushwork.recorded import root_height

    b = bw.Brush("small")
    z0, z1 = root_height(b.model, 15, 0.0) + 1.0, root_height(b.model, 15, depth)
    for k in range(30):
        b.step(bw.Pose((20.0, 20.0, z0 + (z1 - z0) * (k + 1) / 30), 15, 0))
    return b, z1


def dense_sweep(v0, v1, faces, blends=200):
    """The sweep's reference: the union of the footprints of `blends` + 1 evenly spaced blends."""
    loops = []
    for t in np.linspace(0.0, 1.0, blends + 1):
        vt = (1.0 - t) * v0 + t * v1
        loops += _core.swept_footprint(vt, vt, faces)[0]
    return _core.union_loops(loops)


@pytest.mark.parametrize("move", [(1.0, 0.0, 0.0), (0.7, 0.5, 12.0), (0.0, 0.0, 25.0)])
def test_the_swept_footprint_is_the_continuous_sweep(move):
    """A pressed tuft moved (dx mm, dy mm, a turn of the handle in deg) in one frame: the region
    swept_footprint gives covers the dense blends' union and exceeds it by little."""
    b, z1 = pressed_brush()
    opt = VectorPaper(60, 40, 10).mesh_options(b.model)
    v0, f, _ = b.surface_mesh(opt)
    f = f.astype(np.int32)
    still, k = _core.swept_footprint(v0, v0, f)
    # a still tuft leaves its footprint, its outline simplified to within half the tolerance
    fp = _core.union_loops(_core.footprint_projection(v0, f))
    perimeter = sum(float(np.sum(np.linalg.norm(l - np.roll(l, 1, axis=0), axis=1))) for l in fp)
    assert k == 1 and abs(area(_core.union_loops(still)) - area(fp)) <= 0.5 * 0.005 * perimeter
    b.step(bw.Pose((20.0 + move[0], 20.0 + move[1], z1), 15, move[2]))
    v1, _, _ = b.surface_mesh(opt)
    missed, extra, k = against_dense_sweep(v0, v1, f)
    # at 40 px/mm: missed and extra pixels of the reference, each at most a hundredth of its area
    assert missed <= 0.01 and extra <= 0.01, (k, missed, extra)


def against_dense_sweep(v0, v1, faces):
    """The pixels (40 px/mm) of the dense sweep's region that swept_footprint's region misses, and
    those it adds, each as a fraction of the dense sweep's; and the blends it took."""
    region, k = _core.swept_footprint(v0, v1, faces)
    swept, ref = _core.union_loops(region), dense_sweep(v0, v1, faces, 400)
    a = _core.coverage(swept, 40.0, 40 * 40, 40 * 40) > 0.5
    r = _core.coverage(ref, 40.0, 40 * 40, 40 * 40) > 0.5
    n = np.count_nonzero(r)
    return np.count_nonzero(r & ~a) / n, np.count_nonzero(a & ~r) / n, k


def test_a_tuft_that_springs_back_as_it_lifts_sweeps_its_whole_region():
    """A tuft dragged 3 mm, bent behind its root, then lifted 0.35 mm in one frame while the root
    moves on 1 mm: its footprint shrinks back towards the root, against the move, before it goes
    on. The band between its blends folds there; the sweep keeps both sides of the fold and the
    footprint where it turns."""
    b, z1 = pressed_brush(depth=0.3)
    x, y = 20.0, 20.0
    for _ in range(20):
        x, y = x + 2.61 / 20, y + 1.47 / 20
        b.step(bw.Pose((x, y, z1), 15, 0))
    opt = VectorPaper(60, 40, 10).mesh_options(b.model)
    v0, f, _ = b.surface_mesh(opt)
    b.step(bw.Pose((x + 0.71, y + 0.72, z1 + 0.35), 15, -1.1))
    v1, _, _ = b.surface_mesh(opt)
    missed, extra, k = against_dense_sweep(v0, v1, f.astype(np.int32))
    assert missed <= 0.005 and extra <= 0.001, (k, missed, extra)


def dragged_brush(frames=45):
    """A small brush dragged along a straight line at a steady press 0.2 L, `frames` frames of 1 mm,
    with kai's smoothed friction: its belly flattened, the lowest sections' widest points below
    the paper."""
    from brushwork.recorded import along_path

    s = np.linspace(0.0, 1.0, 91)
    model = bw.BrushModel.preset("small")
    model.friction_smoothing = 0.5
    b = bw.Brush(model)
    for pose in along_path(model, np.c_[15.0 + 70.0 * s, 30.0 + 0.0 * s], 0.2 + 0.0 * s, step_mm=1.0)[:frames]:
        b.step(pose)
    return b


def below_paper_raster(v, faces, px_per_mm, width, height):
    """(height, width) bool: the pixel centres under some face's part below z = 0 (each face
    clipped at the paper and filled), row 0 at the top as coverage() has it."""
    import cv2

    img = np.zeros((height, width), np.uint8)
    for tri in v[faces]:
        pts = []
        for a, c in zip(tri, np.roll(tri, -1, axis=0)):
            if a[2] < 0.0:
                pts.append(a[:2])
            if (a[2] < 0.0) != (c[2] < 0.0):
                pts.append((a + a[2] / (a[2] - c[2]) * (c - a))[:2])
        if len(pts) >= 3:
            px = np.c_[np.array(pts)[:, 0] * px_per_mm - 0.5, height - np.array(pts)[:, 1] * px_per_mm - 0.5]
            cv2.fillPoly(img, [np.round(px * 16).astype(np.int32)], 1, cv2.LINE_8, 4)
    return img.astype(bool)


def test_a_footprint_is_the_projection_of_the_part_below_the_paper():
    """The seed's footprint is the orthogonal projection of the penetrating portion of the tuft
    onto the paper. Dragged at a steady press the belly flattens until its sections' widest
    points lie below the paper: the projection matches every face's part below the paper
    filled, and reaches past the plane section (the contact polygon) by several percent."""
    b = dragged_brush()
    opt = VectorPaper(60, 40, 10).mesh_options(b.model)
    v, f, _ = b.surface_mesh(opt)
    f = f.astype(np.int32)
    proj = _core.union_loops(_core.footprint_projection(v, f))
    ppm, w, h = 100.0, 100 * 100, 60 * 100
    got = _core.coverage(proj, ppm, w, h) > 0.5
    ref = below_paper_raster(v, f, ppm, w, h)
    assert np.count_nonzero(got & ref) / np.count_nonzero(got | ref) >= 0.99
    assert area(proj) >= 1.05 * area(_core.union_loops(b.footprint(opt)))


def test_both_papers_take_the_projected_footprint():
    """One deposit of the dragged tuft: the geometry's ink and the GL footprint pass's agree in
    area (both the projection of the part below the paper)."""
    b = dragged_brush()
    inks = {}
    for ink in ("geometry", "gl"):
        paper = make_paper(100, 60, 10, bw.Scene(samples=1), ink)
        paper.deposit(b)
        paper.end_stroke()
        inks[ink] = float(paper.ink().sum())
    assert abs(inks["geometry"] - inks["gl"]) <= 0.015 * inks["gl"], inks



@pytest.mark.parametrize("char, style, floor", [("永", "kai-driver", 0.99), ("和", "kai-driver", 0.99),
                                                ("明", "kai-driver", 0.99), ("永", "kai", 0.97)])
def test_a_character_written_both_ways_is_the_same_ink(char, style, floor):
    """A character at 512 px, inked by the geometry and by the GL footprint pass. The driver's
    motions are the same on both papers: the rasters overlap with IoU >= 0.99 (both draw the
    seed's projected footprint; what is left is the GL pass's slides at a lift and its pixel
    sampling). Plans split a frame in which the tuft snaps into substeps on a GL paper only
    (planned.SNAP_MM), each solved: kai's two inks differ by those solves too."""
    from pathlib import Path

    from brushwork.glyphs import load_source
    from brushwork.glyphs.score import iou
    from brushwork.writing import text_paper

    glyph = load_source(f"mmah:{Path(__file__).parent / 'data' / 'mmah' / 'graphics.txt'}", char)[char]
    geometry, gl = (text_paper([glyph], 512, style, ink=ink).ink() > 0.5 for ink in ("geometry", "gl"))
    assert iou(geometry, gl) >= floor


def test_a_long_move_wets_each_slid_copy_of_the_footprint_once():
    """The wetted paper a deposit spends ink on is its footprint slid back along the move, 64
    copies at most: after a jump of 900 mm every copy lies apart, so the paper gains 64
    footprints' area, whether the move runs along the rows of cells (gathered together) or
    across them (too many rows: raised a copy at a time)."""
    gains = []
    for dx, dy in ((900.0, 0.0), (0.0, 900.0)):
        b, z1 = pressed_brush()
        b.load_ink(total_mm2=1e6)
        paper = VectorPaper(60, 40, 10, scene=bw.Scene(depletion=True))
        first = paper.deposit(b).deposited
        b.step(bw.Pose((20.0 + dx, 20.0 + dy, z1), 15, 0))
        gains.append(paper.deposit(b).deposited / first)
    assert gains[0] == pytest.approx(64.0, rel=0.015) and gains[1] == pytest.approx(gains[0], rel=1e-3), gains


def write_stroke(paper):
    b, z1 = pressed_brush()
    for k in range(25):
        paper.deposit(b)
        b.step(bw.Pose((20.0 + 0.8 * (k + 1), 20.0 + 4 * math.sin(k / 6), z1), 15, 0))
    paper.end_stroke()
    return paper


def test_a_vector_paper_stroke_matches_the_gl_pass_and_repeats_exactly():
    geo = write_stroke(VectorPaper(60, 40, 10))
    gl = write_stroke(bw.Paper(60, 40, 10, scene=bw.Scene(samples=4)))
    a, b = geo.ink() > 0.5, gl.ink() > 0.5
    iou = np.count_nonzero(a & b) / np.count_nonzero(a | b)
    assert iou > 0.97, iou
    # the outlines' area is the raster's ink, and a second writing gives the same bytes
    assert area(geo.outlines()) == pytest.approx(float(geo.ink().sum()) / 100.0, rel=1e-3)
    again = write_stroke(VectorPaper(60, 40, 10))
    assert np.array_equal(again.image(), geo.image())
    assert geo.undo() and geo.ink().sum() == 0.0


def test_every_readback_of_a_geometry_paper_shows_the_same_ink():
    """ink(), rgba() and image() (over white and on transparency, 8 and 16 bits) agree pixel for
    pixel, on a paper of one ink (read out over its strokes' box of pixels only) and of two, and
    the bare paper around the strokes reads as clear in every one."""
    one = write_stroke(VectorPaper(60, 40, 10))
    two = write_stroke(VectorPaper(60, 40, 10))
    b, z1 = pressed_brush()
    b.load_ink(ramp=[(0.8, 0.1, 0.1, 1.0)])
    b.step(bw.Pose((8.0, 8.0, z1), 15, 0))
    two.deposit(b)
    two.end_stroke()
    for paper in (one, two):
        ink, rgba = paper.ink(), paper.rgba()
        assert np.array_equal(rgba[..., 3], ink)
        clear = ink == 0.0
        assert clear[0].all() and clear[-1].all() and clear[:, 0].all() and clear[:, -1].all()
        for bits, top in ((8, 255), (16, 65535)):
            over = paper.image(bits=bits).astype(float)
            straight = paper.image(bits=bits, background="transparent").astype(float)
            # over white: 1 - a + premultiplied colour; on transparency: the alpha itself
            want = np.round(np.clip(1.0 - ink[..., None] + rgba[..., :3], 0.0, 1.0) * top)
            assert np.abs(over - want).max() <= 1.0
            assert np.abs(straight[..., 3] - np.round(ink * top)).max() <= 1.0
            assert (over[clear] == top).all() and (straight[clear] == 0).all()
    assert np.count_nonzero(two.ink()) > np.count_nonzero(one.ink())


def test_the_scene_chooses_the_path():
    assert ink_path(bw.Scene(), "auto") == "geometry"
    assert ink_path(bw.Scene(depletion=True), "auto") == "geometry"
    assert ink_path(bw.Scene(dry_map=True), "auto") == "gl"
    with pytest.raises(ValueError, match="dry_map"):
        ink_path(bw.Scene(dry_map=True), "geometry")
    with pytest.raises(ValueError, match="ink"):
        ink_path(bw.Scene(), "vector")
    assert isinstance(make_paper(10, 10, 4, bw.Scene(), "auto"), VectorPaper)
    assert bw.render_info()["ink"] == "geometry"


def closed_resample(loop, step=1.0):
    """A closed polyline resampled every `step` of arc."""
    p = np.vstack([loop, loop[:1]])
    s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))]
    t = np.arange(0.0, s[-1], step)
    return np.c_[np.interp(t, s, p[:, 0]), np.interp(t, s, p[:, 1])]


def contour_figures(loop_px, reach=8, sigma=12.0, away_px=0):
    """(sharp turns, deviation px) of a closed contour in px: turns of more than 45 deg between
    the chords `reach` px of arc behind and ahead (a run of such points is one turn), and the rms
    distance of the contour from its copy smoothed along the arc (Gaussian, sigma px), less the
    smooth part of that distance (a round end's smoothed copy lies inside it by sigma^2 / 2r),
    over the points at least `away_px` of arc from every sharp turn."""
    p = closed_resample(loop_px)
    n = len(p)
    a, b = p - np.roll(p, reach, axis=0), np.roll(p, -reach, axis=0) - p
    cos = np.sum(a * b, axis=1) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1) + 1e-12)
    sharp = cos < math.cos(math.radians(45.0))
    turns = int(np.count_nonzero(sharp & ~np.roll(sharp, 1))) if not sharp.all() else 1

    def smooth(x):
        k = np.arange(-int(4 * sigma), int(4 * sigma) + 1)
        w = np.exp(-0.5 * (k / sigma) ** 2)
        w /= w.sum()
        return sum(wi * np.roll(x, -ki, axis=0) for ki, wi in zip(k, w))

    d = p - smooth(p)
    rough = d - smooth(d)
    assert n > 100
    # arc (px, points 1 px apart) from each point to the nearest sharp one, the long way round excluded
    i, at = np.arange(n), np.flatnonzero(sharp)
    gap = np.min(np.abs((i[:, None] - at[None, :] + n // 2) % n - n // 2), axis=1) if len(at) else np.full(n, n)
    keep = gap >= away_px
    return turns, float(np.sqrt(np.mean(np.sum(rough[keep] ** 2, axis=1))))


def s_curve_poses(model):
    """A small brush comes down, writes an S-curve of 90 mm at 1 mm a frame whose press swells and
    eases, and lifts: open-loop, no driver."""
    from brushwork.recorded import along_path

    s = np.linspace(0.0, 1.0, 91)
    pts = np.c_[15.0 + 70.0 * s, 30.0 + 14.0 * np.sin(2.0 * np.pi * s)]
    press = 0.12 + 0.12 * np.sin(np.pi * s) ** 2
    return along_path(model, pts, press, step_mm=1.0)


def s_curve_outline(model):
    """The outer contour (mm) of the open-loop S-curve written with `model` on a geometry paper."""
    paper = VectorPaper(100, 60, 20)
    brush = bw.Brush(model)
    for pose in s_curve_poses(model):
        brush.step(pose)
        paper.deposit(brush)
    paper.end_stroke()
    return max(paper.outlines(), key=lambda l: abs(area([l])))


def test_smoothed_paper_friction_takes_the_chatter_off_the_edge():
    """At 1 mm a frame the paper's friction energy sqrt(|dx|^2 + eps^2) - eps is nearly |dx| with
    the preset's eps (0.05 mm): its stick and slip chatter a frame apart on the ink's edge.
    Smoothed over half a frame (kai's 0.5 mm) the edge of the same open-loop S-curve keeps closer
    to its smoothed copy, and it is no sharper."""
    figures = {}
    for eps in (0.05, 0.5):
        model = bw.BrushModel.preset("small")
        model.friction_smoothing = eps
        figures[eps] = contour_figures(s_curve_outline(model) * 20.0)
    assert figures[0.5][1] <= 0.9 * figures[0.05][1], figures
    assert figures[0.5][0] <= figures[0.05][0], figures


def test_an_open_loop_s_curve_leaves_a_smooth_contour():
    """At 20 px/mm (a 2048 px glyph's scale) the contour has no comb of teeth a frame apart and
    no corners where the pressed tuft came down (its tip closes round): at most 2 sharp turns
    (the flick of its lift), and its edge keeps within 0.3 px of its smoothed copy (the footprint
    pass: 0.47 px). The flick's point is sharp, as an exit should be, and no Gaussian copy follows
    a point (a few px there lie over 3 px from it); a millimetre of arc away from it the edge keeps
    within 0.15 px."""
    outer = s_curve_outline(bw.BrushModel.preset("small"))
    turns, deviation = contour_figures(outer * 20.0)
    assert area([outer]) > 100.0
    assert turns <= 2, turns
    assert deviation <= 0.3, deviation
    _, away = contour_figures(outer * 20.0, away_px=20)
    assert away <= 0.15, away
    assert away < 0.7 * deviation, (away, deviation)


def test_render_writes_the_outlines_as_svg_and_pdf(tmp_path, capsys):
    import re

    from brushwork import cli

    svg, pdf = tmp_path / "yi.svg", tmp_path / "yi.pdf"
    assert cli.main(["render", "一", "-o", str(svg), "--size", "256"]) == 0
    assert cli.main(["render", "一", "-o", str(pdf), "--size", "256"]) == 0
    text = svg.read_text()
    assert text.startswith("<svg") and 'viewBox="0 0 100 100"' in text
    loops = [np.array(re.findall(r"[ML]([-\d.]+) ([-\d.]+)", d), dtype=float) for d in re.findall(r"M[^Z]*Z", text)]
    paper = VectorPaper(100, 100, 2.56)
    from brushwork.writing import text_paper
    from brushwork.glyphs import load_source

    ref = text_paper([load_source("default", "一")["一"]], 256, "kai", ink="geometry").outlines()
    # (svg's y runs down: the area's sign turns, its size stays)
    assert abs(area(loops)) == pytest.approx(abs(area(ref)), rel=1e-3) and abs(area(ref)) > 50.0
    data = pdf.read_bytes()
    assert data.startswith(b"%PDF-1.4") and data.rstrip().endswith(b"%%EOF") and b"/MediaBox" in data
    assert cli.main(["render", "一", "-o", str(tmp_path / "x.svg"), "--ink", "gl"]) == 2
    assert "vector outlines come from the ink's geometry" in capsys.readouterr().err
    assert paper.outlines() == []
