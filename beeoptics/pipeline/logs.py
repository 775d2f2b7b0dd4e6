"""The package's log, sent to a rule's log file while its stage runs."""

import logging
import sys
from contextlib import contextmanager

log = logging.getLogger("beeoptics")
#: The heavy libraries a job may load: a job that only draws figures or tables loads neither.
HEAVY = ("open3d", "numba")


@contextmanager
def logging_to(path):
    """Send the package's log messages to a file (a rule's log) for the duration; at its end, say which
    of the heavy libraries (:data:`HEAVY`) the job loaded."""
    handler = logging.FileHandler(path, mode="w")
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
    log.addHandler(handler)
    log.setLevel(logging.INFO)
    try:
        yield
        log.info("loaded: %s", ", ".join(m for m in HEAVY if m in sys.modules) or "none of " + ", ".join(HEAVY))
    finally:
        log.removeHandler(handler)
        handler.close()
