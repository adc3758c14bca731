"""Image files through OpenImageIO: float EXR with named channels, 8-bit PNG, HDR/EXR reading.

Every write is atomic: the image goes to a temporary file in the destination folder, which is
then renamed over the destination (``os.replace``), so a crash never leaves a half-written file
and an existing file is either the old or the new image.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .errors import InputError

__all__ = ["atomic_path", "save_figure", "write_image", "write_exr", "write_png", "read_image"]


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike):
    """Yield a temporary path next to ``path`` (same extension); rename it to ``path`` on success."""
    dest = Path(path)
    dest.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{dest.stem}.", suffix=f".tmp{dest.suffix}", dir=dest.parent)
    os.close(fd)
    # mkstemp creates 0600; give the file the permissions a plain open() would (0666 & ~umask)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    try:
        yield tmp
        os.replace(tmp, dest)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _as_hwc(pixels) -> np.ndarray:
    a = np.asarray(pixels)
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3:
        raise ValueError(f"an image must have shape (height, width[, channels]), got {a.shape}")
    return a


def write_image(path, pixels, *, channel_names: Sequence[str] | None = None, dtype: str | None = None,
                attributes: dict | None = None) -> Path:
    """Write ``pixels`` (height, width, channels) atomically; the format follows the extension.

    ``dtype`` is an OpenImageIO type name ("float", "half", "uint8", "uint16"); default "float"
    for EXR/HDR, "uint8" otherwise.  Floats for 8/16-bit formats are taken as [0, 1].
    ``attributes``: extra metadata (name -> str/int/float) stored in the file header.
    """
    import OpenImageIO as oiio

    path = Path(path)
    a = _as_hwc(pixels)
    h, w, nch = a.shape
    ext = path.suffix.lower()
    if dtype is None:
        dtype = "float" if ext in (".exr", ".hdr") else "uint8"
    if dtype in ("uint8", "uint16") and a.dtype.kind == "f":
        a = np.nan_to_num(np.clip(a, 0.0, 1.0))
        scale = 255.0 if dtype == "uint8" else 65535.0
        a = np.round(a * scale).astype(np.uint8 if dtype == "uint8" else np.uint16)
    elif dtype in ("float", "half"):
        a = a.astype(np.float32)
    spec = oiio.ImageSpec(w, h, nch, dtype)
    if channel_names is not None:
        if len(channel_names) != nch:
            raise ValueError(f"{len(channel_names)} channel names for {nch} channels")
        spec.channelnames = tuple(channel_names)
    if ext == ".exr":
        spec.attribute("compression", "zip")
    # no wall-clock timestamp in the file, so that the same render gives the same bytes (the file's
    # mtime keeps the time); $SOURCE_DATE_EPOCH (reproducible-builds convention) sets one explicitly
    epoch = os.environ.get("SOURCE_DATE_EPOCH", "")
    stamp = ""
    if epoch.isdigit():
        import time

        stamp = time.strftime("%Y:%m:%d %H:%M:%S", time.gmtime(int(epoch)))
    spec.attribute("DateTime", stamp)
    for key, value in (attributes or {}).items():
        spec.attribute(key, value)
    with atomic_path(path) as tmp:
        out = oiio.ImageOutput.create(tmp)
        if out is None:
            raise InputError(f"cannot write this format: {oiio.geterror()}", file=str(path))
        try:
            if not out.open(tmp, spec):
                raise OSError(f"{path}: {out.geterror()}")
            if not out.write_image(np.ascontiguousarray(a)):
                raise OSError(f"{path}: {out.geterror()}")
        finally:
            out.close()
    return path


def write_exr(
    path, pixels, channel_names: Sequence[str] | None = None, attributes: dict | None = None
) -> Path:
    """Float32 EXR with named channels (default R, G, B[, A]) and optional header ``attributes``."""
    a = _as_hwc(pixels)
    if channel_names is None:
        channel_names = ("R", "G", "B", "A")[: a.shape[2]] if a.shape[2] <= 4 else None
    return write_image(path, a, channel_names=channel_names, dtype="float", attributes=attributes)


def write_png(path, rgb) -> Path:
    """8-bit PNG of display-encoded values in [0, 1] (or uint8)."""
    return write_image(path, rgb, dtype="uint8")


def read_image(path) -> tuple[np.ndarray, list[str]]:
    """Read an image (EXR, HDR, PNG, ...) as float32 (height, width, channels) and its channel names."""
    import OpenImageIO as oiio

    path = Path(path)
    if not path.is_file():
        raise InputError("file not found", file=str(path))
    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise InputError(f"cannot read image: {oiio.geterror().strip() or 'unknown format'}", file=str(path))
    try:
        spec = inp.spec()
        pixels = inp.read_image(0, 0, 0, spec.nchannels, "float")
        if pixels is None:
            raise InputError(f"cannot read image: {inp.geterror()}", file=str(path))
        names = list(spec.channelnames)
    finally:
        inp.close()
    a = np.asarray(pixels, dtype=np.float32).reshape(spec.height, spec.width, spec.nchannels)
    return a, names


FIGURE_FORMATS = ("png", "pdf", "svg", "jpg", "jpeg", "tif", "tiff", "eps", "ps", "webp")


def save_figure(fig, path: str | os.PathLike, *, field: str = "-o", **kw) -> Path:
    """Save a matplotlib figure atomically (temp file + rename); the format follows the extension.
    An unsupported extension is an :class:`InputError` naming ``field``."""
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".") or "png"
    if fmt not in FIGURE_FORMATS:
        raise InputError("unsupported plot format", field=field, value=str(path),
                         allowed=", ".join(f".{f}" for f in FIGURE_FORMATS))
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=fmt, **kw)
    return path
