"""Progress while numba compiles the kernels on their first use (cached on disk afterwards).

In a fresh environment the first fit compiles the numba kernels it calls, which takes seconds;
later processes load them from numba's disk cache. :func:`compile_progress` shows a progress bar
(tqdm) over the kernels being compiled, only when compilation actually happens and only for
``verbose > 0``.
"""

import contextlib

from numba.core import event

__all__ = ["compile_progress"]


class _CompileBar(event.Listener):
    """Counts numba's top-level compilations into a bar opened at the first one."""

    def __init__(self):
        self.bar = None
        self.depth = 0

    def on_start(self, ev):
        if self.bar is None:
            from tqdm.auto import tqdm

            self.bar = tqdm(desc="compiling numba kernels (first use; cached afterwards)",
                            unit="kernel")
        self.depth += 1

    def on_end(self, ev):
        self.depth -= 1
        if self.depth == 0:
            self.bar.update(1)

    def close(self):
        if self.bar is not None:
            self.bar.close()


@contextlib.contextmanager
def compile_progress(verbose):
    """Show a bar while numba compiles inside the block, when ``verbose > 0``.

    Parameters
    ----------
    verbose : int
        Nothing is shown (and nothing is installed) for 0.

    Examples
    --------
    >>> with compile_progress(0):
    ...     pass
    """
    if not verbose:
        yield
        return
    listener = _CompileBar()
    try:
        with event.install_listener("numba:compile", listener):
            yield
    finally:
        listener.close()
