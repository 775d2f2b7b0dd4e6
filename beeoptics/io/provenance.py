"""The files a load reads, as its readers name them, for a cache to check.

A cached scene stays valid only while every file that made it is unchanged,
and not only those its ``scene.yaml`` names: an OBJ's material library
holds the colours a palette maps to materials, a glTF's vertices may lie in
a separate ``.bin``. The list of those files is the one the readers give as
they read them (:func:`note`: a mesh, each ``mtllib`` of an OBJ, a glTF's
external buffers and the images pymeshlab loaded for it, a texture, a
table of spectra), not a second parser of the scene's files, which could
come to disagree with the first. Outside :func:`recording`, :func:`note`
does nothing.
"""

import contextvars
from contextlib import contextmanager
from pathlib import Path

_files = contextvars.ContextVar("files_read", default=None)


@contextmanager
def recording():
    """Collect the files :func:`note` names within the block, once each, in order: yields their list
    (absolute paths), filled as the block runs."""
    files = []
    token = _files.set(files)
    try:
        yield files
    finally:
        _files.reset(token)


def note(path):
    """Name a file a reader reads (or looked for and did not find) to the recording that is on, if any."""
    files = _files.get()
    if files is not None:
        path = Path(path).absolute()
        if path not in files:
            files.append(path)
