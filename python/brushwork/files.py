"""Output files in one place: writability checked before the work, images in the format their
suffix names, every write atomic (a temporary file beside the target, then a rename), and
messages that name the path in plain words."""
from __future__ import annotations

import errno
import os
import tempfile
from typing import Callable

import numpy as np

# suffix -> (bit depths, transparency): what OpenCV's encoders write
IMAGE_FORMATS = {".png": ((8, 16), True), ".jpg": ((8,), False), ".jpeg": ((8,), False),
                 ".tif": ((8, 16), True), ".tiff": ((8, 16), True), ".bmp": ((8,), True),
                 ".webp": ((8,), True)}


def os_error_why(err: OSError) -> str:
    """What went wrong, in plain words, without the errno number."""
    why = {errno.ENOENT: "no such file or folder", errno.EACCES: "permission denied",
           errno.EEXIST: "a file is in the way", errno.ENOTDIR: "a part of the path is a file, not a folder",
           errno.EISDIR: "it is a folder", errno.ENOSPC: "no space left on the device",
           errno.EROFS: "the file system is read-only", errno.ENAMETOOLONG: "the name is too long"}
    return why.get(err.errno, (err.strerror or type(err).__name__).lower())


def os_error_text(err: OSError, path: str | os.PathLike, verb: str = "write") -> str:
    """An OSError as a plain sentence naming `path` (not the temporary file it happened on)."""
    return f"cannot {verb} {os.fspath(path)}: {os_error_why(err)}"


def check_writable(path: str | os.PathLike) -> None:
    """Raise FileNotFoundError / PermissionError / IsADirectoryError now if `path` cannot be
    written later (its folder is missing or read-only, or it is a folder), so that long work
    fails before it runs rather than after."""
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise FileNotFoundError(f"cannot write {path}: no such folder {folder}")
    if os.path.isdir(path):
        raise IsADirectoryError(f"cannot write {path}: it is a folder")
    if not os.access(folder, os.W_OK):
        raise PermissionError(f"cannot write {path}: folder {folder} is not writable")


def write_atomic(path: str | os.PathLike, write: Callable[[str], None], suffix: str = "") -> None:
    """Call write(tmp) on a temporary file next to `path`, then os.replace it onto `path`, so that a
    reader never sees a half-written file. The file gets the usual umask permissions; an OSError
    names `path`, never the temporary file."""
    path = os.fspath(path)
    check_writable(path)
    folder = os.path.dirname(os.path.abspath(path))
    tmp = None
    try:
        # write next to the target so that os.replace stays on one file system
        fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=suffix, dir=folder)
        os.close(fd)
        # mkstemp makes the file private (0600): give it the usual umask permissions
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        write(tmp)
        os.replace(tmp, path)
    except OSError as err:
        raise OSError(err.errno, os_error_text(err, path)) from None
    finally:
        if tmp is not None and os.path.exists(tmp):
            os.unlink(tmp)


def check_bits(bits: int) -> int:
    """Bits per channel of an image written: 8 or 16."""
    if bits not in (8, 16):
        raise ValueError(f"--bits {bits}: expected 8 or 16")
    return bits


def check_image_path(path: str | os.PathLike, bits: int = 8, transparent: bool = False) -> str:
    """The image suffix of `path` (.png .jpg .jpeg .tif .tiff .bmp .webp) when it can take `bits`
    per channel and transparency, and its folder is writable; ValueError in one line otherwise."""
    suffix = os.path.splitext(os.fspath(path))[1].lower()
    if suffix not in IMAGE_FORMATS:
        raise ValueError(f"{os.fspath(path)}: cannot write a {suffix or 'suffix-less'} image; "
                         f"name one of {' '.join(IMAGE_FORMATS)}")
    depths, alpha = IMAGE_FORMATS[suffix]
    if bits not in depths:
        raise ValueError(f"{os.fspath(path)}: {suffix} images hold 8 bits per channel, not {bits}; use .png or .tif")
    if transparent and not alpha:
        raise ValueError(f"{os.fspath(path)}: {suffix} images have no transparency; use .png, .tif or .webp")
    check_writable(path)
    return suffix


def write_image(path: str | os.PathLike, bgr: np.ndarray) -> str:
    """Encode `bgr` (OpenCV channel order, uint8 or uint16) in the format the suffix of `path`
    names and put it there atomically. Returns the path."""
    import cv2

    path = os.fspath(path)
    suffix = check_image_path(path, 16 if bgr.dtype == np.uint16 else 8, bgr.ndim == 3 and bgr.shape[2] == 4)
    ok, data = cv2.imencode(suffix, bgr)
    if not ok:
        raise ValueError(f"{path}: the {suffix} encoder failed")

    def write(tmp: str) -> None:
        with open(tmp, "wb") as f:
            f.write(data.tobytes())

    write_atomic(path, write, suffix=suffix)
    return path


def save_paper(paper, path: str | os.PathLike, bits: int = 8, background: str = "white") -> str:
    """The paper as an image at `path`, in the format its suffix names (Paper.image's pixels)."""
    rgb = paper.image(bits=bits, background=background)
    order = [2, 1, 0, 3] if rgb.shape[2] == 4 else [2, 1, 0]      # RGB(A) -> OpenCV's BGR(A)
    return write_image(path, np.ascontiguousarray(rgb[..., order]))


def decodes(path: str | os.PathLike) -> bool:
    """Whether the image file at `path` is whole: it decodes (a zero-byte or truncated file does not)."""
    import cv2

    try:
        data = np.fromfile(os.fspath(path), dtype=np.uint8)
    except OSError:
        return False
    if data.size == 0:
        return False
    return cv2.imdecode(data, cv2.IMREAD_UNCHANGED) is not None
