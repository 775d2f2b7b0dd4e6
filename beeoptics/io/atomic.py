"""Writing artifacts so that a killed run never leaves half a file.

Every output is written to a temporary file beside its destination and
renamed onto it only when complete; a rename within one directory is atomic
on POSIX file systems. A run stopped by Ctrl-C (SIGINT, Python's
KeyboardInterrupt) or by SIGTERM, what a cluster's scheduler sends at a
job's time limit and ``kill`` sends by default, removes its temporary files
and scratch folders on the way out (:func:`sigterm_as_interrupt`); only one
killed outright (SIGKILL) leaves them, for the next run to remove.
"""

import json
import os
import signal
import tempfile
import threading
from contextlib import contextmanager
from pathlib import Path


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised where Ctrl-C raises KeyboardInterrupt, so that the same clean-up runs."""

    #: The exit status of a process ended by SIGTERM, as a shell reports one killed by it (128 + 15).
    status = 128 + signal.SIGTERM


@contextmanager
def sigterm_as_interrupt():
    """Within the block, SIGTERM raises :class:`Terminated` (a KeyboardInterrupt) in the main thread.

    Python's default for SIGTERM ends the process at once, before any
    ``finally`` can remove a temporary file or a ``.partial-`` folder. Like
    Ctrl-C it takes effect between two Python steps: a native call (a trace
    batch) finishes first. Outside the main thread, where no signal handler
    can be set, the block runs unchanged.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def stop(signum, frame):
        # A scheduler may send SIGTERM again (to each process of a job): the clean-up is not stopped in turn.
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        raise Terminated

    previous = signal.signal(signal.SIGTERM, stop)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def stop_behind(error):
    """The Ctrl-C or SIGTERM (a KeyboardInterrupt) ``error`` is, or stands for, else None.

    A stop that comes while a compiled module is imported (Open3D's, through
    pybind11) reaches the caller as an ImportError ("initialization failed")
    caused by it.
    """
    if isinstance(error, KeyboardInterrupt):
        return error
    cause = error.__cause__ or error.__context__
    return cause if isinstance(error, ImportError) and isinstance(cause, KeyboardInterrupt) else None


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
