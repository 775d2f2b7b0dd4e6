"""The package's log, sent to a rule's log file while its stage runs; a job stopped by SIGTERM (a
cluster's time limit) ends as one stopped by Ctrl-C does, its partial outputs removed."""

import logging
import sys
from contextlib import contextmanager

from beeoptics.io.atomic import Terminated, sigterm_as_interrupt, stop_behind

log = logging.getLogger("beeoptics")
#: The heavy libraries a job may load: a job that only draws figures or tables loads neither.
HEAVY = ("open3d", "numba")


@contextmanager
def logging_to(path):
    """Send the package's log messages to a file (a rule's log) for the duration; at its end, say which
    of the heavy libraries (:data:`HEAVY`) the job loaded.

    SIGTERM within it ends the job once its temporary files are removed, with one line and the status
    128 + 15 (:func:`~beeoptics.io.atomic.sigterm_as_interrupt`).
    """
    handler = logging.FileHandler(path, mode="w")
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
    log.addHandler(handler)
    log.setLevel(logging.INFO)
    try:
        with sigterm_as_interrupt():
            yield
        log.info("loaded: %s", ", ".join(m for m in HEAVY if m in sys.modules) or "none of " + ", ".join(HEAVY))
    except (Terminated, ImportError) as e:
        if not isinstance(stop_behind(e), Terminated):
            raise
        log.error("terminated (SIGTERM): its partial outputs removed")
        print("beeoptics: terminated", file=sys.stderr)
        raise SystemExit(Terminated.status) from None
    finally:
        log.removeHandler(handler)
        handler.close()
