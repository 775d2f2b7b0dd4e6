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
import sys
import tempfile
import threading
from contextlib import contextmanager
from pathlib import Path


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised where Ctrl-C raises KeyboardInterrupt, so that the same clean-up runs."""

    #: The exit status of a process ended by SIGTERM, as a shell reports one killed by it (128 + 15).
    status = 128 + signal.SIGTERM


#: The stops (Ctrl-C, SIGTERM) signalled in :func:`sigterm_as_interrupt`'s block, for :func:`raise_stop`.
_STOPS = []


@contextmanager
def sigterm_as_interrupt():
    """Within the block, SIGTERM raises :class:`Terminated` (a KeyboardInterrupt) in the main thread.

    Python's default for SIGTERM ends the process at once, before any
    ``finally`` can remove a temporary file or a ``.partial-`` folder. Like
    Ctrl-C it takes effect between two Python steps: a native call (a trace
    batch) finishes first. The step it lands in may not let it through: a
    finaliser (``__del__``, a weakref's callback, which the garbage collector
    runs at any step) prints it as unraisable and carries on, and a library
    that catches everything swallows it (stops in a render's first seconds
    were lost, silently, twice in 150, and the render committed its
    outputs). Each stop is therefore also kept, and raised again before the
    next commit (:func:`raise_stop`) and at the block's end; a finaliser's
    is not printed. Outside the main thread, where no signal handler can be
    set, the block runs unchanged.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def terminate(signum, frame):
        # A scheduler may send SIGTERM again (to each process of a job): the clean-up is not stopped in turn.
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        _STOPS.append(Terminated())
        raise _STOPS[-1]

    def interrupt(signum, frame):
        _STOPS.append(KeyboardInterrupt())
        raise _STOPS[-1]

    def unraisable(info):
        if not any(info.exc_value is stop for stop in _STOPS):
            hook(info)

    # Ctrl-C only where Python would raise it: a run a shell started in the background (`&`, nohup)
    # inherits SIGINT ignored, so that a Ctrl-C at the terminal does not stop it, and keeps it so.
    catch = {signal.SIGTERM: terminate}
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        catch[signal.SIGINT] = interrupt
    previous = {signum: signal.signal(signum, handler) for signum, handler in catch.items()}
    hook, sys.unraisablehook = sys.unraisablehook, unraisable
    try:
        yield
        raise_stop()
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        sys.unraisablehook = hook
        _STOPS.clear()


def raise_stop():
    """Raise the first Ctrl-C or SIGTERM signalled in :func:`sigterm_as_interrupt`'s block, if one was: called
    before an output is committed, so that a stopped run commits nothing even where the stop was swallowed."""
    if _STOPS:
        raise _STOPS[0]


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
        raise_stop()
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def write_json(path, data):
    """Write JSON atomically, keys in the order given, for stable diffs."""
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(data, indent=2, sort_keys=False) + "\n")
