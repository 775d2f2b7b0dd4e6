"""The package's log, sent to a rule's log file while its stage runs."""

import logging
from contextlib import contextmanager

log = logging.getLogger("beeoptics")


@contextmanager
def logging_to(path):
    """Send the package's log messages to a file (a rule's log) for the duration."""
    handler = logging.FileHandler(path, mode="w")
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
    log.addHandler(handler)
    log.setLevel(logging.INFO)
    try:
        yield
    finally:
        log.removeHandler(handler)
        handler.close()
