"""Random draws of the LFE domain from numpy's legacy ``RandomState`` stream."""

from __future__ import annotations

__all__ = ["Draws"]


class Draws:
    """The draws the simulator makes, from one ``RandomState``."""

    def __init__(self, random_state):
        self.random_state = random_state

    def uniform(self, low, high, size=None):
        return self.random_state.uniform(low, high, size)

    def normal(self, loc, scale, size=None):
        return self.random_state.normal(loc, scale, size)

    def random_sample(self):
        return self.random_state.random_sample()
