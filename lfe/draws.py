"""Random draws of the LFE domain: numpy's frozen ``RandomState`` stream, the same everywhere.

``RandomState``'s stream is frozen (NEP 19): ``random_sample`` and ``randint`` give the same
bits on every machine and numpy version. Its ``uniform`` and ``normal`` are not safe to the
last bit: ``uniform`` computes ``low + (high - low) * u`` in C, which a compiler may fuse into
a multiply-add on some platforms, and ``normal`` calls the platform's ``log``. The functions
here draw the same ``random_sample`` values in the same order and do the arithmetic in Python
with :mod:`lfe.detmath`:

- :func:`uniform` is ``low + (high - low) * u``, bit for bit ``RandomState.uniform`` wherever
  that is not fused (x86-64);
- :func:`normal` is ``RandomState.normal``'s polar Box-Muller method (``legacy_gauss``: pairs
  of uniforms in the unit disc, one value kept for the next call) with the deterministic
  ``log``; it reads and writes the ``RandomState``'s cached value, so the stream continues as
  numpy's would, and its values differ from numpy's only where the platform's ``log`` rounds
  differently.

Examples
--------
>>> import numpy as np
>>> from lfe.draws import normal, uniform
>>> float(uniform(np.random.RandomState(0), -1.0, 1.0)) == float(
...     np.random.RandomState(0).uniform(-1.0, 1.0))
True
>>> a = normal(np.random.RandomState(0), 0.0, 1.0, size=3)
>>> bool(np.allclose(a, np.random.RandomState(0).normal(0.0, 1.0, size=3), rtol=1e-15))
True
"""

from __future__ import annotations

import math

import numpy as np

from lfe.detmath import log

__all__ = ["Draws", "normal", "uniform"]


def uniform(random_state, low, high, size=None):
    """``size`` uniform draws in ``[low, high)``: ``low + (high - low) * random_sample()``.

    Parameters
    ----------
    random_state : numpy.random.RandomState
    low, high : float
    size : int or tuple of int, default=None
        ``None`` draws one float.

    Returns
    -------
    draws : float or ndarray
    """
    low, high = float(low), float(high)
    span = high - low
    if size is None:
        return low + span * random_state.random_sample()
    return low + span * random_state.random_sample(size)


def _gauss_pair(random_state):
    """One accepted pair of ``legacy_gauss``: ``(returned now, kept for the next call)``."""
    while True:
        x1 = 2.0 * random_state.random_sample() - 1.0
        x2 = 2.0 * random_state.random_sample() - 1.0
        r2 = x1 * x1 + x2 * x2
        if r2 < 1.0 and r2 != 0.0:
            break
    f = math.sqrt(-2.0 * log(r2) / r2)
    return f * x2, f * x1


def normal(random_state, loc, scale, size=None):
    """Normal draws, ``loc + scale * gauss`` as ``RandomState.normal`` (see the module).

    Parameters
    ----------
    random_state : numpy.random.RandomState
    loc, scale : float
    size : int or tuple of int, default=None
        ``None`` draws one float.

    Returns
    -------
    draws : float or ndarray
    """
    loc, scale = float(loc), float(scale)
    state = random_state.get_state(legacy=True)
    has_gauss, cached = bool(state[3]), float(state[4])
    count = 1 if size is None else int(np.prod(size, dtype=np.int64))
    values = np.empty(count)
    for k in range(count):
        if has_gauss:
            gauss, has_gauss = cached, False
        else:
            gauss, cached = _gauss_pair(random_state)
            has_gauss = True
        values[k] = loc + scale * gauss
    state = random_state.get_state(legacy=True)
    random_state.set_state((*state[:3], int(has_gauss), cached if has_gauss else 0.0))
    return float(values[0]) if size is None else values.reshape(size)


class Draws:
    """The draws of one simulation, from its ``RandomState`` (:func:`uniform`, :func:`normal`).

    Parameters
    ----------
    random_state : numpy.random.RandomState
    """

    def __init__(self, random_state):
        self.random_state = random_state

    def uniform(self, low, high, size=None):
        """See :func:`uniform`."""
        return uniform(self.random_state, low, high, size)

    def normal(self, loc, scale, size=None):
        """See :func:`normal`."""
        return normal(self.random_state, loc, scale, size)

    def random_sample(self):
        """One ``RandomState.random_sample()`` (exact on every machine)."""
        return self.random_state.random_sample()
