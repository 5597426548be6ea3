"""Simulated dinner-table demonstrations: placement plans, wrist keyframes and piece poses."""

import numpy as np

from bsi_sklearn.datasets._dinner_scene import (
    _GRASP_HEIGHT,
    _HANDS,
    _MOCAP_NOISE,
    _P,
    _REST,
    _SIDE_SLOTS,
    _THICKNESS,
    CENTERPIECE_XY,
    MEALS,
    PARTICIPANTS,
    PIECES,
    STACK,
    TABLE_HEIGHT,
)
from bsi_sklearn.datasets.tsr import make_pose, matrix_to_rpy

__all__ = ["simulate_demonstration"]


def _plan(participant, meal, rng):
    """Order in which the participant places the needed pieces (plates stacked correctly)."""
    habit = PARTICIPANTS[participant]
    if habit["priority"] is None:
        order = list(PIECES)
        rng.shuffle(order)
    else:
        order = list(habit["priority"])
        for k in range(len(order) - 1):
            if rng.random_sample() < habit["swap_prob"]:
                order[k], order[k + 1] = order[k + 1], order[k]
    order = [p for p in order if p in MEALS[meal]]
    slots = [k for k, p in enumerate(order) if p in STACK]
    stacked = [p for p in STACK if p in order]
    for k, p in zip(slots, stacked, strict=True):
        order[k] = p
    return order


def _steps(order, habit):
    """Group the plan into steps ``{hand: piece}``; bimanual people carry fork and knife."""
    dominant = habit["hand"]
    other = "left" if dominant == "right" else "right"
    pair = ("fork", "knife")
    steps = []
    for p in order:
        if habit["bimanual"] and p in pair and all(q in order for q in pair):
            if p == next(q for q in order if q in pair):  # the first of the two
                steps.append({"left": "fork", "right": "knife"})
            continue
        hand = other if (p == "fork" and habit["bimanual"]) else dominant
        steps.append({hand: p})
    return steps


class _Keyframes:
    """Per-hand keyframes ``(time, xyz, rpy)`` with minimum-jerk segments between them."""

    def __init__(self):
        self.frames = {h: [(0.0, np.array(_REST[h]), np.array([0.0, 0.2, np.pi / 2]))]
                       for h in _HANDS}

    def now(self, hand):
        return self.frames[hand][-1][0]

    def add(self, hand, xyz, rpy, speed, rng, dwell=0.0):
        t, p0, a0 = self.frames[hand][-1]
        xyz = np.asarray(xyz, float)
        rpy = np.asarray(rpy, float).copy()
        # unwrap the angles so the interpolation turns the short way
        rpy = a0 + (rpy - a0 + np.pi) % (2 * np.pi) - np.pi
        dist = np.linalg.norm(xyz - p0) + 0.05 * np.abs(rpy - a0).sum()
        dur = 0.15 + dist / speed * rng.uniform(0.85, 1.15)
        self.frames[hand].append((t + dur, xyz, rpy))
        if dwell > 0:
            self.frames[hand].append((t + dur + dwell, xyz, rpy))
        return t + dur

    def wait_until(self, hand, t):
        t0, p, a = self.frames[hand][-1]
        if t > t0:
            self.frames[hand].append((t, p, a))

    def sample(self, hand, times):
        ts = np.array([f[0] for f in self.frames[hand]])
        ps = np.array([f[1] for f in self.frames[hand]])
        angs = np.array([f[2] for f in self.frames[hand]])
        idx = np.clip(np.searchsorted(ts, times, side="right") - 1, 0, len(ts) - 1)
        nxt = np.minimum(idx + 1, len(ts) - 1)
        span = ts[nxt] - ts[idx]
        tau = np.where(span > 0, (times - ts[idx]) / np.where(span > 0, span, 1.0), 0.0)
        tau = np.clip(tau, 0.0, 1.0)
        s = (10 * tau**3 - 15 * tau**4 + 6 * tau**5)[:, None]
        pos = ps[idx] + s * (ps[nxt] - ps[idx])
        rpy = angs[idx] + s * (angs[nxt] - angs[idx])
        return make_pose(pos, rpy)


def _final_pose(piece, tsrs, precision, rng, stack_height):
    """Draw a placement inside the piece's region, using ``precision`` of each tolerance."""
    B = tsrs[piece].Bw
    mid = B.mean(axis=1)
    half = (B[:, 1] - B[:, 0]) / 2 * precision
    d = mid + half * rng.uniform(-1.0, 1.0, size=6)
    if B[5, 1] - B[5, 0] >= 2 * np.pi:
        d[5] = rng.uniform(-np.pi, np.pi)
    d[2] = stack_height + rng.uniform(0.0, 0.002)
    # pieces lie flat on the table (or on the plate below): barely any roll or pitch
    d[3:5] = np.clip(rng.normal(0.0, 0.01, size=2), -half[3:5], half[3:5])
    return tsrs[piece].T0_w @ make_pose(d[:3], d[3:])


def _misplaced_pose(piece, tsrs, rng, stack_height):
    """Draw a placement outside the piece's region: shifted, or turned the wrong way."""
    B = tsrs[piece].Bw
    d = np.zeros(6)
    d[2] = stack_height
    if B[5, 1] - B[5, 0] < 2 * np.pi and rng.random_sample() < 0.5:
        d[5] = rng.choice([-1.0, 1.0]) * rng.uniform(np.pi / 2, np.pi)
    else:
        angle = rng.uniform(0, 2 * np.pi)
        reach = max(B[0, 1], B[1, 1]) + rng.uniform(0.04, 0.1)
        d[0], d[1] = reach * np.cos(angle), reach * np.sin(angle)
        if B[5, 1] - B[5, 0] >= 2 * np.pi:
            d[5] = rng.uniform(-np.pi, np.pi)
    return tsrs[piece].T0_w @ make_pose(d[:3], d[3:])


def simulate_demonstration(participant, meal, rng, tsrs, kinds, dt):
    """One simulated demonstration, or None when this draw cannot give the requested kind.

    Parameters
    ----------
    participant : int
        Index into :data:`PARTICIPANTS`.
    meal : str
        Key of :data:`MEALS`.
    rng : numpy.random.RandomState
        Source of every random draw.
    tsrs : dict
        The task-space regions (:func:`bsi_sklearn.datasets.dinner_table_tsrs`).
    kinds : tuple of str or None
        Negative kinds to choose among; None for a positive demonstration.
    dt : float
        Sampling period (s).

    Returns
    -------
    demo : tuple or None
        ``(object_poses, wrist_poses, times, placed, kind)``.
    """
    habit = PARTICIPANTS[participant]
    order = _plan(participant, meal, rng)
    kind = None
    misplaced = None
    via_step = None
    if kinds is not None:
        needed_stack = [p for p in order if p in STACK]
        feasible = [k for k in kinds
                    if k in ("centerpiece", "skip", "misplace")
                    or (k == "order" and len(needed_stack) >= 2)]
        if not feasible:
            return None
        kind = feasible[rng.randint(len(feasible))]
        if kind == "skip":
            order.remove(order[rng.randint(len(order))])
        elif kind == "misplace":
            misplaced = order[rng.randint(len(order))]
        elif kind == "order":
            a, b = rng.choice(len(needed_stack), size=2, replace=False)
            ia, ib = order.index(needed_stack[a]), order.index(needed_stack[b])
            order[ia], order[ib] = order[ib], order[ia]
    steps = _steps(order, habit)
    if kind == "centerpiece":
        via_step = rng.randint(len(steps)) if steps else None
        if via_step is None:
            return None

    speed = habit["speed"] * rng.uniform(0.9, 1.1)
    frames = _Keyframes()
    initial = np.empty((len(PIECES), 4, 4))
    for p, k in _P.items():
        x, y, yaw = _SIDE_SLOTS[p]
        initial[k] = make_pose(
            [x + rng.uniform(-0.01, 0.01), y + rng.uniform(-0.01, 0.01), TABLE_HEIGHT],
            [0.0, 0.0, yaw + rng.uniform(-0.15, 0.15)],
        )
    final = initial.copy()
    grasp = {}
    release = {}
    hand_of = {}
    up = np.array([0.0, 0.0, 1.0])
    wrist_offset = make_pose([0.0, 0.0, _GRASP_HEIGHT])
    stacked = set()
    t = 0.3 + rng.uniform(0.0, 0.5)  # reaction time
    for s, step in enumerate(steps):
        ends = []
        for j, hand in enumerate(_HANDS):
            if hand not in step:
                continue
            p = step[hand]
            frames.wait_until(hand, t + 0.15 * j * rng.random_sample())
            # a plate or bowl rests on those placed before it that belong below it
            height = sum(_THICKNESS[q] for q in STACK[: STACK.index(p)] if q in stacked) \
                if p in STACK else 0.0
            if p == misplaced:
                final[_P[p]] = _misplaced_pose(p, tsrs, rng, height)
            else:
                final[_P[p]] = _final_pose(p, tsrs, habit["precision"], rng, height)
            stacked.add(p)
            pick = initial[_P[p]] @ wrist_offset
            place = final[_P[p]] @ wrist_offset
            pick_xyz, pick_rpy = pick[:3, 3], matrix_to_rpy(pick[:3, :3])
            place_xyz, place_rpy = place[:3, 3], matrix_to_rpy(place[:3, :3])
            frames.add(hand, pick_xyz + 0.10 * up, pick_rpy, speed, rng)
            grasp[p] = frames.add(hand, pick_xyz, pick_rpy, speed, rng,
                                  dwell=rng.uniform(0.1, 0.4))
            lift = pick_xyz + rng.uniform(0.12, 0.2) * up
            frames.add(hand, lift, pick_rpy, speed, rng)
            if via_step == s and hand == next(iter(step)):
                # reaching across the table: the wrist passes over the centerpiece
                cx, cy = CENTERPIECE_XY
                via = [cx + rng.uniform(-0.06, 0.06), cy + rng.uniform(-0.06, 0.06),
                       TABLE_HEIGHT + rng.uniform(0.12, 0.28)]
                frames.add(hand, via, place_rpy, speed, rng)
            frames.add(hand, place_xyz + rng.uniform(0.1, 0.14) * up, place_rpy, speed, rng)
            release[p] = frames.add(hand, place_xyz, place_rpy, 0.6 * speed, rng,
                                    dwell=rng.uniform(0.05, 0.3))
            frames.add(hand, place_xyz + 0.12 * up, place_rpy, speed, rng)
            ends.append(frames.add(hand, _REST[hand], [0.0, 0.2, np.pi / 2], speed, rng))
            hand_of[p] = hand
        t = max(ends) + rng.uniform(0.0, 0.4)
    t_end = t + 0.5
    times = np.arange(0.0, t_end + 1e-9, dt)
    wrists = np.stack([frames.sample(h, times) for h in _HANDS], axis=1)
    objects = np.broadcast_to(initial, (len(times),) + initial.shape).copy()
    wrist_to_object = np.linalg.inv(wrist_offset)
    for p, hand in hand_of.items():
        k = _P[p]
        carried = (times >= grasp[p]) & (times < release[p])
        h = _HANDS.index(hand)
        objects[carried, k] = wrists[carried, h] @ wrist_to_object
        objects[times >= release[p], k] = final[k]
    # tracking noise on positions
    wrists[..., :3, 3] += rng.normal(0.0, _MOCAP_NOISE, size=wrists.shape[:-2] + (3,))
    objects[..., :3, 3] += rng.normal(0.0, _MOCAP_NOISE, size=objects.shape[:-2] + (3,))
    placed = sorted(release, key=release.get)
    placed = [p for p in placed if p != misplaced]
    return objects, wrists, times, placed, kind
