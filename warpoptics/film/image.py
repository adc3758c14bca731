"""Rendered images and image files: :class:`Image` (XYZ, Stokes layers, views) and, through
OpenImageIO, float EXR with named channels, 8-bit PNG, HDR/EXR reading.

Every write is atomic: the image goes to a temporary file in the destination folder, which is
then renamed over the destination (``os.replace``), so a crash never leaves a half-written file
and an existing file is either the old or the new image.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import color
from ..atomic import atomic_path
from ..errors import InputError

__all__ = ["Image", "save_figure", "write_image", "write_exr", "write_png", "read_image", "FIGURE_FORMATS"]

# EXR header attribute of the light's polarizer angle (Image.save / Image.load)
_SOURCE_ATTR = "warpoptics:source_polarizer"


def _as_hwc(pixels) -> np.ndarray:
    a = np.asarray(pixels)
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3:
        raise ValueError(f"an image must have shape (height, width[, channels]), got {a.shape}")
    return a


def write_image(
    path,
    pixels,
    *,
    channel_names: Sequence[str] | None = None,
    dtype: str | None = None,
    attributes: dict | None = None,
    field: str | None = None,
) -> Path:
    """Write ``pixels`` (height, width, channels) atomically and verified (re-read before it
    replaces ``path``; :func:`warpoptics.atomic.atomic_path`); the format follows the extension.

    ``dtype`` is an OpenImageIO type name ("float", "half", "uint8", "uint16"); default "float"
    for EXR/HDR, "uint8" otherwise.  Floats for 8/16-bit formats are taken as [0, 1].
    ``attributes``: extra metadata (name -> str/int/float) stored in the file header.
    ``field``: the option the path came from (``"-o"``), named in an :class:`OutputError`.
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
    out = oiio.ImageOutput.create(str(path))
    if out is None:
        raise InputError(f"cannot write this format: {oiio.geterror()}", file=str(path))

    def verify(tmp: str) -> None:
        # re-read every pixel: a chunk lost at the end of an EXR or PNG fails here (cheap next to
        # the render that made the image)
        try:
            back, _ = read_image(tmp)
        except InputError as exc:
            msg = exc.message.splitlines()[0] if exc.message else ""
            raise OSError(0, f"the written file does not read back ({msg})") from exc
        if back.shape != (h, w, nch):
            raise OSError(f"the file reads back as {back.shape}, not {(h, w, nch)}")

    with atomic_path(path, field=field, verify=verify) as tmp:
        with _captured_stderr() as said:  # libpng prints "libpng error: ..." itself: not on the terminal
            opened = out.open(tmp, spec)
            ok = opened and out.write_image(np.ascontiguousarray(a))
            # OpenImageIO reports a failed final flush (a full disk) only in close()'s result
            closed = out.close() if opened else True
        if not (ok and closed):
            raise OSError(
                0,
                out.geterror()
                or oiio.geterror()
                or said().strip()
                or "the image library could not write the file",
            )
    return path


@contextlib.contextmanager
def _captured_stderr():
    """Route what C libraries print on file descriptor 2 (libpng's own ``libpng error: Write
    Error``) into a temporary file while the block runs; yields a callable that returns that
    text, for the error message instead of a stray line on the terminal."""
    import sys
    import tempfile

    with contextlib.suppress(AttributeError, ValueError, OSError):
        sys.stderr.flush()
    try:
        saved = os.dup(2)
    except OSError:  # no descriptor 2 (a detached process): nothing to capture
        yield lambda: ""
        return
    text = ""
    with tempfile.TemporaryFile(mode="w+b") as sink:
        os.dup2(sink.fileno(), 2)
        try:
            yield lambda: text
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            sink.seek(0)
            text = sink.read(4096).decode("utf-8", errors="replace")


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
        raise InputError(
            "unsupported plot format",
            field=field,
            value=str(path),
            allowed=", ".join(f".{f}" for f in FIGURE_FORMATS),
        )
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=fmt, **kw)
    return path


@dataclass
class Image:
    """A rendered image.  ``xyz`` (H, W, 3) CIE XYZ (Y = 1 is the luminance of a white at the
    illuminant's level); ``stokes`` (H, W, 4) Y-weighted Stokes vector S0..S3 in the camera frame
    (x = image right, y = image up; S0 = Y); ``alpha`` (H, W) fraction of samples whose primary ray
    hit an object; ``stokes_xyz`` (H, W, 3, 4) the Stokes vector of each of X, Y, Z (its [..., c, 0]
    is ``xyz[..., c]``, its Y row is ``stokes``), for the polarization views (:mod:`warpoptics.film.views`,
    :meth:`view`); ``source_polarizer`` the angle (degrees, from image right toward image up) of the
    polarizer in front of the light when the image was rendered with polarized light, else None."""

    xyz: np.ndarray
    stokes: np.ndarray
    alpha: np.ndarray
    exposure: float = 0.0
    tone: str = "filmic"
    stats: dict = field(default_factory=dict)
    stokes_xyz: np.ndarray | None = None
    source_polarizer: float | None = None

    def view(self, kind: str, angle: float | None = None) -> Image:
        """A polarization view of this image (no re-render): ``"analyzer"`` (an ideal linear
        analyzer at ``angle`` degrees), ``"polariscope"`` (analyzer crossed with the light's
        polarizer; ``"polariscope:parallel"`` for parallel), ``"dichroscope"`` (analyzer at
        ``angle`` and ``angle + 90`` side by side) or ``"none"``; ``kind`` may carry the angle
        (``"analyzer:30"``).  See :mod:`warpoptics.film.views`."""
        from .views import apply_view  # views build on Image (one way)

        return apply_view(self, kind, angle)

    @classmethod
    def load(cls, path: str | Path) -> Image:
        """Read an EXR written by :meth:`save` (XYZ, A, the Stokes layers, the light's polarizer)."""
        import OpenImageIO as oiio

        pixels, names = read_image(path)
        idx = {n: i for i, n in enumerate(names)}
        need = ["X", "Y", "Z", "S0", "S1", "S2", "S3"]
        missing = [n for n in need if n not in idx]
        if missing:
            raise InputError(
                f"not a warpoptics render (missing channels {', '.join(missing)})", file=str(path)
            )

        def ch(*keys):
            return np.stack([pixels[..., idx[k]] for k in keys], axis=-1).astype(np.float64)

        xyz = ch("X", "Y", "Z")
        stokes = ch("S0", "S1", "S2", "S3")
        alpha = pixels[..., idx["A"]].astype(np.float64) if "A" in idx else np.ones(xyz.shape[:2])
        stokes_xyz = None
        layer = [f"stokes_{c}.S{i}" for c in "XZ" for i in range(4)]
        if all(n in idx for n in layer):
            sx = ch(*layer[:4])
            sz = ch(*layer[4:])
            stokes_xyz = np.stack([sx, stokes, sz], axis=-2)
        source = None
        inp = oiio.ImageInput.open(str(path))
        if inp is not None:
            try:
                v = inp.spec().getattribute(_SOURCE_ATTR)
                source = None if v is None else float(v)
            finally:
                inp.close()
        return cls(xyz=xyz, stokes=stokes, alpha=alpha, stokes_xyz=stokes_xyz, source_polarizer=source)

    @property
    def rgb(self) -> np.ndarray:
        """Scene-linear sRGB, Smits–Meyer gamut-clipped (negative components only; HDR kept)."""
        return color.gamut_clip(self.xyz.reshape(-1, 3), 1.0e30).reshape(self.xyz.shape)

    def display(self) -> np.ndarray:
        """Display-encoded sRGB in [0, 1]: exposure, tone curve, sRGB transfer function."""
        mapped = color.tone_map(self.rgb, exposure=self.exposure, curve=self.tone)
        # self.rgb is already >= 0 (Smits–Meyer, constant Y); the tone curve maps each channel into [0, 1]
        return color.encode_srgb(mapped)

    def save(self, path: str | Path) -> Path:
        """EXR: R, G, B (linear sRGB), A, S0..S3 (the Y-weighted Stokes vector) and X, Y, Z layers, and
        with per-channel Stokes also ``stokes_X.S0..S3`` and ``stokes_Z.S0..S3`` (the Y ones are
        S0..S3); PNG/JPEG/TIFF: tone mapped."""
        p = Path(path)
        ext = p.suffix.lower()
        if ext == ".exr":
            data = np.concatenate([self.rgb, self.alpha[..., None], self.stokes, self.xyz], axis=-1)
            names = ["R", "G", "B", "A", "S0", "S1", "S2", "S3", "X", "Y", "Z"]
            attributes = None
            if self.stokes_xyz is not None:
                # per-channel Stokes: stokes_X.S0..S3, stokes_Z.S0..S3 (the Y vector is S0..S3)
                s = np.asarray(self.stokes_xyz, dtype=np.float64)
                data = np.concatenate([data, s[..., 0, :], s[..., 2, :]], axis=-1)
                names += [f"stokes_{c}.S{i}" for c in "XZ" for i in range(4)]
                attributes = (
                    {} if self.source_polarizer is None else {_SOURCE_ATTR: float(self.source_polarizer)}
                )
            return write_exr(p, data.astype(np.float32), names, attributes=attributes)
        if ext in (".png", ".jpg", ".jpeg", ".tif", ".tiff"):
            return write_png(p, self.display())
        raise InputError(
            "unsupported image format", field="output", value=str(path), allowed=".exr, .png, .jpg, .tif"
        )

    def _repr_png_(self) -> bytes:
        import io

        from matplotlib.image import imsave

        buf = io.BytesIO()
        # rounded to 8 bits here (imsave would truncate floats)
        imsave(buf, np.round(np.clip(self.display(), 0.0, 1.0) * 255.0).astype(np.uint8), format="png")
        return buf.getvalue()

    def _repr_html_(self) -> str:
        import base64

        h, w = self.xyz.shape[:2]
        data = base64.b64encode(self._repr_png_()).decode("ascii")
        # small renders are scaled up without blurring their pixels
        scale = max(1, 256 // max(w, h, 1))
        return (
            f'<img src="data:image/png;base64,{data}" width="{w * scale}" height="{h * scale}" '
            f'style="image-rendering: pixelated" alt="warpoptics render {w}x{h}"/>'
        )
