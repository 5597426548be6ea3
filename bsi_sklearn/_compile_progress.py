"""What a user sees while numba compiles the kernels on their first use (cached afterwards).

In a fresh environment the first fit compiles the numba kernels it calls, which takes seconds;
later processes load them from numba's disk cache (``python -m bsi_sklearn.compile`` fills it
ahead of time, :mod:`bsi_sklearn.compile`). Two things say so:

- a *notice*: once this package's kernels have spent a second compiling, one line on standard
  error says what is happening and how to do it ahead of time, whatever the ``verbose``
  setting; once per burst of compilation (a burst ends after :data:`QUIET_GAP` seconds
  without compiling, so a later fit that compiles other kernels says it again). A timer
  thread prints it, so it comes at the first second even while one long kernel compiles. It
  is a plain line, not a warning (no warning filter repeats or hides it); every process that
  compiles prints its own (each joblib or dask worker that starts cold waits too, and its
  standard error is where its output goes). :func:`install_notice` starts listening;
  :mod:`bsi_sklearn.model.clauses`, which every fit, prediction and monitor imports, calls it.
- a *bar* (tqdm) over the kernels being compiled, for ``verbose > 0`` inside
  :func:`compile_progress`; the notice stays quiet while a bar is shown
  (:func:`quiet_notice`), as it does while the compile step runs.
"""

import contextlib
import sys
import threading
import time

from numba.core import event

__all__ = ["compile_progress", "install_notice", "quiet_notice", "NOTICE", "NOTICE_UNCACHED",
           "DELAY", "QUIET_GAP"]

#: Seconds of compilation before the notice is printed.
DELAY = 1.0
#: Seconds without compiling that end a burst: a later compilation may print the notice again.
QUIET_GAP = 2.0
#: The line printed (standard error); the second when numba has no writable cache.
NOTICE = ("bsi_sklearn: compiling numba kernels on first use (once; later processes load them "
          "from the cache). To compile them all ahead: python -m bsi_sklearn.compile")
NOTICE_UNCACHED = ("bsi_sklearn: compiling numba kernels (no writable numba cache: every "
                   "process compiles them again; set NUMBA_CACHE_DIR to a writable folder)")


def _ours(ev):
    """Whether a compile event is one of this package's functions."""
    func = getattr(ev.data.get("dispatcher"), "py_func", None)
    return getattr(func, "__module__", "").split(".")[0] == "bsi_sklearn"


def _notice_text():
    from numba.core.dispatcher import Dispatcher

    if getattr(Dispatcher.enable_caching, "_bsi_sklearn_skips", False):  # _numba_cache
        return NOTICE_UNCACHED
    return NOTICE


class _Notice(event.Listener):
    """One line on standard error when this package's kernels compile for over DELAY seconds.

    Listens to every ``numba:compile`` event of the process. A burst starts with a top-level
    compilation of one of this package's functions and lasts while compilations follow each
    other within :data:`QUIET_GAP` seconds; the notice is printed once the burst has spent
    ``delay`` seconds compiling (the time between compilations does not count).
    """

    def __init__(self, stream=None, delay=DELAY, quiet_gap=QUIET_GAP):
        self.stream = stream
        self.delay = delay
        self.quiet_gap = quiet_gap
        self.lock = threading.Lock()
        self.depth = 0          # nesting of the compilations under way (any package)
        self.burst = False      # a burst of this package's compilations is under way
        self.busy = 0.0         # seconds the burst has compiled, up to busy_since
        self.busy_since = 0.0   # when the compilation under way started
        self.last = float("-inf")  # when a compilation last ended
        self.printed = False    # the notice of the current burst is out
        self.bars = 0           # compile_progress bars open: they say it already
        self.timer = None

    def on_start(self, ev):
        with self.lock:
            now = time.monotonic()
            if self.depth == 0:
                if not self.burst or now - self.last > self.quiet_gap:
                    self.burst = _ours(ev)
                    self.busy = 0.0
                    self.printed = False
                self.busy_since = now
                if self.burst:
                    self._arm(now)
            self.depth += 1

    def on_end(self, ev):
        with self.lock:
            self.depth = max(self.depth - 1, 0)
            now = time.monotonic()
            if self.depth == 0:
                self.busy += now - self.busy_since
                self.last = now
            self._check(now)

    def _compiled(self, now):
        return self.busy + (now - self.busy_since if self.depth else 0.0)

    def _arm(self, now):
        # A timer for when the burst will have compiled `delay` seconds, if it goes on.
        if self.printed:
            return
        if self.timer is not None:
            self.timer.cancel()
        self.timer = threading.Timer(max(self.delay - self._compiled(now), 0.0),
                                     self._on_timer)
        self.timer.daemon = True
        self.timer.start()

    def _on_timer(self):
        with self.lock:
            now = time.monotonic()
            self._check(now)
            if self.depth and not self.printed:
                self._arm(now)  # started before the previous compilations were counted

    def _check(self, now):
        # With the lock held: print once the burst has compiled for `delay` seconds.
        if self.printed or not self.burst or self._compiled(now) < self.delay:
            return
        self.printed = True
        if self.bars:
            return
        stream = self.stream if self.stream is not None else sys.stderr
        try:
            print(_notice_text(), file=stream, flush=True)
        except (OSError, ValueError, AttributeError):  # no usable standard error
            pass


_NOTICE = _Notice()
_installed = False


def install_notice():
    """Listen to numba's compilations for the notice (once per process; idempotent)."""
    global _installed
    if not _installed:
        event.register("numba:compile", _NOTICE)
        _installed = True


@contextlib.contextmanager
def quiet_notice():
    """No notice inside the block (``python -m bsi_sklearn.compile`` says what it does)."""
    with _NOTICE.lock:
        _NOTICE.bars += 1
    try:
        yield
    finally:
        with _NOTICE.lock:
            _NOTICE.bars -= 1


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

    Without it (``verbose=0``) the notice of :func:`install_notice` still says, in one line,
    when compilation takes more than a second.

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
        with quiet_notice(), event.install_listener("numba:compile", listener):
            yield
    finally:
        listener.close()
