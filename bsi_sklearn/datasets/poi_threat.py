"""Synthetic 2-D navigation domain: points of interest to visit and threats to avoid."""

from __future__ import annotations

import re
from numbers import Integral, Real

import numpy as np
import pandas as pd
from sklearn.utils import Bunch, check_random_state

from bsi_sklearn.datasets._kinds import check_kinds
from bsi_sklearn.datasets._poi_navigation import Navigator
from bsi_sklearn.param_validation import Interval, Options, validate_params
from bsi_sklearn.specification import Specification

__all__ = [
    "make_poi_threat_demos",
    "poi_threat_labels",
    "poi_threat_specification",
]

#: Fixed POI layouts of the paper's scenarios (world coordinates in ``[0, 10] x [0, 10]``).
POI_LAYOUTS = {
    4: np.array([[2.0, 3.5], [2.5, 8.0], [7.5, 8.0], [8.0, 3.5]]),
    5: np.array([[1.5, 4.0], [3.0, 8.5], [6.5, 8.5], [8.5, 5.5], [6.0, 2.5]]),
}
_SCENARIO_ORDERS = {1: [(1, 2), (2, 3), (3, 4)], 2: [(1, 3), (3, 5)], 3: []}
_SCENARIO_N_POIS = {1: 4, 2: 5, 3: 5}
NEGATIVE_KINDS = ("threat", "skip", "order")

_SCENARIOS = Options(Integral, tuple(_SCENARIO_ORDERS))
_N_THREATS = [Interval(Integral, 1, None, closed="left")]
_POSITIVE = [Interval(Real, 0, None, closed="neither")]
# poi_positions, start and negative_kinds are arrays / sequences, checked where they are read.
_DEMOS_CONSTRAINTS = {
    "scenario": [_SCENARIOS, Specification],
    "n_demos": [Interval(Integral, 0, None, closed="left")],
    "n_negative": [Interval(Integral, 0, None, closed="left")],
    "n_threats": _N_THREATS,
    "threat_radius": _POSITIVE,
    "poi_radius": _POSITIVE,
    "speed": _POSITIVE,
    "max_turn_rate": _POSITIVE,
    "max_tries": [Interval(Integral, 1, None, closed="left")],
    "random_state": ["random_state"],
}


def _names(n_threats, n_pois):
    taus = [f"tau_{i}" for i in range(1, n_threats + 1)]
    omegas = [f"omega_{i}" for i in range(1, n_pois + 1)]
    pis = [f"pi_{i}" for i in range(1, n_pois + 1)]
    return taus, omegas, pis


def poi_threat_specification(scenario, n_threats=5):
    """Ground-truth specification of one of the paper's synthetic scenarios.

    Every scenario requires ``G(tau_i)`` for every threat and ``pi_i -> F(omega_i)`` for
    every POI. Scenario 1 (4 POIs) orders ``1 < 2 < 3 < 4``; Scenario 2 (5 POIs) orders the
    chain ``1 < 3 < 5`` and leaves ``{2, 4}`` free; Scenario 3 (5 POIs) has no order.

    Parameters
    ----------
    scenario : {1, 2, 3}
    n_threats : int, default=5

    Returns
    -------
    specification : Specification
        Identifiers are the proposition names ``tau_i``, ``omega_i``; conditions map every
        ``omega_i`` to ``pi_i``.

    Examples
    --------
    >>> print(poi_threat_specification(2, n_threats=1).to_ltl())  # doctest: +NORMALIZE_WHITESPACE
    G(tau_1) & (pi_1 -> F(omega_1)) & (pi_2 -> F(omega_2)) & (pi_3 -> F(omega_3))
    & (pi_4 -> F(omega_4)) & (pi_5 -> F(omega_5)) & (pi_1 -> (!omega_3 U omega_1))
    & (pi_1 -> (!omega_5 U omega_1)) & (pi_3 -> (!omega_5 U omega_3))
    """
    validate_params({"scenario": scenario, "n_threats": n_threats},
                    {"scenario": [_SCENARIOS], "n_threats": _N_THREATS},
                    "poi_threat_specification")
    n_threats = int(n_threats)
    taus, omegas, pis = _names(n_threats, _SCENARIO_N_POIS[scenario])
    return Specification(
        globals=taus,
        eventuals=omegas,
        orders=[(f"omega_{a}", f"omega_{b}") for a, b in _SCENARIO_ORDERS[scenario]],
        conditions=dict(zip(omegas, pis, strict=True)),
    )


def poi_threat_labels(
    positions, threat_positions, poi_positions, *, threat_radius=1.0, poi_radius=0.4
):
    """Labelling functions of the synthetic domain: positions to a boolean trace.

    - ``tau_i`` holds when the agent is at least ``threat_radius`` from threat ``i``;
    - ``omega_i`` holds when the agent is within ``poi_radius`` of POI ``i``;
    - ``pi_i`` (constant) holds when POI ``i`` is farther than ``threat_radius`` from every
      threat, i.e. it is accessible.

    Parameters
    ----------
    positions : array-like of shape (T, 2)
        Agent positions over time (extra columns, such as a heading, are ignored).
    threat_positions : array-like of shape (n_threats, 2)
    poi_positions : array-like of shape (n_pois, 2)
    threat_radius : float, default=1.0
        Avoidance radius ``epsilon_threat``.
    poi_radius : float, default=0.4
        Tolerance radius ``epsilon_POI``.

    Returns
    -------
    trace : pandas.DataFrame of shape (T, n_threats + 2 * n_pois), dtype bool
        Columns ``tau_1..``, ``omega_1..``, ``pi_1..``.

    Examples
    --------
    >>> trace = poi_threat_labels([[0, 0], [1, 0], [2, 0]], [[2, 0.5]], [[1, 0.1]])
    >>> trace.astype(int).to_numpy().tolist()
    [[1, 0, 1], [1, 1, 1], [0, 0, 1]]
    >>> list(trace.columns)
    ['tau_1', 'omega_1', 'pi_1']
    """
    pos = _as_points(positions, "positions", extra_columns=True)[:, :2]
    threats = _as_points(threat_positions, "threat_positions", allow_empty=True)
    pois = _as_points(poi_positions, "poi_positions", allow_empty=True)
    validate_params({"threat_radius": threat_radius, "poi_radius": poi_radius},
                    _DEMOS_CONSTRAINTS, "poi_threat_labels")
    threat_radius, poi_radius = float(threat_radius), float(poi_radius)
    tau, omega, pi = _label_arrays(pos, threats, pois, threat_radius, poi_radius)
    taus, omegas, pis = _names(len(threats), len(pois))
    data = np.concatenate([tau, omega, np.broadcast_to(pi, (len(pos), len(pois)))], axis=1)
    return pd.DataFrame(data, columns=taus + omegas + pis)


def _label_arrays(pos, threats, pois, threat_radius, poi_radius):
    d_threat = np.linalg.norm(pos[:, None, :] - threats[None, :, :], axis=-1)
    d_poi = np.linalg.norm(pos[:, None, :] - pois[None, :, :], axis=-1)
    d_poi_threat = np.linalg.norm(pois[:, None, :] - threats[None, :, :], axis=-1)
    tau = d_threat >= threat_radius
    omega = d_poi <= poi_radius
    pi = ~np.any(d_poi_threat <= threat_radius, axis=1)
    return tau, omega, pi


def make_poi_threat_demos(
    scenario=1,
    *,
    n_demos=20,
    n_negative=0,
    n_threats=5,
    poi_positions=None,
    threat_radius=1.0,
    poi_radius=0.4,
    speed=0.15,
    max_turn_rate=0.6,
    start=(5.0, 0.5),
    negative_kinds=NEGATIVE_KINDS,
    max_tries=200,
    random_state=None,
):
    """Generate demonstrations of the paper's synthetic POI / threat navigation domain.

    An agent with Dubins-car dynamics (constant ``speed`` per time step, turn rate bounded by
    ``max_turn_rate`` radians per step) starts at ``start`` in the square ``[0, 10]^2``. In
    every demonstration ``n_threats`` threats are placed uniformly (away from the start);
    POIs stay at fixed positions. The agent plans shortest paths on a 0.1-resolution grid
    around the threat zones (inflated by a safety margin) and follows them by pure pursuit,
    visiting the POIs the specification requires and that are accessible, in a random linear
    extension of the specification's partial order. On its way it keeps out of the tolerance
    zone of every POI it has not yet visited, other than its current goal, so the POIs are
    first reached in the planned order. The trace ends when the last POI is reached.

    Negative demonstrations break the specification in one of ``negative_kinds``, chosen
    uniformly among those possible for the threat layout:

    - ``"threat"``: the agent ignores one threat of the specification's globals and flies
      through the middle of its zone;
    - ``"skip"``: the agent never visits one accessible POI the specification requires;
    - ``"order"``: the agent visits an accessible POI ``b`` before an accessible ``a`` that
      the specification orders before it.

    Every positive demonstration satisfies the ground truth and every negative one violates
    it (checked with :meth:`Specification.satisfied_by`); a draw that does not (the car
    clipped a threat zone in a tight turn, a POI is accessible but cannot be reached safely)
    is discarded and the threats are redrawn.

    Parameters
    ----------
    scenario : {1, 2, 3} or Specification, default=1
        The paper's scenarios (see :func:`poi_threat_specification`) or a custom
        specification over the names ``tau_i`` (globals), ``omega_i`` (eventuals, orders).
        Its conditions are replaced by the domain's ``omega_i -> pi_i``.
    n_demos : int, default=20
        Number of positive (acceptable) demonstrations.
    n_negative : int, default=0
        Number of negative (unacceptable) demonstrations, returned after the positives.
    n_threats : int, default=5
    poi_positions : array-like of shape (n_pois, 2), default=None
        POI positions; ``None`` takes the scenario's layout (4 POIs in Scenario 1, else 5).
    threat_radius : float, default=1.0
        Avoidance radius ``epsilon_threat``.
    poi_radius : float, default=0.4
        Tolerance radius ``epsilon_POI``; must exceed ``speed``.
    speed : float, default=0.15
        Distance travelled per time step.
    max_turn_rate : float, default=0.6
        Largest heading change per time step (radians); the turning radius is
        ``speed / max_turn_rate`` and must stay below 0.3 (the planner's margin is 0.35).
    start : (float, float), default=(5.0, 0.5)
        Start position; the heading starts upwards with a random deviation of up to 0.5 rad.
    negative_kinds : sequence of {"threat", "skip", "order"}, default=all three
    max_tries : int, default=200
        Draws allowed per demonstration before giving up with ``RuntimeError``.
    random_state : int, RandomState instance or None, default=None

    Returns
    -------
    data : sklearn.utils.Bunch
        - ``traces``: list of ``pandas.DataFrame`` (bool), columns ``feature_names``;
        - ``labels``: ndarray of int, 1 for positives, 0 for negatives;
        - ``feature_names``: ``tau_1..``, ``omega_1..``, ``pi_1..``;
        - ``roles``: dict with ``global_candidates`` (the ``tau_i``), ``subtasks`` (the
          ``omega_i``) and ``conditions`` (``omega_i -> pi_i``), as ``BSIClassifier``
          parameters;
        - ``specification``: the ground-truth ``Specification``;
        - ``trajectories``: list of ndarray ``(T_i, 3)``, columns x, y, heading;
        - ``threat_positions``: list of ndarray ``(n_threats, 2)``;
        - ``poi_positions``: ndarray ``(n_pois, 2)``;
        - ``accessible``: list of bool ndarray ``(n_pois,)`` (the ``pi_i``);
        - ``visit_orders``: list of lists of POI numbers (1-based) in planned order;
        - ``violations``: list of str, ``""`` for positives, else the negative kind;
        - ``threat_radius``, ``poi_radius``, ``start``, ``world_size``, ``scenario``,
          ``DESCR``.

    See Also
    --------
    bsi_sklearn.datasets.plot_demos : draw the generated demonstrations.

    Examples
    --------
    >>> data = make_poi_threat_demos(1, n_demos=3, n_negative=2, random_state=0)
    >>> len(data.traces), data.labels.tolist()
    (5, [1, 1, 1, 0, 0])
    >>> data.feature_names[:6]
    ['tau_1', 'tau_2', 'tau_3', 'tau_4', 'tau_5', 'omega_1']
    >>> all(data.specification.satisfied_by(t) == bool(y)
    ...     for t, y in zip(data.traces, data.labels))
    True
    """
    validate_params(
        {"scenario": scenario, "n_demos": n_demos, "n_negative": n_negative,
         "n_threats": n_threats, "threat_radius": threat_radius, "poi_radius": poi_radius,
         "speed": speed, "max_turn_rate": max_turn_rate, "max_tries": max_tries,
         "random_state": random_state},
        _DEMOS_CONSTRAINTS, "make_poi_threat_demos",
    )
    n_demos, n_negative, n_threats = int(n_demos), int(n_negative), int(n_threats)
    max_tries = int(max_tries)
    threat_radius, poi_radius = float(threat_radius), float(poi_radius)
    speed, max_turn_rate = float(speed), float(max_turn_rate)
    if n_demos + n_negative < 1:
        raise ValueError("n_demos + n_negative must be at least 1")
    if speed >= poi_radius:
        raise ValueError(f"speed ({speed}) must be smaller than poi_radius ({poi_radius})")
    if max_turn_rate > np.pi / 2:
        raise ValueError(f"max_turn_rate must be at most pi/2, got {max_turn_rate}")
    if speed / max_turn_rate >= 0.3:
        raise ValueError(
            f"the turning radius speed / max_turn_rate = {speed / max_turn_rate:.3f} must be "
            "below 0.3; raise max_turn_rate or lower speed"
        )
    start = _as_points([start], "start")[0]
    world = 10.0
    if not (0 <= start[0] <= world and 0 <= start[1] <= world):
        raise ValueError(f"start must lie in [0, {world}]^2, got {start.tolist()}")
    kinds = check_kinds(negative_kinds, n_negative, NEGATIVE_KINDS)

    if isinstance(scenario, Specification):
        if poi_positions is None:
            poi_positions = POI_LAYOUTS[5]
        pois = _as_points(poi_positions, "poi_positions")
        spec = _custom_specification(scenario, n_threats, len(pois))
    else:
        spec = poi_threat_specification(scenario, n_threats)
        scenario = int(scenario)
        n_pois = _SCENARIO_N_POIS[scenario]
        if poi_positions is None:
            poi_positions = POI_LAYOUTS[n_pois]
        pois = _as_points(poi_positions, "poi_positions")
        if len(pois) != n_pois:
            raise ValueError(
                f"poi_positions must have {n_pois} rows for scenario {scenario}, "
                f"got {len(pois)}"
            )
    if np.any(pois < 0) or np.any(pois > world):
        raise ValueError(f"poi_positions must lie in [0, {world}]^2")

    taus, omegas, pis = _names(n_threats, len(pois))
    sim = Navigator(
        pois=pois,
        n_threats=n_threats,
        threat_radius=threat_radius,
        poi_radius=poi_radius,
        speed=speed,
        max_turn_rate=max_turn_rate,
        start=start,
        world=world,
    )
    rng = check_random_state(random_state)
    spec_idx = _spec_indices(spec)
    out = Bunch(traces=[], trajectories=[], threat_positions=[], accessible=[],
                visit_orders=[], violations=[])
    for i in range(n_demos + n_negative):
        negative = i >= n_demos
        for _ in range(max_tries):
            demo = sim.demonstration(spec_idx, rng, kinds if negative else None)
            if demo is None:
                continue
            traj, threats, visits, kind = demo
            trace = poi_threat_labels(
                traj, threats, pois, threat_radius=threat_radius, poi_radius=poi_radius
            )
            if spec.satisfied_by(trace) != negative:
                break
        else:
            raise RuntimeError(
                f"no valid {'negative' if negative else 'positive'} demonstration in "
                f"{max_tries} draws (demonstration {i}); check the layout parameters"
            )
        out.traces.append(trace)
        out.trajectories.append(traj)
        out.threat_positions.append(threats)
        out.accessible.append(trace.iloc[0][pis].to_numpy(dtype=bool))
        out.visit_orders.append([v + 1 for v in visits])
        out.violations.append(kind if negative else "")
    out.labels = np.array([1] * n_demos + [0] * n_negative)
    out.feature_names = taus + omegas + pis
    out.roles = {
        "global_candidates": list(taus),
        "subtasks": list(omegas),
        "conditions": dict(zip(omegas, pis, strict=True)),
    }
    out.specification = spec
    out.poi_positions = pois
    out.threat_radius = threat_radius
    out.poi_radius = poi_radius
    out.start = start
    out.world_size = world
    out.scenario = scenario
    out.DESCR = (
        f"Synthetic POI/threat navigation domain: {n_threats} threats (redrawn per "
        f"demonstration), {len(pois)} fixed POIs; {n_demos} positive and {n_negative} "
        f"negative demonstrations.\nGround truth: {spec.to_ltl()}"
    )
    return out


def _custom_specification(spec, n_threats, n_pois):
    taus, omegas, pis = _names(n_threats, n_pois)
    for g in spec.globals:
        if g not in taus:
            raise ValueError(
                f"scenario global {g!r} is not a threat proposition (tau_1..tau_{n_threats})"
            )
    for w in spec.eventuals | {x for pair in spec.orders for x in pair}:
        if w not in omegas:
            raise ValueError(
                f"scenario subtask {w!r} is not a POI proposition (omega_1..omega_{n_pois}); "
                "pass poi_positions for more POIs"
            )
    return Specification(
        globals=spec.globals,
        eventuals=spec.eventuals,
        orders=spec.orders,
        conditions=dict(zip(omegas, pis, strict=True)),
    )


def _spec_indices(spec):
    """Zero-based threat / POI indices of the specification's clauses."""

    def idx(name):
        return int(re.fullmatch(r"(?:tau|omega)_(\d+)", name).group(1)) - 1

    return (
        sorted(idx(g) for g in spec.globals),
        sorted(idx(w) for w in spec.eventuals),
        sorted((idx(a), idx(b)) for a, b in spec.orders),
    )


def _as_points(value, name, allow_empty=False, extra_columns=False):
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a numeric array of 2-D points") from None
    if arr.ndim != 2 or arr.shape[1] < 2 or (arr.shape[1] > 2 and not extra_columns):
        raise ValueError(f"{name} must have shape (n, 2), got {arr.shape}")
    if not allow_empty and len(arr) == 0:
        raise ValueError(f"{name} is empty")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} has non-finite values")
    return arr
