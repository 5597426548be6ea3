"""The POI / threat domain's agent: threat layouts, visit plans, grid planning, Dubins car."""

import heapq

import numpy as np
from numba import njit

from bsi_sklearn._compile_progress import install_notice

__all__ = ["Navigator"]

install_notice()  # one line when its kernels compile for more than a second

_RESOLUTION = 0.1  # planning grid cell size
_CLEARANCE = 0.35  # planning margin around threat zones (above the turning radius)
_GOAL_FRACTION = 0.6  # a POI counts as reached within this fraction of its tolerance
_GOAL_MARGIN = 0.1  # goal cells keep at least this distance from every threat zone
_POI_CLEARANCE = 0.2  # margin around POIs that must not be visited yet


class Navigator:
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
