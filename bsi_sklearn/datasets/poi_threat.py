"""Synthetic 2-D navigation domain: points of interest to visit and threats to avoid."""

from __future__ import annotations

import heapq
import numbers
import re

import numpy as np
import pandas as pd
from numba import njit
from sklearn.utils import Bunch, check_random_state

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

_RESOLUTION = 0.1  # planning grid cell size
_CLEARANCE = 0.35  # planning margin around threat zones (above the turning radius)
_GOAL_FRACTION = 0.6  # a POI counts as reached within this fraction of its tolerance
_GOAL_MARGIN = 0.1  # goal cells keep at least this distance from every threat zone
_POI_CLEARANCE = 0.2  # margin around POIs that must not be visited yet


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
    if (isinstance(scenario, bool) or not isinstance(scenario, numbers.Integral)
            or scenario not in _SCENARIO_ORDERS):
        raise ValueError(f"scenario must be 1, 2, 3 or a Specification, got {scenario!r}")
    n_threats = _check_int(n_threats, "n_threats", 1)
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
    threat_radius = _check_positive(threat_radius, "threat_radius")
    poi_radius = _check_positive(poi_radius, "poi_radius")
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
    n_demos = _check_int(n_demos, "n_demos", 0)
    n_negative = _check_int(n_negative, "n_negative", 0)
    if n_demos + n_negative < 1:
        raise ValueError("n_demos + n_negative must be at least 1")
    n_threats = _check_int(n_threats, "n_threats", 1)
    max_tries = _check_int(max_tries, "max_tries", 1)
    threat_radius = _check_positive(threat_radius, "threat_radius")
    poi_radius = _check_positive(poi_radius, "poi_radius")
    speed = _check_positive(speed, "speed")
    max_turn_rate = _check_positive(max_turn_rate, "max_turn_rate")
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
    kinds = _check_kinds(negative_kinds, n_negative)

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
    sim = _Simulator(
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


class _Simulator:
    """Threat layouts, visit plans, grid planning and the Dubins car."""

    def __init__(self, *, pois, n_threats, threat_radius, poi_radius, speed, max_turn_rate,
                 start, world):
        self.pois = pois
        self.n_threats = n_threats
        self.r_t = threat_radius
        self.r_p = poi_radius
        self.speed = speed
        self.max_turn = max_turn_rate
        self.start = start
        self.world = world
        n = int(round(world / _RESOLUTION)) + 1
        g = np.arange(n) * _RESOLUTION
        self.gx, self.gy = np.meshgrid(g, g, indexing="ij")
        # cells to keep out of while a POI must not be entered yet
        self.poi_block = [
            (self.gx - p[0]) ** 2 + (self.gy - p[1]) ** 2 <= (poi_radius + _POI_CLEARANCE) ** 2
            for p in pois
        ]
        self.poi_goal = [
            (self.gx - p[0]) ** 2 + (self.gy - p[1]) ** 2 <= (_GOAL_FRACTION * poi_radius) ** 2
            for p in pois
        ]
        self.max_leg_steps = int(8 * world / speed)

    def draw_threats(self, rng):
        min_d = self.r_t + _CLEARANCE + self.speed
        while True:
            threats = rng.uniform(0.0, self.world, size=(self.n_threats, 2))
            if np.all(np.linalg.norm(threats - self.start, axis=1) > min_d):
                return threats

    def demonstration(self, spec_idx, rng, kinds):
        """One trajectory, or None when this draw cannot produce the requested kind."""
        globals_, eventuals, orders = spec_idx
        threats = self.draw_threats(rng)
        d = np.linalg.norm(self.pois[:, None, :] - threats[None, :, :], axis=-1)
        accessible = ~np.any(d <= self.r_t, axis=1)
        required = set(eventuals) | {a for a, _ in orders}
        visit_set = sorted(w for w in required if accessible[w])
        order_pairs = [(a, b) for a, b in orders if a in visit_set and b in visit_set]
        ignored_threat = None
        waypoint_at = None
        kind = None
        if kinds is None:
            visits = _linear_extension(visit_set, order_pairs, rng)
        else:
            feasible = []
            if "threat" in kinds and globals_:
                feasible.append("threat")
            if "skip" in kinds and visit_set:
                feasible.append("skip")
            if "order" in kinds and order_pairs:
                feasible.append("order")
            if not feasible:
                return None
            kind = feasible[rng.randint(len(feasible))]
            visits = _linear_extension(visit_set, order_pairs, rng)
            if kind == "threat":
                ignored_threat = globals_[rng.randint(len(globals_))]
                waypoint_at = rng.randint(len(visits) + 1)
            elif kind == "skip":
                skipped = visit_set[rng.randint(len(visit_set))]
                visits = [v for v in visits if v != skipped]
            else:
                a, b = order_pairs[rng.randint(len(order_pairs))]
                visits.remove(b)
                visits.insert(rng.randint(visits.index(a) + 1), b)

        active = [j for j in range(self.n_threats) if j != ignored_threat]
        threat_free = np.ones(self.gx.shape, dtype=bool)
        goal_safe = np.ones(self.gx.shape, dtype=bool)
        for j in active:
            d2 = (self.gx - threats[j, 0]) ** 2 + (self.gy - threats[j, 1]) ** 2
            threat_free &= d2 > (self.r_t + _CLEARANCE) ** 2
            goal_safe &= d2 >= (self.r_t + _GOAL_MARGIN) ** 2

        legs = [("poi", v) for v in visits]
        if ignored_threat is not None:
            legs.insert(waypoint_at, ("threat", ignored_threat))
        x, y = self.start
        heading = np.pi / 2 + rng.uniform(-0.5, 0.5)
        pieces = [np.array([[x, y, heading]])]
        visited = set()
        for leg_kind, target in legs:
            if leg_kind == "poi":
                goal_xy = self.pois[target]
                goal = self.poi_goal[target] & goal_safe
                goal_r = _GOAL_FRACTION * self.r_p
            else:
                goal_xy = threats[target]
                goal = (
                    (self.gx - goal_xy[0]) ** 2 + (self.gy - goal_xy[1]) ** 2
                    <= (0.5 * self.r_t) ** 2
                ) & threat_free
                goal_r = 0.5 * self.r_t
            free = threat_free.copy()
            for w in range(len(self.pois)):
                if w not in visited and not (leg_kind == "poi" and w == target):
                    free &= ~self.poi_block[w]
            goal &= free
            if not goal.any():
                return None
            dist = _distance_field(free, goal)
            buf = np.empty((self.max_leg_steps, 3))
            n, x, y, heading = _drive(
                x, y, heading, dist, goal_xy[0], goal_xy[1], goal_r, _RESOLUTION,
                self.speed, self.max_turn, 6, buf,
            )
            if n < 0:
                return None
            pieces.append(buf[:n].copy())
            if leg_kind == "poi":
                visited.add(target)
        traj = np.concatenate(pieces)
        return traj, threats, visits, kind


def _linear_extension(items, pairs, rng):
    """Return a random topological order of ``items`` under the precedence ``pairs``."""
    remaining = list(items)
    preds = {v: {a for a, b in pairs if b == v} for v in items}
    out = []
    while remaining:
        ready = [v for v in remaining if not (preds[v] - set(out))]
        v = ready[rng.randint(len(ready))]
        out.append(v)
        remaining.remove(v)
    return out


_DI = np.array([1, -1, 0, 0, 1, 1, -1, -1])
_DJ = np.array([0, 0, 1, -1, 1, -1, 1, -1])
_W = np.array([1.0, 1.0, 1.0, 1.0, np.sqrt(2), np.sqrt(2), np.sqrt(2), np.sqrt(2)])


@njit(cache=True)
def _distance_field(free, goal):
    """Grid shortest-path length (in cells) to the goal cells, 8-connected, no corner cuts."""
    nx, ny = free.shape
    dist = np.full((nx, ny), np.inf)
    heap = [(0.0, 0, 0)]
    heap.pop()
    for i in range(nx):
        for j in range(ny):
            if goal[i, j] and free[i, j]:
                dist[i, j] = 0.0
                heap.append((0.0, i, j))
    heapq.heapify(heap)
    while len(heap) > 0:
        d, i, j = heapq.heappop(heap)
        if d > dist[i, j]:
            continue
        for k in range(8):
            ii = i + _DI[k]
            jj = j + _DJ[k]
            if ii < 0 or ii >= nx or jj < 0 or jj >= ny or not free[ii, jj]:
                continue
            if k >= 4 and not (free[ii, j] and free[i, jj]):
                continue
            nd = d + _W[k]
            if nd < dist[ii, jj]:
                dist[ii, jj] = nd
                heapq.heappush(heap, (nd, ii, jj))
    return dist


@njit(cache=True)
def _drive(x, y, heading, dist, gx, gy, goal_r, res, speed, max_turn, lookahead, out):
    """Drive the Dubins car down the distance field until it is within ``goal_r`` of the goal.

    Writes ``(x, y, heading)`` of every step into ``out`` and returns the number of steps and
    the final state; the step count is -1 when the goal is not reached in ``len(out)`` steps
    or the car is stranded far from every reachable cell.
    """
    nx, ny = dist.shape
    radius = speed / max_turn
    for step in range(out.shape[0]):
        if (x - gx) ** 2 + (y - gy) ** 2 <= goal_r * goal_r:
            return step, x, y, heading
        ci = min(max(int(round(x / res)), 0), nx - 1)
        cj = min(max(int(round(y / res)), 0), ny - 1)
        if not np.isfinite(dist[ci, cj]):
            best = np.inf
            bi, bj = -1, -1
            for di in range(-6, 7):
                for dj in range(-6, 7):
                    ii, jj = ci + di, cj + dj
                    if 0 <= ii < nx and 0 <= jj < ny and np.isfinite(dist[ii, jj]):
                        r2 = di * di + dj * dj
                        if r2 < best:
                            best, bi, bj = r2, ii, jj
            if bi < 0:
                return -1, x, y, heading
            ci, cj = bi, bj
        for _ in range(lookahead):
            if dist[ci, cj] == 0.0:
                break
            bi, bj, bd = ci, cj, dist[ci, cj]
            for k in range(8):
                ii = ci + _DI[k]
                jj = cj + _DJ[k]
                if 0 <= ii < nx and 0 <= jj < ny and dist[ii, jj] < bd:
                    bi, bj, bd = ii, jj, dist[ii, jj]
            if bi == ci and bj == cj:
                break
            ci, cj = bi, bj
        if dist[ci, cj] == 0.0:
            tx, ty = gx, gy
        else:
            tx, ty = ci * res, cj * res
        err = np.arctan2(ty - y, tx - x) - heading
        err = (err + np.pi) % (2.0 * np.pi) - np.pi
        # a target inside the turning circle cannot be reached by turning: go straight first
        side = 1.0 if err >= 0 else -1.0
        cx = x - side * radius * np.sin(heading)
        cy = y + side * radius * np.cos(heading)
        if (tx - cx) ** 2 + (ty - cy) ** 2 < radius * radius:
            u = 0.0
        else:
            u = min(max(err, -max_turn), max_turn)
        heading = heading + u
        x = x + speed * np.cos(heading)
        y = y + speed * np.sin(heading)
        out[step, 0] = x
        out[step, 1] = y
        out[step, 2] = heading
    return -1, x, y, heading


def _check_int(value, name, minimum):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def _check_positive(value, name):
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not (
        np.isfinite(value) and value > 0
    ):
        raise ValueError(f"{name} must be a positive number, got {value!r}")
    return float(value)


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


def _check_kinds(kinds, n_negative):
    if isinstance(kinds, str):
        kinds = (kinds,)
    try:
        kinds = tuple(kinds)
    except TypeError:
        raise ValueError(f"negative_kinds must be a sequence of kinds, got {kinds!r}") from None
    for k in kinds:
        if k not in NEGATIVE_KINDS:
            raise ValueError(f"negative_kinds has {k!r}; choose among {NEGATIVE_KINDS}")
    if n_negative and not kinds:
        raise ValueError("negative_kinds is empty but n_negative > 0")
    return kinds
