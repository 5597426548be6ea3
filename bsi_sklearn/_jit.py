"""How the package's numba helpers are compiled: :func:`helper`.

Every compiled function costs its first fit in a fresh environment compilation time (issue 29),
and numba builds, for each one, a CPython wrapper (unboxing every argument, NamedTuples of
arrays included) and a C wrapper, then optimises and emits machine code for them, even when
the function is only ever called from other compiled functions. A *helper* is such a function:
it is compiled without either wrapper, and cannot be called from Python. The entry points
that Python calls stay ``njit(cache=True, nogil=True)``.
"""

from numba import njit

__all__ = ["helper"]

#: Decorator of a numba function called only from other numba functions.
helper = njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
