"""Compiled kernels: how numba compiles them, where it keeps them, and the one notice of compiling.

The tracer's shading between two Embree casts, and the facet relaxation's
steps, are compiled by numba on first use and cached on disk, so that they
are compiled once per install: next to the package's source when that
folder is writable (an editable install, or a wheel in a user's
environment); otherwise, for a read-only site-packages, in numba's
user-wide cache (``$XDG_CACHE_HOME/numba`` or ``~/.cache/numba``), or
wherever ``NUMBA_CACHE_DIR`` points. Each kernel
that is compiled, rather than loaded from the cache, logs how long that
took: a first run says so, later runs are silent.

References
----------
Lam SK, Pitrou A, Seibert S (2015) Numba: a LLVM-based Python JIT compiler.
Proc. Second Workshop on the LLVM Compiler Infrastructure in HPC, 7:1–6.
"""

import logging
import time

import numba
from numba.core import event

log = logging.getLogger("beeoptics")


def kernel(function):
    """Compile ``function`` with numba: cached on disk; without the GIL, so that
    one thread shades while another's rays are cast; with IEEE division, not
    Python's zero-division checks."""
    return numba.njit(cache=True, nogil=True, error_model="numpy")(function)


class _CompileNotice(event.Listener):
    """Logs each compilation numba runs (a kernel with the kernels it calls), with its time."""

    def __init__(self):
        self._depth, self._start = 0, 0.0

    def on_start(self, ev):
        if self._depth == 0:
            self._start = time.perf_counter()
        self._depth += 1

    def on_end(self, ev):
        self._depth -= 1
        if self._depth == 0:
            name = getattr(ev.data.get("dispatcher"), "__qualname__", "a kernel")
            log.warning("compiled %s in %.1f s, once: numba caches it for later runs", name,
                        time.perf_counter() - self._start)


event.register("numba:compile", _CompileNotice())
