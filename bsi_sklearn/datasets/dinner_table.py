"""Dinner-table setting domain: regions, ground truth, labelling and the demonstration generator.

The scene's constants live in ``_dinner_scene``, the simulated wrist motion in
``_dinner_motion``; demonstrations have two wrists tracked with poses in SE(3).
"""

from __future__ import annotations

from numbers import Integral, Real

import numpy as np
import pandas as pd
from sklearn.utils import Bunch, check_random_state

from bsi_sklearn.datasets._dinner_motion import simulate_demonstration
from bsi_sklearn.datasets._dinner_scene import (
    _P,
    _TARGETS,
    CENTERPIECE_XY,
    MEALS,
    NEGATIVE_KINDS,
    PARTICIPANTS,
    PIECES,
    STACK,
    TABLE_HEIGHT,
)
from bsi_sklearn.datasets._kinds import check_kinds
from bsi_sklearn.datasets.tsr import TaskSpaceRegion, make_pose
from bsi_sklearn.param_validation import Interval, validate_params
from bsi_sklearn.specification import Specification

__all__ = [
    "make_dinner_table_demos",
    "dinner_table_labels",
    "dinner_table_specification",
    "dinner_table_tsrs",
    "PIECES",
    "MEALS",
    "PARTICIPANTS",
]

# negative_kinds is a sequence, checked by check_kinds.
_DEMOS_CONSTRAINTS = {
    "n_demos": [Interval(Integral, 0, None, closed="left")],
    "n_negative": [Interval(Integral, 0, None, closed="left")],
    "sampling_rate": [Interval(Real, 1.0, 1000.0, closed="both")],  # Hz
    "max_tries": [Interval(Integral, 1, None, closed="left")],
    "random_state": ["random_state"],
}


def _tsr_bounds(piece):
    free = [-np.pi, np.pi]
    if piece in STACK:
        return [[-0.04, 0.04], [-0.04, 0.04], [-0.006, 0.065], [-0.15, 0.15], [-0.15, 0.15],
                free]
    if piece in ("fork", "knife", "spoon"):
        return [[-0.03, 0.03], [-0.05, 0.05], [-0.006, 0.03], [-0.2, 0.2], [-0.2, 0.2],
                [-0.25, 0.25]]
    if piece == "water_glass":
        return [[-0.03, 0.03], [-0.03, 0.03], [-0.006, 0.02], [-0.1, 0.1], [-0.1, 0.1], free]
    return [[-0.03, 0.03], [-0.03, 0.03], [-0.006, 0.02], [-0.1, 0.1], [-0.1, 0.1],
            [-0.6, 0.6]]


def dinner_table_tsrs():
    """Task-space regions of the dinner-table domain.

    Returns
    -------
    tsrs : dict
        One :class:`TaskSpaceRegion` per piece (its frame sits at the piece's place on the
        table, yawed as the piece should lie; translation and rotation tolerances as a
        person would accept) and ``"centerpiece"``: a 0.26 m square column, 0.35 m tall,
        around the centerpiece, any orientation, that no wrist may enter.

    Examples
    --------
    >>> tsrs = dinner_table_tsrs()
    >>> sorted(tsrs)[:3]
    ['bowl', 'centerpiece', 'dinner_plate']
    >>> from bsi_sklearn.datasets.tsr import make_pose
    >>> bool(tsrs["fork"].contains(make_pose([-0.19, -0.2, 0.75], [0.0, 0.0, 1.6])))
    True
    """
    tsrs = {}
    for piece in PIECES:
        x, y, yaw = _TARGETS[piece]
        tsrs[piece] = TaskSpaceRegion(make_pose([x, y, TABLE_HEIGHT], [0.0, 0.0, yaw]),
                                      _tsr_bounds(piece))
    cx, cy = CENTERPIECE_XY
    tsrs["centerpiece"] = TaskSpaceRegion(
        make_pose([cx, cy, TABLE_HEIGHT]),
        [[-0.13, 0.13], [-0.13, 0.13], [0.0, 0.35], [-np.pi, np.pi], [-np.pi, np.pi],
         [-np.pi, np.pi]],
    )
    return tsrs


def _names():
    omegas = [f"omega_{p}" for p in PIECES]
    pis = [f"pi_{p}" for p in PIECES]
    return ["tau_c"], omegas, pis


def dinner_table_specification():
    """Ground truth of the dinner-table task.

    ``G(tau_c)`` (no wrist in the centerpiece's region), ``pi_i -> F(omega_i)`` for every
    piece, and dinner plate before small plate before bowl (``pi_a -> (!omega_b U omega_a)``
    for the three ordered pairs).

    Returns
    -------
    specification : Specification

    Examples
    --------
    >>> spec = dinner_table_specification()
    >>> spec.n_conjuncts, sorted(spec.orders)[0]
    (12, ('omega_dinner_plate', 'omega_bowl'))
    """
    taus, omegas, pis = _names()
    return Specification(
        globals=taus,
        eventuals=omegas,
        orders=[(f"omega_{a}", f"omega_{b}") for a, b in zip(STACK[:-1], STACK[1:],
                                                                  strict=True)],
        conditions=dict(zip(omegas, pis, strict=True)),
    )


def dinner_table_labels(object_poses, wrist_poses, needed, *, tsrs=None):
    """Labelling functions of the dinner-table domain: poses to a boolean trace.

    - ``tau_c`` holds when no wrist pose lies in the centerpiece's TSR;
    - ``omega_i`` holds when piece ``i``'s pose lies in its TSR;
    - ``pi_i`` (constant) holds when the meal needs piece ``i``.

    Parameters
    ----------
    object_poses : array-like of shape (T, 8, 4, 4)
        World poses of the pieces, in the order of :data:`PIECES`.
    wrist_poses : array-like of shape (T, n_wrists, 4, 4)
        World poses of the demonstrator's wrists.
    needed : array-like of 8 bool, or iterable of piece names
        The pieces the meal needs.
    tsrs : dict, default=None
        Region per piece and ``"centerpiece"``; :func:`dinner_table_tsrs` when None.

    Returns
    -------
    trace : pandas.DataFrame of shape (T, 17), dtype bool
        Columns ``tau_c``, ``omega_<piece>`` and ``pi_<piece>``.

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn.datasets.tsr import make_pose
    >>> objects = make_pose(np.zeros((1, 8, 3)))  # every piece at the world origin
    >>> wrists = make_pose([[[0.0, 0.24, 0.9], [0.3, -0.6, 0.9]]])  # one over the centerpiece
    >>> trace = dinner_table_labels(objects, wrists, ["fork"])
    >>> trace[["tau_c", "omega_fork", "pi_fork", "pi_mug"]].iloc[0].tolist()
    [False, False, True, False]
    """
    tsrs = dinner_table_tsrs() if tsrs is None else tsrs
    obj = np.asarray(object_poses, dtype=float)
    wr = np.asarray(wrist_poses, dtype=float)
    if obj.ndim != 4 or obj.shape[1:] != (len(PIECES), 4, 4):
        raise ValueError(f"object_poses must have shape (T, 8, 4, 4), got {obj.shape}")
    if wr.ndim != 4 or wr.shape[0] != obj.shape[0] or wr.shape[2:] != (4, 4):
        raise ValueError(
            f"wrist_poses must have shape (T, n_wrists, 4, 4) with T = {obj.shape[0]}, "
            f"got {wr.shape}"
        )
    if obj.shape[0] < 1:
        raise ValueError("object_poses must hold at least one time step")
    missing = [k for k in (*PIECES, "centerpiece") if k not in tsrs]
    if missing:
        raise ValueError(f"tsrs lacks a region for {missing}")
    need = _check_needed(needed)
    T = obj.shape[0]
    omega = np.column_stack([tsrs[p].contains(obj[:, k]) for k, p in enumerate(PIECES)])
    tau = ~np.any(tsrs["centerpiece"].contains(wr), axis=1)
    data = np.concatenate(
        [tau[:, None], omega, np.broadcast_to(need, (T, len(PIECES)))], axis=1
    )
    taus, omegas, pis = _names()
    return pd.DataFrame(data, columns=taus + omegas + pis)


def _check_needed(needed):
    arr = None
    if not isinstance(needed, str):
        try:
            arr = np.asarray(needed)
        except (TypeError, ValueError):
            arr = None
    if arr is not None and arr.dtype == bool:
        if arr.shape != (len(PIECES),):
            raise ValueError(f"needed must have {len(PIECES)} booleans, got shape {arr.shape}")
        return arr
    if isinstance(needed, str):
        raise ValueError("needed must be an iterable of piece names or 8 booleans")
    need = np.zeros(len(PIECES), dtype=bool)
    for p in needed:
        if p not in _P:
            raise ValueError(f"needed has unknown piece {p!r}; pieces are {PIECES}")
        need[_P[p]] = True
    return need


def make_dinner_table_demos(
    n_demos=71,
    *,
    n_negative=0,
    negative_kinds=NEGATIVE_KINDS,
    sampling_rate=10.0,
    max_tries=50,
    random_state=None,
):
    """Simulate demonstrations of setting a dinner table, with both wrists tracked.

    A demonstrator stands at the front of a table; the eight pieces (:data:`PIECES`) wait on
    a side table to the right. Each demonstration serves one of four meals (:data:`MEALS`),
    which decides the pieces to place (the conditions ``pi_i``). Demonstration ``i`` is
    given by participant ``i % 6`` for meal ``(i // 6) % 4``, so every participant sets the
    table several times for every meal. Participants (:data:`PARTICIPANTS`) differ in
    dominant hand, speed, precision, preferred order (perturbed by random swaps from one
    demonstration to the next) and whether they carry fork and knife at once. Each
    piece is moved by pick, lift, carry, lower and release, the wrists following
    minimum-jerk motions between these keyframes; the piece follows the wrist that holds
    it. Poses are 4x4 homogeneous transforms in SE(3), sampled at ``sampling_rate``, with
    1 mm of tracking noise on every position.

    ``omega_i`` holds while piece ``i`` lies in its task-space region and ``tau_c`` while no
    wrist is in the centerpiece's region (:func:`dinner_table_labels`). In positive
    demonstrations the plates are stacked dinner plate, small plate, bowl, and the hands
    keep clear of the centerpiece. Negative ones break the ground truth in one of
    ``negative_kinds``, chosen uniformly among those possible for the meal:

    - ``"centerpiece"``: one carry passes over the centerpiece, through its region;
    - ``"skip"``: a needed piece is never placed;
    - ``"misplace"``: a needed piece is put down out of its region (shifted, or cutlery and
      mug turned the wrong way) and left there;
    - ``"order"``: two needed plates / bowl are placed in the wrong stacking order (when
      ``"order"`` is the only kind, a meal needing fewer than two of them is replaced by
      the next meal in the cycle).

    Every positive satisfies the ground truth and every negative violates it (checked with
    :meth:`Specification.satisfied_by`; a failing draw is redrawn).

    Parameters
    ----------
    n_demos : int, default=71
        Number of positive demonstrations (the paper collected 71).
    n_negative : int, default=0
        Number of negative demonstrations, returned after the positives.
    negative_kinds : sequence of str, default=all four
        Among ``"centerpiece"``, ``"skip"``, ``"misplace"``, ``"order"``.
    sampling_rate : float, default=10.0
        Tracking rate in Hz.
    max_tries : int, default=50
        Draws allowed per demonstration before giving up with ``RuntimeError``.
    random_state : int, RandomState instance or None, default=None

    Returns
    -------
    data : sklearn.utils.Bunch
        - ``traces``: list of ``pandas.DataFrame`` (bool), columns ``feature_names``;
        - ``labels``: ndarray of int, 1 for positives, 0 for negatives;
        - ``feature_names``: ``tau_c``, ``omega_<piece>`` (8), ``pi_<piece>`` (8);
        - ``roles``: dict with ``global_candidates`` (``["tau_c"]``), ``subtasks``
          (the ``omega_<piece>``) and ``conditions`` (``omega_<piece> -> pi_<piece>``);
        - ``specification``: the ground truth (:func:`dinner_table_specification`);
        - ``object_poses``: list of ndarray ``(T_i, 8, 4, 4)``;
        - ``wrist_poses``: list of ndarray ``(T_i, 2, 4, 4)`` (left, right);
        - ``times``: list of ndarray ``(T_i,)`` in seconds;
        - ``meals``, ``participants`` (1 to 6): per demonstration;
        - ``placements``: list of the pieces in the order they were put down;
        - ``violations``: ``""`` for positives, else the negative kind;
        - ``pieces``, ``meal_configurations``, ``participant_habits``, ``tsrs``,
          ``centerpiece_pose``, ``DESCR``.

    Examples
    --------
    >>> data = make_dinner_table_demos(4, n_negative=2, random_state=0)
    >>> data.labels.tolist(), data.meals[:2]
    ([1, 1, 1, 1, 0, 0], ['dinner', 'dinner'])
    >>> data.object_poses[0].shape[1:], data.wrist_poses[0].shape[1:]
    ((8, 4, 4), (2, 4, 4))
    >>> all(data.specification.satisfied_by(t) == bool(y)
    ...     for t, y in zip(data.traces, data.labels))
    True
    """
    validate_params(
        {"n_demos": n_demos, "n_negative": n_negative, "sampling_rate": sampling_rate,
         "max_tries": max_tries, "random_state": random_state},
        _DEMOS_CONSTRAINTS, "make_dinner_table_demos",
    )
    n_demos, n_negative, max_tries = int(n_demos), int(n_negative), int(max_tries)
    if n_demos + n_negative < 1:
        raise ValueError("n_demos + n_negative must be at least 1")
    kinds = check_kinds(negative_kinds, n_negative, NEGATIVE_KINDS)
    rng = check_random_state(random_state)
    tsrs = dinner_table_tsrs()
    spec = dinner_table_specification()
    meal_names = list(MEALS)
    out = Bunch(traces=[], object_poses=[], wrist_poses=[], times=[], meals=[],
                participants=[], placements=[], violations=[])
    for i in range(n_demos + n_negative):
        negative = i >= n_demos
        participant = i % len(PARTICIPANTS)
        meal = meal_names[(i // len(PARTICIPANTS)) % len(MEALS)]
        if negative and kinds == ("order",) and sum(q in STACK for q in MEALS[meal]) < 2:
            # no stacking order to break in this meal: take the next meal that has one
            start = meal_names.index(meal)
            meal = next(m for m in meal_names[start:] + meal_names[:start]
                        if sum(q in STACK for q in MEALS[m]) >= 2)
        for _ in range(max_tries):
            demo = simulate_demonstration(participant, meal, rng, tsrs,
                                          kinds if negative else None,
                                          1.0 / float(sampling_rate))
            if demo is None:
                continue
            objects, wrists, times, placed, kind = demo
            trace = dinner_table_labels(objects, wrists, MEALS[meal], tsrs=tsrs)
            if spec.satisfied_by(trace) != negative:
                break
        else:
            raise RuntimeError(
                f"no valid {'negative' if negative else 'positive'} demonstration in "
                f"{max_tries} draws (demonstration {i}, meal {meal!r})"
            )
        out.traces.append(trace)
        out.object_poses.append(objects)
        out.wrist_poses.append(wrists)
        out.times.append(times)
        out.meals.append(meal)
        out.participants.append(participant + 1)
        out.placements.append(placed)
        out.violations.append(kind if negative else "")
    taus, omegas, pis = _names()
    out.labels = np.array([1] * n_demos + [0] * n_negative)
    out.feature_names = taus + omegas + pis
    out.roles = {
        "global_candidates": list(taus),
        "subtasks": list(omegas),
        "conditions": dict(zip(omegas, pis, strict=True)),
    }
    out.specification = spec
    out.pieces = list(PIECES)
    out.meal_configurations = {m: list(p) for m, p in MEALS.items()}
    out.participant_habits = [dict(h) for h in PARTICIPANTS]
    out.tsrs = tsrs
    out.centerpiece_pose = tsrs["centerpiece"].T0_w.copy()
    out.DESCR = (
        f"Simulated dinner-table setting: {n_demos} positive and {n_negative} negative "
        f"demonstrations by {len(PARTICIPANTS)} participants over {len(MEALS)} meals.\n"
        f"Ground truth: {spec.to_ltl()}"
    )
    return out
