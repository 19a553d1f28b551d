"""Mesh files in: trimesh reads them (OBJ, PLY, STL, OFF, GLB/glTF); an OBJ it refuses is read
plainly (its v and f lines, faces with bad indices dropped) so that a damaged file still draws;
what is missing or was dropped comes back as warnings, one phrase each."""
from __future__ import annotations

import logging
import os
from pathlib import Path

import numpy as np

SUFFIXES = (".obj", ".ply", ".stl", ".off", ".glb", ".gltf")    # the formats load_mesh reads


def mesh_files(folder) -> list[Path]:
    """The mesh files of a folder, sorted; ValueError when it is not a folder or holds none."""
    root = Path(folder)
    if not root.is_dir():
        raise ValueError(f"{folder}: no such folder")
    files = sorted(p for p in root.iterdir() if p.suffix.lower() in SUFFIXES)
    if not files:
        raise ValueError(f"{folder}: no mesh files ({', '.join(SUFFIXES)})")
    return files


def _face_indices(tokens: list, n: int) -> list | None:
    """0-based vertex indices of an OBJ face's tokens (v, v/t, v/t/n, v//n; negative: from the
    end), None when one is not a vertex of the n read so far."""
    out = []
    for tok in tokens:
        try:
            i = int(tok.split("/")[0])
        except ValueError:
            return None
        i = i - 1 if i > 0 else n + i
        if not 0 <= i < n:
            return None
        out.append(i)
    return out


def read_obj_plainly(path: str) -> tuple[np.ndarray, np.ndarray, list]:
    """Vertices (n, 3), triangles (m, 3) (polygons fanned) and notes of an OBJ's v and f lines."""
    vertices, faces, bad = [], [], 0
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            parts = line.split()
            if len(parts) >= 4 and parts[0] == "v":
                try:
                    vertices.append([float(x) for x in parts[1:4]])
                except ValueError:
                    vertices.append([float("nan")] * 3)
            elif len(parts) >= 4 and parts[0] == "f":
                idx = _face_indices(parts[1:], len(vertices))
                if idx is None:
                    bad += 1
                    continue
                faces += [[idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1)]
    notes = [f"{bad} face(s) with bad vertex indices dropped"] if bad else []
    return np.array(vertices, dtype=float).reshape(-1, 3), np.array(faces, dtype=np.int64).reshape(-1, 3), notes


class _Collect(logging.Handler):
    """Keeps the warnings trimesh logs while it reads a file (a missing texture, say)."""

    def __init__(self):
        super().__init__(logging.WARNING)
        self.messages: list[str] = []

    def emit(self, record):
        self.messages.append(" ".join(record.getMessage().split())[:200])


def _missing_files(path: str) -> list[str]:
    """Warnings for an OBJ's material libraries and textures that are not there (the mesh is
    drawn all the same: outlines need no texture)."""
    if not path.lower().endswith(".obj"):
        return []
    folder, notes = os.path.dirname(os.path.abspath(path)), []

    def refs(text: str, keys: tuple) -> list[str]:
        return [line.split(None, 1)[1].strip() for line in text.splitlines()
                if line.strip() and line.split(None, 1)[0] in keys and len(line.split(None, 1)) > 1]

    with open(path, encoding="utf-8", errors="replace") as f:
        libraries = refs(f.read(), ("mtllib",))
    for lib in libraries:
        lib_path = os.path.join(folder, lib)
        if not os.path.isfile(lib_path):
            notes.append(f"material library {lib} is missing (drawn without it)")
            continue
        with open(lib_path, encoding="utf-8", errors="replace") as f:
            maps = refs(f.read(), ("map_Kd", "map_Ka", "map_Ks", "map_Bump", "map_d", "bump"))
        for tex in maps:
            name = tex.split()[-1]
            if not os.path.isfile(os.path.join(os.path.dirname(lib_path), name)):
                notes.append(f"texture {name} of {lib} is missing (drawn without it)")
    return notes


def load_mesh(path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray, list]:
    """(n, 3) vertices, (m, 3) faces and warnings of a mesh file (OBJ, PLY, STL, OFF, GLB/glTF,
    through trimesh; a scene's meshes are joined in their placed positions).  ValueError with
    one line when the file cannot be read as a triangle mesh."""
    try:
        import trimesh
    except ImportError:
        raise ValueError("reading meshes needs trimesh: pip install 'brushwork[outline]'") from None
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise ValueError(f"{path}: no such file")
    log, catch = logging.getLogger("trimesh"), _Collect()
    log.addHandler(catch)
    notes = []
    try:
        loaded = trimesh.load(path, force="mesh", process=False)
        faces = np.asarray(getattr(loaded, "faces", np.zeros((0, 3))))
        vertices = np.asarray(getattr(loaded, "vertices", np.zeros((0, 3))))
    except Exception as err:  # noqa: BLE001 - any reader failure is the file's fault, said in one line
        why = f"{type(err).__name__}: {' '.join(str(err).split())[:160]}"
        if not path.lower().endswith(".obj"):
            raise ValueError(f"{path}: not a readable mesh ({why})") from None
        vertices, faces, notes = read_obj_plainly(path)
        notes.insert(0, f"read by the plain OBJ reader ({why})")
    finally:
        log.removeHandler(catch)
    if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0:
        raise ValueError(f"{path}: no triangles in the file")
    vertices, faces, dropped = checked_faces(path, vertices, faces)
    return vertices, faces, _missing_files(path) + notes + dropped + catch.messages


def checked_faces(path: str, vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray, list]:
    """The faces whose three indices name vertices of the file (0..n-1) with finite coordinates,
    and a warning for each kind dropped; ValueError naming the file when none is left."""
    vertices = np.asarray(vertices, dtype=float).reshape(-1, 3)
    faces = np.asarray(faces)
    n, notes = len(vertices), []
    inside = np.all((faces >= 0) & (faces < n), axis=1) if faces.dtype.kind in "iu" else np.zeros(len(faces), bool)
    if not inside.all():
        notes.append(f"{int((~inside).sum())} face(s) with vertex indices outside 0..{n - 1} dropped")
    faces = faces[inside].astype(np.int64)
    finite = np.isfinite(vertices).all(axis=1)[faces].all(axis=1)
    if not finite.all():
        notes.append(f"{int((~finite).sum())} face(s) with non-finite vertices dropped")
    faces = faces[finite]
    if len(faces) == 0:
        raise ValueError(f"{path}: no triangle whose vertices are in the file and finite ({'; '.join(notes)})")
    return vertices, faces, notes

