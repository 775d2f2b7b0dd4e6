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

import functools
import importlib
import logging
import threading
import time
import types

log = logging.getLogger("beeoptics")
_LOCK = threading.RLock()


def kernel(function):
    """Compile ``function`` with numba on its first call: cached on disk; without the GIL, so that
    one thread shades while another's rays are cast; with IEEE division, not
    Python's zero-division checks.

    Nothing of numba is imported until a kernel is first called, so that a
    job that only draws figures or tables, importing modules that hold
    kernels, does not pay for numba (about a second) or compile anything.
    """
    return Kernel(function)


def stage(function):
    """A :func:`kernel` that only another kernel calls, as one of its stages: compiled into that kernel (numba's
    ``inline="always"``), not on its own with the wrappers that let Python call it, which for a stage taking
    named tuples of arrays cost more to compile than the stage. A helper called from many places stays a
    kernel: inlined, numba would copy and compile it at every call.
    """
    return Kernel(function, inline=True)


class Kernel:
    """A function numba compiles on its first call (:func:`kernel`, :func:`stage`)."""

    def __init__(self, function, inline=False):
        functools.update_wrapper(self, function)
        self.py_func = function
        self._options = {"inline": "always"} if inline else {}
        self._compiled = None

    def compiled(self):
        """The numba dispatcher, compiling it (and first the kernels it calls) if need be."""
        if self._compiled is None:
            with _LOCK:
                if self._compiled is None:
                    numba = _numba()
                    # numba reads a kernel's globals when it compiles it: the kernels it calls
                    # must be numba's by then, and the numba modules it names imported.
                    scope = self.py_func.__globals__
                    for name in _global_names(self.py_func.__code__):
                        value = scope.get(name)
                        if isinstance(value, Kernel):
                            scope[name] = value.compiled()
                        elif isinstance(value, NumbaModule):
                            scope[name] = importlib.import_module(value.name)
                    self._compiled = numba.njit(cache=True, nogil=True, error_model="numpy",
                                                **self._options)(self.py_func)
        return self._compiled

    def __call__(self, *args, **kwargs):
        return self.compiled()(*args, **kwargs)


class NumbaModule:
    """A module of numba's that kernels name (``numba.typed``, ``numba.types``), imported when the first of
    them is compiled, so that importing the module that holds them imports nothing of numba."""

    def __init__(self, name):
        self.name = name


def _global_names(code):
    """The global names a function's code, and the code nested in it, refers to."""
    names = set(code.co_names)
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            names |= _global_names(const)
    return names


@functools.cache
def _numba():
    """numba, imported once, with the notice of each compilation registered."""
    import numba
    from numba.core import event

    event.register("numba:compile", _compile_notice(event))
    return numba


def _compile_notice(event):
    """A listener that logs each compilation numba runs (a kernel with the kernels it calls), with its time."""

    class CompileNotice(event.Listener):
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

    return CompileNotice()
