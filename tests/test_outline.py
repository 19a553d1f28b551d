"""3-D outlines on procedural meshes: lines, visibility, chains, the camera file, bad meshes, the CLI."""
import json

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")

from brushwork.cli import main  # noqa: E402
from brushwork.outline3d import View, draw, fit, load_mesh, prepare  # noqa: E402
from brushwork.outline3d.lines import BOUNDARY, CREASE, SILHOUETTE  # noqa: E402
from brushwork.outline3d.strokes import OutlineStyle  # noqa: E402
from brushwork.bench.outline import lowpoly_set, score  # noqa: E402

SIZE = 256


def _draw(mesh, kinds=("silhouette", "boundary", "crease"), view=None, hidden="none", style="baimiao"):
    surface = prepare(mesh.vertices, mesh.faces)
    return draw(surface, view or View(30.0, 20.0, 30.0, (SIZE, SIZE)), OutlineStyle.load(style), kinds, 60.0, hidden)


def _chains(drawing, kind, visible=True):
    return [c for c in drawing.chains if c.kind == kind and c.visible == visible]


def test_sphere_outline_is_one_long_closed_contour_drawn_all_round():
    d = _draw(trimesh.creation.icosphere(subdivisions=2))
    loops = _chains(d, SILHOUETTE)
    assert len(loops) == 1 and loops[0].closed
    assert loops[0].length > 0.9 * np.pi * 0.8 * SIZE * 0.8     # about the fitted disc's circumference
    s = score(d)
    assert s["recall"] >= 0.95 and s["precision"] >= 0.9


def test_torus_hole_is_outlined_too():
    d = _draw(trimesh.creation.torus(1.0, 0.3, major_sections=48, minor_sections=16),
              view=View(0.0, 60.0, 30.0, (SIZE, SIZE)))
    assert len(_chains(d, SILHOUETTE)) >= 2                    # outer outline and the hole
    assert score(d)["recall"] >= 0.95


def test_box_creases_seen_and_hidden():
    box = trimesh.creation.box((1.0, 1.0, 1.0))
    d = _draw(box, kinds=("crease",), hidden="faint")
    # a cube edge is seen when one of its two faces faces the eye: 9 of 12 from above and aside
    ends = d.camera.project(box.vertices)[:, :2]
    seen = hidden = 0.0
    sharp = box.face_adjacency_angles > 1.0                      # the 12 cube edges, not the faces' diagonals
    for (a, b), (f, g) in zip(box.face_adjacency_edges[sharp], box.face_adjacency[sharp]):
        mid = 0.5 * (box.vertices[a] + box.vertices[b])
        front = [(d.camera.eye - mid) @ box.face_normals[k] > 0 for k in (f, g)]
        length = np.linalg.norm(ends[a] - ends[b])
        seen, hidden = (seen + length, hidden) if any(front) else (seen, hidden + length)
    drawn = sum(c.length for c in _chains(d, CREASE))
    drawn_hidden = sum(c.length for c in _chains(d, CREASE, visible=False))
    assert 0.85 * seen < drawn <= seen + 1 and 0.7 * hidden < drawn_hidden <= hidden + 1
    assert _draw(box, kinds=("silhouette",)).stats["chains"] >= 1


def _open_cylinder():
    mesh = trimesh.creation.cylinder(radius=0.5, height=2.0, sections=48)
    side = np.abs(mesh.face_normals[:, 2]) < 0.5
    return trimesh.Trimesh(mesh.vertices, mesh.faces[side], process=False)


def test_open_cylinder_rims_are_boundaries():
    mesh = _open_cylinder()
    d = _draw(mesh, view=View(0.0, 0.0, 30.0, (SIZE, SIZE)))   # side on: y is the view's up, the axis is z
    assert len(_chains(d, BOUNDARY)) >= 2
    d = _draw(mesh, kinds=("boundary",), view=View(0.0, 70.0, 30.0, (SIZE, SIZE)), hidden="faint")
    assert len(_chains(d, BOUNDARY, visible=False)) >= 1       # the far rim's back half
    assert d.stats["strokes"] == len(d.chains)


def test_line_behind_a_box_is_not_drawn():
    box = trimesh.creation.box((2.0, 2.0, 2.0))
    sheet = trimesh.Trimesh([[-0.5, -0.5, -3.0], [0.5, -0.5, -3.0], [0.5, 0.5, -3.0], [-0.5, 0.5, -3.0]],
                            [[0, 1, 2], [0, 2, 3]])
    view = View(0.0, 0.0, 20.0, (SIZE, SIZE))                  # the eye on +z: the sheet hides behind the box
    behind = trimesh.util.concatenate([box, sheet])
    d = _draw(behind, kinds=("boundary",), view=view)
    assert not _chains(d, BOUNDARY) and d.paper.ink().max() == 0      # nothing drawn
    faint = _draw(behind, kinds=("boundary",), view=view, hidden="faint")
    assert _chains(faint, BOUNDARY, visible=False)                    # it was found, and hidden
    assert 0 < faint.paper.ink().max() < 0.5                          # drawn light
    aside = sheet.copy()
    aside.apply_translation([3.0, 0.0, 0.0])
    d = _draw(trimesh.util.concatenate([box, aside]), kinds=("boundary",), view=view)
    assert len(_chains(d, BOUNDARY)) >= 1


def test_camera_json_puts_vertices_on_the_drawing(tmp_path):
    import cv2

    big = trimesh.creation.icosphere(subdivisions=2)
    small = trimesh.creation.icosphere(subdivisions=2, radius=0.3).apply_translation([2.0, 1.2, 0.0])
    mesh = trimesh.util.concatenate([big, small])
    mesh.apply_scale(37.0)
    mesh.apply_translation([100.0, -20.0, 5.0])                 # any units, anywhere
    src, out, cam = tmp_path / "balls.ply", tmp_path / "balls.png", tmp_path / "cam.json"
    mesh.export(src)
    assert main(["outline", str(src), "-o", str(out), "--size", str(SIZE), "--camera-json", str(cam),
                 "--azimuth", "20", "--elevation", "-10"]) == 0
    data = json.loads(cam.read_text())
    assert data["size"] == [SIZE, SIZE]
    M = np.array(data["matrix"])
    p = np.column_stack([mesh.vertices, np.ones(len(mesh.vertices))]) @ M.T
    xy = p[:, :2] / p[:, 3:4]
    ink = cv2.imread(str(out), cv2.IMREAD_GRAYSCALE) < 128
    ys, xs = np.nonzero(ink)
    # the outline hugs the projected vertices' extent
    assert abs(xy[:, 0].min() - xs.min()) < 6 and abs(xy[:, 0].max() - xs.max()) < 6
    assert abs(xy[:, 1].min() - ys.min()) < 6 and abs(xy[:, 1].max() - ys.max()) < 6
    # x right, y down from the top-left: the small ball's outline is where its vertices project,
    # and not where a mirrored convention would put it
    ball = xy[len(big.vertices):]
    centre, radius = ball.mean(axis=0), np.ptp(ball, axis=0).max() / 2 + 4
    def ink_near(c):
        return int(np.sum(np.hypot(xs - c[0], ys - c[1]) < radius))
    assert ink_near(centre) > 0
    assert ink_near((SIZE - centre[0], centre[1])) == 0 and ink_near((centre[0], SIZE - centre[1])) == 0
    # depth p2/p3 grows away from the camera: the vertex nearest the eye has the least
    camera = fit(mesh.vertices, (SIZE, SIZE), 20.0, -10.0, 30.0)
    dist = np.linalg.norm(mesh.vertices - camera.eye, axis=1)
    assert p[dist.argmin(), 2] / p[dist.argmin(), 3] < p[dist.argmax(), 2] / p[dist.argmax(), 3]


def test_orthographic_camera_matches_its_json(tmp_path):
    mesh = trimesh.creation.box((1.0, 2.0, 3.0))
    src, out, cam = tmp_path / "box.stl", tmp_path / "box.png", tmp_path / "cam.json"
    mesh.export(src)
    assert main(["outline", str(src), "-o", str(out), "--size", "128", "--orthographic", "--camera-json", str(cam)]) == 0
    M = np.array(json.loads(cam.read_text())["matrix"])
    assert np.allclose(M[3], [0, 0, 0, 1])                     # no perspective division


def _write(path, text):
    path.write_text(text)
    return str(path)


def test_bad_meshes_give_one_line(tmp_path, capsys):
    out = tmp_path / "o.png"
    cases = {"empty.obj": "", "garbage.stl": "\x00\x01 not a mesh at all \x02" * 10,
             "points.obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "flat.obj": "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"}
    for name, text in cases.items():
        rc = main(["outline", _write(tmp_path / name, text), "-o", str(out), "--size", "64"])
        err = capsys.readouterr().err
        assert rc == 2 and err.count("\n") == 1 and err.startswith("brushwork: error:"), (name, err)
        assert not out.exists()
    assert main(["outline", str(tmp_path / "missing.obj"), "-o", str(out)]) == 2


def test_damaged_meshes_warn_and_draw(tmp_path, capsys):
    box = trimesh.creation.box((1.0, 1.0, 1.0))
    lines = [f"v {x} {y} {z}" for x, y, z in box.vertices] + ["v nan 0 0"]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in box.faces] + ["f 1 2 9", "f 1 1 2", "f 1 2 3"]
    lines += ["f 1 2 4"]                                         # a third face on an edge: non-manifold
    src = _write(tmp_path / "damaged.obj", "mtllib gone.mtl\nusemtl skin\n" + "\n".join(lines) + "\n")
    _write(tmp_path / "gone.mtl", "newmtl skin\nmap_Kd no_such_texture.png\n")
    out = tmp_path / "d.png"
    assert main(["outline", src, "-o", str(out), "--size", "96"]) == 0
    err = capsys.readouterr().err
    assert "non-finite" in err and "degenerate" in err and "no_such_texture.png" in err and out.exists()
    assert all(line.startswith("brushwork: warning:") for line in err.splitlines())


def test_obj_with_a_bad_face_index_still_draws(tmp_path, capsys):
    box = trimesh.creation.box((1.0, 1.0, 1.0))
    text = "".join(f"v {x} {y} {z}\n" for x, y, z in box.vertices)
    text += "".join(f"f {a + 1}/1 {b + 1}/1 {c + 1}/1\n" for a, b, c in box.faces) + "f 1 2 99\n"
    out = tmp_path / "b.png"
    assert main(["outline", _write(tmp_path / "b.obj", text), "-o", str(out), "--size", "96"]) == 0
    err = capsys.readouterr().err
    assert "1 face(s) with bad vertex indices dropped" in err and out.exists()


def test_cli_usage_errors_and_orbit(tmp_path):
    src = tmp_path / "t.ply"
    trimesh.creation.icosphere(subdivisions=1).export(src)
    out = tmp_path / "t.png"
    for extra in (["--lines", "wobbly"], ["--size", "9"], ["--frames", "3"], ["--style", "nope"],
                  ["--elevation", "95"], ["--crease-angle", "0"], ["--weight", "crease=9"],
                  ["--weight", "bold=1"], ["--depth-weight", "2"]):
        assert main(["outline", str(src), "-o", str(out)] + extra) == 2, extra
        assert not out.exists()
    stats = tmp_path / "s.json"
    assert main(["outline", str(src), "-o", str(out), "--size", "96", "--frames", "3", "--orbit",
                 "--stats", str(stats), "--lines", "silhouette,suggestive"]) == 0
    assert sorted(p.name for p in tmp_path.glob("t_*.png")) == ["t_000.png", "t_001.png", "t_002.png"]
    frames = json.loads(stats.read_text())["frames"]
    assert [f["azimuth"] for f in frames] == [30.0, 150.0, 270.0]
    assert set(frames[0]["seconds"]) >= {"load", "lines", "visibility", "chaining", "brush", "deposit"}


def test_faces_wound_against_their_neighbours_are_turned_over():
    ball = trimesh.creation.icosphere(subdivisions=2)
    faces = ball.faces.copy()
    faces[::7] = faces[::7, ::-1]                               # every 7th face inside out
    surface = prepare(ball.vertices, faces)
    assert any("turned over" in note for note in surface.notes)
    radial = surface.vertices / np.linalg.norm(surface.vertices, axis=1, keepdims=True)
    assert np.all(np.einsum("ij,ij->i", surface.normals, radial) > 0.99)          # outward, all of them
    d = draw(surface, View(30.0, 20.0, 30.0, (SIZE, SIZE)), OutlineStyle.load("baimiao"))
    assert len(_chains(d, SILHOUETTE)) == 1


@pytest.mark.parametrize("scale, offset", [(1e-3, 3e7), (1e40, 0.0)])
def test_any_units_and_any_place(tmp_path, scale, offset):
    ball = trimesh.creation.icosphere(subdivisions=2)
    v = ball.vertices * scale + offset
    src = tmp_path / "ball.obj"
    src.write_text("".join("v %r %r %r\n" % tuple(float(x) for x in p) for p in v)
                   + "".join("f %d %d %d\n" % tuple(int(i) + 1 for i in f) for f in ball.faces))
    d = draw(prepare(*load_mesh(src)[:2]),
             View(30.0, 20.0, 30.0, (SIZE, SIZE)), OutlineStyle.load("baimiao"))
    assert len(_chains(d, SILHOUETTE)) == 1 and score(d)["recall"] >= 0.95


@pytest.mark.parametrize("style", ["baimiao", "xieyi"])
def test_a_line_ends_where_its_chain_ends(style):
    """The stroke sets off far enough before the chain's start that its light entry inks from
    the start on, the footprint's front stops at the chain's end and the tip leaves the paper at
    once: ink reaches past either end by at most 1 px (lines meeting at a point do not cross
    there), and up to within 1 px of it (the line is not cut short: no gap at a T-junction)."""
    from brushwork.outline3d.chains import Chain
    from brushwork.outline3d.strokes import OutlineDrawer

    for heading in (0.0, 30.0, 250.0):
        drawer = OutlineDrawer(OutlineStyle.load(style), (1024, 1024))
        u = np.array([np.cos(np.radians(heading)), np.sin(np.radians(heading))])
        start, end = np.array([512.0, 512.0]) - 300 * u, np.array([512.0, 512.0])
        pts = start + np.linspace(0.0, 1.0, 60)[:, None] * (end - start)
        drawer.draw(Chain(pts, np.zeros(60), SILHOUETTE))
        rows, cols = np.nonzero(drawer.paper.ink() > 0.25)          # row 0 on top, as the chain's y
        along = (np.column_stack([cols, rows]) + 0.5 - end) @ u       # px past the end
        assert -1.0 <= along.max() <= 1.0, f"{style} at {heading} deg: ink ends {along.max():.1f} px from the end"
        assert abs(along.min() + 300.0) <= 1.0, f"{style} at {heading} deg: ink starts {-300 - along.min():.1f} px early"


def _ply(vertices, faces) -> str:
    head = ("ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\n"
            "element face {}\nproperty list uchar int vertex_indices\nend_header\n").format(len(vertices), len(faces))
    return head + "".join(f"{x} {y} {z}\n" for x, y, z in vertices) + "".join(f"3 {a} {b} {c}\n" for a, b, c in faces)


@pytest.mark.parametrize("index", [99999, -5, 2 ** 31 - 1])
def test_faces_naming_no_vertex_of_the_file_are_dropped_with_a_warning(tmp_path, capsys, index):
    """A PLY face whose index is past the vertices, negative or huge is dropped and said, naming
    the file; a mesh of only such faces is refused in one line naming it."""
    box = trimesh.creation.box((1.0, 1.0, 1.0))
    src = _write(tmp_path / "box.ply", _ply(box.vertices, box.faces.tolist() + [[0, 1, index]]))
    out = tmp_path / "b.png"
    assert main(["outline", src, "-o", str(out), "--size", "96"]) == 0
    err = capsys.readouterr().err
    assert f"{src}: 1 face(s) with vertex indices outside 0..7 dropped" in err and out.exists(), err
    only = _write(tmp_path / "only.ply", _ply(box.vertices, [[0, 1, index], [index, 2, 3]]))
    assert main(["outline", only, "-o", str(tmp_path / "o.png"), "--size", "96"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and only in err and "outside 0..7" in err, err


@pytest.mark.parametrize("name, data", [
    ("random.stl", bytes(range(256)) * 3),
    ("short.stl", b"\x00" * 80 + (5).to_bytes(4, "little") + b"\x00" * 20),
    ("ascii.stl", b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 nan\nendloop\nendfacet\nendsolid\n"),
    ("garbage.off", b"OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 7000000000\n"),
])
def test_garbage_mesh_bytes_name_the_file_and_the_problem(tmp_path, capsys, name, data):
    src = tmp_path / name
    src.write_bytes(data)
    assert main(["outline", str(src), "-o", str(tmp_path / "o.png"), "--size", "64"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(src) in err and "No module named" not in err, err


@pytest.mark.parametrize("name", sorted(lowpoly_set()) + ["bunny_blob"])
def test_faceted_and_low_poly_meshes_are_outlined_whole(name):
    """Vertex normals lie on a low-poly surface (the smooth contour they give cuts across the
    flat faces, inside the polygons' outline and partly hidden by them): the outline follows
    the facet edges there, seen from any side; and a smooth one of parts through each other
    (the bunny) is outlined whole too."""
    from brushwork.bench.outline import bunny_blob

    mesh = bunny_blob() if name == "bunny_blob" else lowpoly_set()[name]
    for azimuth, elevation in ((30.0, 20.0), (200.0, -35.0)):
        s = score(_draw(mesh, view=View(azimuth, elevation, 30.0, (SIZE, SIZE))))
        assert s["recall"] >= 0.95 and s["precision"] >= 0.95, (name, azimuth, s["recall"], s["precision"])


def test_a_polygon_outline_is_one_line_round_its_corners():
    """An icosahedron's outline, a polygon of turns up to 72 degrees, is one closed chain; the
    cube's creases along its outline are not drawn again under it."""
    d = _draw(trimesh.creation.icosphere(subdivisions=0), kinds=("silhouette",))
    assert len(_chains(d, SILHOUETTE)) == 1 and _chains(d, SILHOUETTE)[0].closed
    box = _draw(trimesh.creation.box((1.0, 1.0, 1.0)), kinds=("silhouette", "crease"))
    assert len(_chains(box, SILHOUETTE)) == 1
    outline = _chains(box, SILHOUETTE)[0].points
    inner = np.vstack([c.points for c in _chains(box, CREASE)])           # the three edges at the near corner
    along = np.min(np.linalg.norm(inner[:, None, :] - outline[None, ::4, :], axis=2), axis=1) < 3.0
    assert len(inner) > 100 and along.mean() < 0.05


def _ink_widths(ink, pts):
    """The ink's width (px) across a polyline (k, 2) at every other sample: the ink pixels
    nearest each such sample, short of the end's cap, over the length of line it stands for;
    and the ink pixels nearest the last sample, their distance past the end along the line."""
    ys, xs = np.nonzero(ink)
    ink_xy = np.column_stack([xs + 0.5, ys + 0.5])
    samples = pts[::2]
    nearest = np.argmin(np.linalg.norm(ink_xy[:, None, :] - samples[None, :, :], axis=2), axis=1)
    heading = (pts[-1] - pts[-5]) / np.linalg.norm(pts[-1] - pts[-5])
    past = (ink_xy - pts[-1]) @ heading
    spacing = np.linalg.norm(np.diff(samples, axis=0), axis=1).mean()
    widths = np.bincount(nearest[past <= 0], minlength=len(samples)) / spacing
    return widths, past[nearest >= len(samples) - 2]


@pytest.mark.parametrize("style", ["baimiao", "xieyi"])
def test_no_hook_or_bead_at_a_line_end(style):
    """Over the last 5% of a stroke the ink is never wider than the stroke's median width (to a
    pixel), on straight lines of three headings and arcs turning either way, and it stops
    within 1 px of the chain's end."""
    from brushwork.outline3d.chains import Chain
    from brushwork.outline3d.strokes import OutlineDrawer

    t = np.linspace(0.0, 1.0, 120)
    paths = [np.array([512.0, 512.0]) + (300.0 * t - 300.0)[:, None] * [np.cos(h), np.sin(h)]
             for h in np.radians([0.0, 30.0, 250.0])]
    paths += [np.column_stack([512 + 250 * np.cos(a), 512 + 250 * np.sin(a)]) for a in (np.radians(200 * t),
                                                                                       np.radians(-200 * t))]
    for pts in paths:
        drawer = OutlineDrawer(OutlineStyle.load(style), (1024, 1024))
        drawer.draw(Chain(pts, np.zeros(len(pts)), SILHOUETTE))
        widths, past = _ink_widths(drawer.paper.ink() > 0.25, pts)
        last = widths[int(0.95 * len(widths)):]
        assert last.max() <= np.median(widths) + 1.0, (style, pts[-1], last, np.median(widths))
        assert past.max() <= 1.0, (style, pts[-1], past.max())


@pytest.mark.parametrize("style", ["baimiao", "xieyi"])
def test_lines_meeting_at_a_t_junction_meet_cleanly(style):
    """A line starting on another (a T-junction) is inked from the junction on, so the two
    touch, and pokes through the other by at most 1 px (no crossing tick); one ending on it
    likewise (its free end is the other tests')."""
    from brushwork.outline3d.chains import Chain
    from brushwork.outline3d.strokes import OutlineDrawer

    t = np.linspace(0.0, 1.0, 100)[:, None]
    bar = np.array([200.0, 400.0]) + t * [600.0, 0.0]
    for stem in (np.array([500.0, 400.0]) + t * [0.0, 300.0], np.array([500.0, 700.0]) - t * [0.0, 300.0]):
        drawer = OutlineDrawer(OutlineStyle.load(style), (1024, 1024))
        for pts in (bar, stem):
            drawer.draw(Chain(pts, np.zeros(len(pts)), SILHOUETTE))
        ink = drawer.paper.ink() > 0.25
        column = ink[:, 494:507].any(axis=1)                   # along the stem
        assert column[400:680].all(), (style, np.flatnonzero(~column[400:680])[:5] + 400)   # from the bar on
        bar_top = np.flatnonzero(ink[:, 300:320].any(axis=1)).min()     # the bar's upper edge, away from the stem
        assert np.flatnonzero(column).min() >= bar_top - 1, (style, np.flatnonzero(column).min(), bar_top)


@pytest.mark.parametrize("option", ["--azimuth", "--elevation", "--fov", "--crease-angle", "--depth-weight"])
@pytest.mark.parametrize("value", ["nan", "inf", "-inf"])
def test_float_options_refuse_non_finite_values(tmp_path, capsys, option, value):
    src, out = tmp_path / "t.ply", tmp_path / "t.png"
    trimesh.creation.icosphere(subdivisions=1).export(src)
    with pytest.raises(SystemExit) as stop:                  # argparse's usage error
        main(["outline", str(src), "-o", str(out), f"{option}={value}"])
    err = capsys.readouterr().err
    assert stop.value.code == 2
    assert err.count("\n") == 1 and option in err and "finite" in err and not out.exists()


def test_style_files_are_checked_field_by_field(tmp_path, capsys):
    """A bad outline style is one line naming the file and the field: malformed or deeply nested
    JSON, a value out of its range (a step that would ask for terabytes, endless smoothing), a
    kind missing from the weights, an unknown field."""
    src, out = tmp_path / "t.ply", tmp_path / "t.png"
    trimesh.creation.icosphere(subdivisions=1).export(src)
    from brushwork.outline3d.style import OUTLINE_STYLE_DIR

    good = json.loads((OUTLINE_STYLE_DIR / "baimiao.json").read_text(encoding="utf-8"))
    cases = {"garbage.json": ("{[", "not a style file"), "deep.json": ("[" * 100000, "not a style file"),
             "step.json": ({**good, "step_mm": 1e-9}, "step_mm"), "passes.json": ({**good, "smooth_passes": 10**9},
                                                                                  "smooth_passes"),
             "weight.json": ({**good, "weight": {"silhouette": 1.0}}, "weight"),
             "extra.json": ({**good, "colour": "red"}, "colour")}
    for name, (doc, needle) in cases.items():
        path = tmp_path / name
        path.write_text(doc if isinstance(doc, str) else json.dumps(doc))
        assert main(["outline", str(src), "-o", str(out), "--style", str(path)]) == 2, name
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and str(path) in err and needle in err, (name, err)
    assert not out.exists()


def test_outline_style_table_is_the_writing_styles_machinery():
    from brushwork.outline3d.style import FIELDS
    from brushwork.writing.style import StyleField

    assert all(isinstance(f, StyleField) and f.unit and f.doc for f in FIELDS)
    style = OutlineStyle.load("baimiao")
    assert style.weight["silhouette"] > style.weight["crease"]                   # 白描: the outline heavier


def _box_widths(**style):
    from brushwork.bench.outline import kind_widths

    box = trimesh.creation.box((1.0, 1.0, 1.0))
    surface = prepare(box.vertices, box.faces)
    look = OutlineStyle.load("baimiao")
    for k, v in style.items():
        setattr(look, k, v)
    d = draw(surface, View(30.0, 25.0, 30.0, (512, 512)), look, ("silhouette", "crease"))
    return kind_widths(d)


def test_line_weights_by_kind():
    """Measured from the ink: the outline of a cube at least 1.4 times as wide as its inner
    creases with the style's weights; --weight turns that round."""
    widths = _box_widths()
    assert widths[SILHOUETTE] >= 1.4 * widths[CREASE], widths
    turned = _box_widths(weight={"silhouette": 0.6, "boundary": 0.8, "crease": 1.0, "suggestive": 0.4})
    assert turned[CREASE] >= 1.25 * turned[SILHOUETTE], turned


def test_depth_weight_makes_the_nearer_line_wider():
    """Two equal balls, one twice as far: with a depth weight the near ball's outline is drawn
    wider than the far one's (measured from the ink), without one they are about equal."""
    import cv2

    near = trimesh.creation.icosphere(subdivisions=3).apply_translation([-1.3, 0.0, 1.5])
    far = trimesh.creation.icosphere(subdivisions=3).apply_translation([1.3, 0.0, -1.5])
    surface = prepare(*(lambda m: (m.vertices, m.faces))(trimesh.util.concatenate([near, far])))
    ratios = []
    for k in (0.0, 1.2):
        look = OutlineStyle.load("baimiao")
        look.depth_weight = k
        d = draw(surface, View(0.0, 0.0, 30.0, (512, 512)), look, ("silhouette",))
        half = cv2.distanceTransform((d.paper.ink() > 0.25).astype(np.uint8), cv2.DIST_L2, 5)
        loops = sorted(_chains(d, SILHOUETTE), key=lambda c: -np.mean(d.camera.eye_distance(c.depth)))
        w = [np.median(half[np.round(c.points[:, 1] - 0.5).astype(int), np.round(c.points[:, 0] - 0.5).astype(int)])
             for c in loops]                                   # far first
        ratios.append(w[-1] / w[0])
    assert ratios[1] >= 1.3 and ratios[1] > ratios[0] + 0.25, ratios


def _dark(data: bytes) -> np.ndarray:
    import cv2

    return cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_GRAYSCALE) < 128


def _iou(a: np.ndarray, b: np.ndarray) -> float:
    assert a.shape == b.shape
    return float((a & b).sum() / (a | b).sum())


def _outline_files(tmp_path, src, outputs, *options) -> list:
    """Run `outline` on src once per output name with the options; each run's stats."""
    stats = []
    for name in outputs:
        assert main(["outline", str(src), "-o", str(tmp_path / name), "--size", "512", "--lines", "silhouette,crease",
                     "--stats", str(tmp_path / f"{name}.json"), *options]) == 0
        stats.append(json.loads((tmp_path / f"{name}.json").read_text())["frames"][0])
    return stats


@pytest.mark.parametrize("ink", ["geometry", "gl"])
def test_svg_and_pdf_strokes_match_the_png(tmp_path, ink):
    """`-o x.svg` / `x.pdf`: one filled path per stroke (the SVG's grouped by kind), from the
    stroke's region where the ink is geometry (the default for an opaque scene), traced from
    the coverage where it is gl; real renderers draw them as the PNG of that ink shows it: resvg
    the SVG, PDFium the PDF (the same paths as the SVG's; IoU of the dark pixels >= 0.97, both
    against the PNG where the paths are geometry; without antialiasing, a pixel dark where its
    centre is inside a path, as the PNG's pixel is dark where its ink is)."""
    import cv2
    resvg = pytest.importorskip("resvg_py")
    pdfium = pytest.importorskip("pypdfium2")

    src = tmp_path / "head.ply"
    lowpoly_set()["faceted_head"].export(src)
    png, svg, pdf = _outline_files(tmp_path, src, ["h.png", "h.svg", "h.pdf"], "--ink", ink)
    assert png["ink"] == svg["ink"] == pdf["ink"] == ink
    text = (tmp_path / "h.svg").read_text()
    assert text.count("<path ") == svg["strokes"] and '<g id="silhouette"' in text and '<g id="crease"' in text
    assert text.index('<g id="silhouette"') < text.index('<g id="crease"')        # the outline drawn first
    ink_png = cv2.imread(str(tmp_path / "h.png"), cv2.IMREAD_GRAYSCALE) < 128
    ink_svg = _dark(resvg.svg_to_bytes(svg_path=str(tmp_path / "h.svg"), shape_rendering="crisp_edges"))
    assert _iou(ink_png, ink_svg) >= 0.97
    page = pdfium.PdfDocument(str(tmp_path / "h.pdf"))[0]
    assert np.allclose(page.get_size(), OutlineStyle.load("baimiao").paper_mm * 72.0 / 25.4, rtol=1e-4)   # the paper
    ink_pdf = page.render(scale=512 / page.get_size()[0], no_smoothpath=True).to_numpy()[..., :3].min(axis=2) < 128
    assert _iou(ink_svg, ink_pdf) >= 0.97 and (ink != "geometry" or _iou(ink_png, ink_pdf) >= 0.97)


def test_geometry_ink_is_refused_for_a_textured_style(tmp_path, capsys):
    src = tmp_path / "t.ply"
    trimesh.creation.icosphere(subdivisions=1).export(src)
    out = tmp_path / "t.svg"
    assert main(["outline", str(src), "-o", str(out), "--style", "xieyi", "--ink", "geometry"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--ink geometry" in err and "xieyi" in err and not out.exists(), err


def test_camera_from_a_gltf_scene(tmp_path, capsys):
    """`--camera-from` draws through the scene's own camera: a unit ball 8 units in front of a
    camera of 40 degrees, moved 1 unit right of it, lies left of the image's centre, as large
    as that lens shows it; a scene without a camera is one line."""
    import cv2

    ball = trimesh.creation.icosphere(subdivisions=3)
    to_world = np.eye(4)
    to_world[:3, 3] = [1.0, 0.0, 8.0]
    scene = trimesh.Scene(ball, camera=trimesh.scene.Camera(resolution=(SIZE, SIZE), fov=(40.0, 40.0)),
                          camera_transform=to_world)
    src, out = tmp_path / "scene.glb", tmp_path / "s.png"
    scene.export(src)
    assert main(["outline", str(src), "-o", str(out), "--size", str(SIZE), "--camera-from", str(src)]) == 0
    ys, xs = np.nonzero(cv2.imread(str(out), cv2.IMREAD_GRAYSCALE) < 128)
    focal = 0.5 * SIZE / np.tan(np.radians(20.0))                 # px per unit at unit depth
    centre_x = 0.5 * SIZE - focal * 1.0 / 8.0
    radius = focal / np.sqrt(8.0 ** 2 - 1.0)                    # the tangent cone's half angle, imaged
    assert abs(0.5 * (xs.min() + xs.max()) - centre_x) < 4 and abs(0.5 * (ys.min() + ys.max()) - 0.5 * SIZE) < 4
    assert abs(0.5 * (ys.max() - ys.min()) - radius) < 0.06 * radius
    bare = tmp_path / "bare.glb"
    trimesh.Scene(ball).export(bare)
    assert main(["outline", str(src), "-o", str(out), "--camera-from", str(bare)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no camera" in err


def test_camera_picks_a_named_camera_of_the_scene(tmp_path, capsys):
    """`--camera NAME` draws through the scene's camera of that name, its node placed by its
    parent's transform (a rig turned 90 degrees about y holding a camera 8 units off); without
    it, the first camera; a name not there is one line listing the names."""
    import cv2

    half = np.sin(np.radians(45.0))
    scene = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
             "nodes": [{"name": "Front", "camera": 0, "translation": [0.0, 0.0, 8.0]},
                       {"name": "rig", "rotation": [0.0, half, 0.0, half], "children": [2]},
                       {"name": "Side", "camera": 1, "translation": [1.0, 0.0, 8.0]}],
             "cameras": [{"type": "perspective", "perspective": {"yfov": np.radians(40.0), "znear": 0.1}}] * 2}
    cams = tmp_path / "cams.gltf"
    cams.write_text(json.dumps(scene))
    src, out = tmp_path / "ball.ply", tmp_path / "b.png"
    trimesh.creation.icosphere(subdivisions=3).export(src)
    focal = 0.5 * SIZE / np.tan(np.radians(20.0))
    for name, centre_x in ((None, 0.5 * SIZE), ("Side", 0.5 * SIZE - focal / 8.0)):
        pick = ["--camera", name] if name else []
        assert main(["outline", str(src), "-o", str(out), "--size", str(SIZE), "--camera-from", str(cams)] + pick) == 0
        ys, xs = np.nonzero(cv2.imread(str(out), cv2.IMREAD_GRAYSCALE) < 128)
        assert abs(0.5 * (xs.min() + xs.max()) - centre_x) < 4 and abs(0.5 * (ys.min() + ys.max()) - 0.5 * SIZE) < 4
    out.unlink()
    assert main(["outline", str(src), "-o", str(out), "--camera-from", str(cams), "--camera", "Top"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "'Top'" in err and "'Front', 'Side'" in err and not out.exists(), err
    assert main(["outline", str(src), "-o", str(out), "--camera", "Side"]) == 2
    assert "--camera-from" in capsys.readouterr().err

def test_a_line_thins_where_it_runs_behind_a_nearer_one():
    """A small ball half behind a big one (an ear behind a head): its outline's width falls by
    the style's occlusion thinning where it meets the big ball's outline, not away from it."""
    from brushwork.outline3d.draw import weights

    big = trimesh.creation.icosphere(subdivisions=3)
    small = trimesh.creation.icosphere(subdivisions=3, radius=0.4).apply_translation([1.1, 0.6, -0.8])
    mesh = trimesh.util.concatenate([big, small])
    style = OutlineStyle.load("baimiao")
    d = draw(prepare(mesh.vertices, mesh.faces), View(0.0, 0.0, 30.0, (512, 512)), style, ("silhouette",))
    chains = [c for c in d.chains if c.visible]
    near_eye = [float(np.mean(d.camera.eye_distance(c.depth))) for c in chains]
    w = weights(chains, d.camera, style, 3.0)
    head, ear = int(np.argmin(near_eye)), int(np.argmax(near_eye))
    gap = np.min(np.linalg.norm(chains[ear].points[:, None, :] - chains[head].points[None, ::3, :], axis=2), axis=1)
    assert w[ear][gap < 2.0].min() <= 1.0 - 0.9 * style.occlusion_thinning
    assert np.allclose(w[ear][gap > 0.03 * np.hypot(512, 512)], 1.0) and np.allclose(w[head], 1.0)


@pytest.mark.parametrize("style", ["baimiao", "xieyi"])
def test_a_closed_line_has_no_gap_at_its_seam(style):
    """A closed chain is drawn round again over its light entry: ink all the way round a
    circle, at every degree."""
    from brushwork.outline3d.chains import Chain
    from brushwork.outline3d.strokes import OutlineDrawer

    a = np.radians(np.arange(0.0, 360.0, 1.0))
    pts = np.column_stack([512 + 300 * np.cos(a), 512 + 300 * np.sin(a)])
    drawer = OutlineDrawer(OutlineStyle.load(style), (1024, 1024))
    drawer.draw(Chain(np.vstack([pts, pts[:1]]), np.zeros(len(pts) + 1), SILHOUETTE, closed=True))
    ink = drawer.paper.ink() > 0.25
    ix = np.round(pts).astype(int)
    around = [ink[y - 2:y + 3, x - 2:x + 3].any() for x, y in ix]
    assert all(around), np.degrees(a[~np.array(around)])


def test_a_depth_jump_is_a_step_the_surface_slope_does_not_explain():
    """The truth the outlines are scored against: a sheet ending a few pixels' width in front of
    another is a line however small that is against the mesh, a plane seen at a grazing angle
    (steps of many pixels' width, all alike) is none."""
    from brushwork.bench.outline import depth_jumps

    x = np.arange(64, dtype=float)
    pixel = np.full((64, 64), 0.01)
    grazing = np.tile(0.5 * x, (64, 1))                        # 50 pixel widths a step, steadily
    area = np.ones((64, 64), bool)
    assert not depth_jumps(grazing, area, pixel).any()
    tail = grazing + np.where(np.abs(x - 32) < 6, -0.08, 0.0)  # a strip 8 pixel widths nearer
    jumps = depth_jumps(tail, area, pixel)
    assert set(np.flatnonzero(jumps.any(axis=0))) == {26, 27, 37, 38}    # either side of its two edges
    assert not depth_jumps(grazing + np.where(np.abs(x - 32) < 6, -0.02, 0.0), area, pixel).any()
