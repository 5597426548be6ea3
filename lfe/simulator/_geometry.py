"""The simulator's geometry: distances, headings, orbit points and steps along a heading.

The only place the simulator computes a distance or an angle, with :mod:`lfe.detmath`'s
deterministic functions (never numpy's ``hypot``, ``arctan2``, ``sin``, ``cos``, whose last
bit depends on the CPU), so a mission is the same bits on every IEEE-754 machine. ``% 360.0``
is exact (``fmod`` is exactly representable; C and IEEE 754 fix it).
"""

from __future__ import annotations

import numpy as np

from lfe import detmath
from lfe.detmath import DEG, RAD

__all__ = ["heading_to", "mean_position", "norm", "orbit_point", "step_along"]


def norm(dx, dy):
    """Euclidean length of ``(dx, dy)`` (scalars or arrays): ``sqrt(dx*dx + dy*dy)``."""
    return detmath.hypot(dx, dy)


def heading_to(dx, dy):
    """Heading (degrees clockwise from north, in [0, 360]) of the direction ``(dx, dy)``."""
    return (detmath.atan2(dx, dy) * DEG) % 360.0


def step_along(heading, step):
    """``(dx, dy)`` of a move of length ``step`` along ``heading`` (degrees)."""
    sin, cos = detmath.sincos(heading * RAD)
    return step * sin, step * cos


def orbit_point(offset, radius, step_deg):
    """The point ``step_deg`` degrees clockwise of ``offset`` on a circle of ``radius``.

    ``offset`` is the position relative to the circle's centre; the result is relative to it
    too.
    """
    angle = detmath.atan2(offset[1], offset[0]) - step_deg * RAD
    sin, cos = detmath.sincos(angle)
    return radius * np.array([cos, sin])


def mean_position(points):
    """The mean of the rows of ``points`` (k, 2), summed in row order, then divided by k."""
    total = points[0].copy()
    for row in points[1:]:
        total = total + row
    return total / len(points)
