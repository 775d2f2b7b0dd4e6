"""Writing artifacts so that a killed run never leaves half a file.

Every output is written to a temporary file beside its destination and
renamed onto it only when complete; a rename within one directory is atomic
on POSIX file systems.
"""

import json
import os
import tempfile
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def atomic_path(path):
    """Yield a temporary path to write; it replaces ``path`` only if the block succeeds.

    The temporary name keeps the destination's suffix, for writers that
    choose a format by extension.
    """
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=path.suffix)
    except OSError as e:
        # Name the folder asked for, not the temporary file's name.
        reason = "a file, not a folder" if path.parent.is_file() else e.strerror
        raise OSError(e.errno, f"cannot write there ({reason})", str(path.parent)) from None
    os.close(fd)
    # mkstemp makes the file private; an artifact gets the permissions open() would give it.
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    try:
        yield Path(tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def write_json(path, data):
    """Write JSON atomically, keys in the order given, for stable diffs."""
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(data, indent=2, sort_keys=False) + "\n")
