"""Writing images with OpenImageIO: PNG for viewing, float EXR for analysis.

EXR files carry named channels. OpenImageIO stamps files with the current
time by default; the ``DateTime`` attribute is pinned here, so that the
same inputs give byte-identical files.
"""

import os
import sys
from contextlib import contextmanager

import numpy as np
import OpenImageIO as oiio

from beeoptics.io.atomic import atomic_path
from beeoptics.io.errors import InputError
from beeoptics.io.provenance import note

#: The timestamp written into every image (EXIF form), fixed for reproducibility.
DATETIME = "2000:01:01 00:00:00"


def _write(path, pixels, fmt, channel_names=None, **attributes):
    pixels = np.ascontiguousarray(pixels)
    if pixels.ndim == 2:
        pixels = pixels[:, :, None]
    h, w, nc = pixels.shape
    spec = oiio.ImageSpec(w, h, nc, fmt)
    if channel_names:
        spec.channelnames = tuple(channel_names)
    spec.attribute("DateTime", DATETIME)
    spec.attribute("Software", "beeoptics")
    for k, v in attributes.items():
        spec.attribute(k, v)
    with atomic_path(path) as tmp:
        out = oiio.ImageOutput.create(str(tmp))
        if out is None or not out.open(str(tmp), spec):
            raise OSError(f"cannot write {path}: {oiio.geterror()}")
        ok = out.write_image(pixels)
        out.close()
        if not ok:
            raise OSError(f"cannot write {path}: {oiio.geterror()}")


def write_png(path, rgb):
    """Write an image given as floats in [0, 1] (display-encoded) as 8-bit PNG.

    Pixels that are NaN (where there is nothing to show) are written
    transparent, with an alpha channel, so that no value of the image can
    be mistaken for them.
    """
    pixels = np.asarray(rgb, float)
    pixels = pixels[..., None] if pixels.ndim == 2 else pixels
    empty = np.isnan(pixels).any(-1, keepdims=True)
    if empty.any():
        pixels = np.concatenate([np.where(empty, 0.0, pixels), (~empty).astype(float)], -1)
    _write(path, np.rint(np.clip(pixels, 0.0, 1.0) * 255.0).astype(np.uint8), oiio.UINT8)


def write_gif(path, frames, fps):
    """Write RGB frames (each (h, w, 3) uint8, all one size) as an animated GIF at ``fps`` frames a second."""
    frames = [np.ascontiguousarray(f, np.uint8) for f in frames]
    h, w, nc = frames[0].shape
    spec = oiio.ImageSpec(w, h, nc, oiio.UINT8)
    spec.attribute("FramesPerSecond", oiio.TypeRational, (int(round(fps * 1000)), 1000))
    with atomic_path(path) as tmp:
        out = oiio.ImageOutput.create(str(tmp))
        if out is None or not out.open(str(tmp), [spec] * len(frames)):
            raise OSError(f"cannot write {path}: {oiio.geterror()}")
        for k, frame in enumerate(frames):
            if (k and not out.open(str(tmp), spec, "AppendSubimage")) or not out.write_image(frame):
                out.close()
                raise OSError(f"cannot write {path}: {out.geterror()}")
        out.close()


def write_mp4(path, frames, fps):
    """Write RGB frames (each (h, w, 3) uint8, all one size) as an H.264 MP4 at ``fps``, atomically.

    Encoded by the ffmpeg that imageio-ffmpeg's wheel ships (libx264, yuv420p, as
    browsers and players expect, so an odd width or height is padded by a pixel).
    """
    import imageio_ffmpeg

    # yuv420p wants even sides: pad by the edge pixel.
    frames = [np.pad(np.asarray(f, np.uint8), ((0, f.shape[0] % 2), (0, f.shape[1] % 2), (0, 0)), mode="edge")
              for f in frames]
    h, w, _ = frames[0].shape
    with atomic_path(path) as tmp:
        writer = imageio_ffmpeg.write_frames(str(tmp), (w, h), fps=float(fps), codec="libx264", quality=8,
                                             pix_fmt_out="yuv420p", macro_block_size=1,
                                             output_params=["-f", "mp4"])
        writer.send(None)
        for frame in frames:
            writer.send(frame)
        writer.close()


def write_exr(path, data, channel_names):
    """Write float data (h, w, c) as a zip-compressed EXR with named channels."""
    _write(path, np.asarray(data, np.float32), oiio.FLOAT, channel_names, compression="zip")


@contextmanager
def _stderr_silenced():
    """The process's stderr (file descriptor 2) pointed at /dev/null for the block.

    libpng prints its complaints about a damaged file to stderr, below Python and OpenImageIO,
    before OpenImageIO reports them; the reader reports them once, in its own error.
    """
    sys.stderr.flush()
    saved, devnull = os.dup(2), os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 2)
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)
        os.close(devnull)


def read_image(path):
    """Pixels (h, w, c) as float32 and the channel names.

    Raises
    ------
    InputError
        If the file is missing, truncated or damaged, or not an image OpenImageIO reads.
    """
    if not os.path.isfile(path):
        raise InputError(path, "", "no such image file")
    note(path)
    with _stderr_silenced():
        buf = oiio.ImageBuf(str(path))
        pixels = None if buf.has_error else buf.get_pixels(oiio.FLOAT)
        # Read out, the error is not printed again when the buffer is destroyed.
        error = buf.geterror()
    if error or pixels is None:
        reason = error.strip().splitlines()[0] if error.strip() else "no pixels"
        raise InputError(path, "", f"the image is unreadable, truncated or damaged ({reason})")
    return pixels, list(buf.spec().channelnames)
