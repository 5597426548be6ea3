"""The simulator's geometry: distances, headings, orbit points and steps along a heading.

The only place the simulator computes a distance or an angle.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["heading_to", "norm", "orbit_point", "step_along"]


def norm(dx, dy):
    """Euclidean length of ``(dx, dy)`` (scalars or arrays)."""
    return np.hypot(dx, dy)


def heading_to(dx, dy):
    """Heading (degrees clockwise from north, in [0, 360)) of the direction ``(dx, dy)``."""
    return np.degrees(np.arctan2(dx, dy)) % 360.0


def step_along(heading, step):
    """``(dx, dy)`` of a move of length ``step`` along ``heading`` (degrees)."""
    rad = np.radians(heading)
    return step * np.sin(rad), step * np.cos(rad)


def orbit_point(offset, radius, step_deg):
    """The point ``step_deg`` degrees clockwise of ``offset`` on a circle of ``radius``.

    ``offset`` is the position relative to the circle's centre; the result is relative to it
    too.
    """
    angle = math.atan2(offset[1], offset[0]) - math.radians(step_deg)
    return radius * np.array([math.cos(angle), math.sin(angle)])
