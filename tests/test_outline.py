"""3-D outlines on procedural meshes: lines, visibility, chains, the camera file, bad meshes, the CLI."""
import json

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")

from brushwork.cli import main  # noqa: E402
from brushwork.outline3d import View, draw, fit, load_mesh, prepare  # noqa: E402
from brushwork.outline3d.lines import BOUNDARY, CREASE, SILHOUETTE  # noqa: E402
from brushwork.outline3d.strokes import OutlineStyle  # noqa: E402
from brushwork.bench.outline import score  # noqa: E402

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
                  ["--elevation", "95"], ["--crease-angle", "0"]):
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
    """The footprint's front stops at the chain's end and the tip leaves the paper at once: ink
    reaches past either end by at most 2.5 px (lines meeting at a point do not cross there: the
    tuft's rounded tip reaches 0.5-1 px further than a pointed one), and up to within 2 px of the
    end (the line is not cut short)."""
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
        assert -2.0 <= along.max() <= 2.5, f"{style} at {heading} deg: ink ends {along.max():.1f} px from the end"
        assert along.min() >= -300.0 - 2.0, f"{style} at {heading} deg: ink starts {-300 - along.min():.1f} px early"
