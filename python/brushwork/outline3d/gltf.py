"""The cameras of a glTF scene (.gltf or .glb), read from its JSON: each node of the scene that
holds a perspective camera, its camera-to-world matrix (the node's transform composed with its
parents', glTF's column-major `matrix` or translation, rotation (x, y, z, w) and scale) and its
vertical field of view.  A camera is named by its node's name, else by its camera's, else
camera0, camera1, ... in the order the scene's nodes are walked."""
from __future__ import annotations

import json
import math
import os
import struct

import numpy as np

GLB_MAGIC = b"glTF"
GLB_JSON = 0x4E4F534A         # the chunk type of a GLB's JSON chunk


def _document(path: str) -> dict:
    """The JSON of a .gltf file or of a .glb's first chunk; ValueError when it is neither."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == GLB_MAGIC:
        if len(data) < 20:
            raise ValueError("a GLB file cut short")
        length, kind = struct.unpack_from("<II", data, 12)
        if kind != GLB_JSON or 20 + length > len(data):
            raise ValueError("a GLB file without its JSON chunk")
        data = data[20:20 + length]
    try:
        doc = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError):
        raise ValueError("not glTF JSON") from None
    if not isinstance(doc, dict):
        raise ValueError("not glTF JSON")
    return doc


def _quaternion(x: float, y: float, z: float, w: float) -> np.ndarray:
    """(3, 3) rotation of a quaternion, normalised."""
    n = math.sqrt(x * x + y * y + z * z + w * w) or 1.0
    x, y, z, w = x / n, y / n, z / n, w / n
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def _local(node: dict) -> np.ndarray:
    """(4, 4) a node's transform against its parent's frame."""
    if "matrix" in node:
        return np.asarray(node["matrix"], dtype=float).reshape(4, 4).T        # column-major in the file
    m = np.eye(4)
    m[:3, :3] = _quaternion(*node.get("rotation", (0.0, 0.0, 0.0, 1.0))) * np.asarray(node.get("scale", (1, 1, 1)))
    m[:3, 3] = node.get("translation", (0.0, 0.0, 0.0))
    return m


def _walk(doc: dict) -> list:
    """(node, camera-to-world (4, 4)) of every node of the document's scene holding a camera,
    depth first from the scene's roots (a node met again is not walked twice)."""
    nodes = doc.get("nodes", [])
    scenes = doc.get("scenes", [])
    scene = doc.get("scene", 0)
    roots = scenes[scene].get("nodes", []) if 0 <= scene < len(scenes) else range(len(nodes))
    out, seen = [], set()
    stack = [(int(i), np.eye(4)) for i in reversed(list(roots))]
    while stack:
        i, parent = stack.pop()
        if i in seen or not 0 <= i < len(nodes):
            continue
        seen.add(i)
        world = parent @ _local(nodes[i])
        if "camera" in nodes[i]:
            out.append((nodes[i], world))
        stack += [(int(c), world) for c in reversed(nodes[i].get("children", []))]
    return out


def scene_cameras(path: str | os.PathLike) -> dict:
    """The scene's perspective cameras by name (see the module), in order: (camera-to-world
    (4, 4), vertical field of view in degrees).  ValueError naming the file when it cannot be read."""
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise ValueError(f"--camera-from {path}: no such file")
    try:
        doc = _document(path)
        cameras = doc.get("cameras", [])
        out = {}
        for node, world in _walk(doc):
            cam = cameras[int(node["camera"])]
            if cam.get("type") != "perspective":
                continue
            name = node.get("name") or cam.get("name") or f"camera{len(out)}"
            out.setdefault(str(name), (world, math.degrees(float(cam["perspective"]["yfov"]))))
    except (ValueError, KeyError, IndexError, TypeError, AttributeError, OSError) as err:
        raise ValueError(f"--camera-from {path}: not a readable glTF scene ({type(err).__name__})") from None
    return out


def scene_camera(path: str | os.PathLike, name: str | None = None) -> tuple[np.ndarray, float]:
    """The scene's camera called `name` (None: its first perspective camera): its camera-to-world
    (4, 4) matrix and vertical field of view (degrees).  ValueError in one line when there is
    none, or none of that name (listing the names there are)."""
    path = os.fspath(path)
    cameras = scene_cameras(path)
    if not cameras:
        raise ValueError(f"--camera-from {path}: the scene has no camera (glTF/GLB perspective cameras are read)")
    if name is not None and name not in cameras:
        raise ValueError(f"--camera {name!r}: {path} has no camera of that name; its cameras: "
                         f"{', '.join(repr(n) for n in cameras)}")
    to_world, yfov = cameras[name] if name is not None else next(iter(cameras.values()))
    if not 0.0 < yfov < 180.0:
        raise ValueError(f"--camera-from {path}: the camera's field of view {yfov:g} is not 0..180 degrees")
    return to_world, yfov
