"""Set-up of one scenario: forces, geometry, timeline and the initial state of every aircraft.

Every random draw of the set-up happens here, in a fixed order (the order is part of the
missions: changing it changes every mission).
"""

from __future__ import annotations

import numpy as np

from lfe.draws import Draws
from lfe.simulator._geometry import norm
from lfe.simulator.config import (
    AIRBASE_DEPTH,
    AIRBASE_JITTER,
    AIRBASE_SPREAD_Y,
    ALTITUDE,
    ALTITUDE_JITTER,
    CAP_DEPTH,
    CAP_JITTER,
    CAP_SPREAD_Y,
    ESC,
    ESCORT_PUSH_JITTER,
    FRIENDLY_HEADING,
    FTR,
    HEADING_JITTER,
    HOSTILE_HEADING,
    IP_DISTANCE,
    LANE_HALF_WIDTH,
    LANE_JITTER,
    MARSHAL_X,
    PH,
    RELEASE_AIM,
    RELEASE_RANGE,
    ROLE_NAMES,
    SAM_DEPTH,
    SAM_DETECT_MARGIN,
    SAM_RANGE,
    SAM_SPREAD_Y,
    SCRAMBLE_DELAY,
    SEAD,
    SEAD_PUSH_JITTER,
    SPEED,
    STATION_DEPTH,
    STATION_JITTER,
    STATION_LANE_FACTOR,
    STK,
    STRIKER_MARSHAL,
    STRIKER_PUSH_JITTER,
    TARGET_SPREAD_Y,
)

__all__ = ["World"]


def _lanes(n, half_width):
    """``n`` lanes spread evenly over ``[-half_width, half_width]`` (one lane: 0).

    ``start + k * step``, the last lane exactly ``half_width`` (what ``numpy.linspace``
    computes, written out so that it cannot change with numpy's version).
    """
    if n == 1:
        return np.zeros(1)
    step = (half_width - -half_width) / (n - 1)
    lanes = np.arange(n) * step + -half_width
    lanes[-1] = half_width
    return lanes


class World:
    """The state of one scenario after its set-up (arrays over aircraft, SAM sites)."""

    def __init__(self, config, seed, scenario_id):
        self.c = c = config
        self.seed = seed
        self.scenario_id = scenario_id
        self.rng = Draws(np.random.RandomState(seed))
        self.dt = float(c.dt)
        self.tot_start = float(c.tot_start)
        self.tot_end = float(c.tot_start + c.tot_window)
        self._forces()
        self._positions()
        self._sam_sites()
        self._timeline()
        self._initial_state()

    def _forces(self):
        c = self.c
        self.target = np.array([c.target_distance,
                                self.rng.uniform(-TARGET_SPREAD_Y, TARGET_SPREAD_Y)])
        roles = ([ESC] * c.n_escorts + [SEAD] * c.n_sead + [STK] * c.n_strikers
                 + [FTR] * c.n_hostile)
        self.role = np.array(roles, dtype=np.int64)
        self.n = len(roles)
        self.friendly = self.role != FTR
        names, counters = [], dict.fromkeys(range(4), 0)
        for r in roles:
            counters[r] += 1
            names.append(f"{ROLE_NAMES[r]}_{counters[r]:02d}")
        self.names = names

    def _positions(self):
        """Marshal areas and lanes, hostile patrols and airbase, friendly stations."""
        c, rng, n = self.c, self.rng, self.n
        tx, ty = self.target
        home = np.zeros((n, 2))
        self.lane = np.zeros(n)
        for r in (ESC, SEAD, STK):
            idx = np.flatnonzero(self.role == r)
            if len(idx):
                lanes = _lanes(len(idx), LANE_HALF_WIDTH[r])
                home[idx, 0] = rng.uniform(*MARSHAL_X[r], size=len(idx))
                home[idx, 1] = lanes + rng.normal(0.0, LANE_JITTER, size=len(idx))
                self.lane[idx] = lanes
        hostile = np.flatnonzero(self.role == FTR)
        self.cap = np.zeros((n, 2))
        self.cap[hostile, 0] = tx - rng.uniform(*CAP_DEPTH, size=len(hostile))
        self.cap[hostile, 1] = ty + rng.uniform(-CAP_SPREAD_Y, CAP_SPREAD_Y, size=len(hostile))
        home[hostile] = self.cap[hostile] + rng.normal(0.0, CAP_JITTER, size=(len(hostile), 2))
        self.airbase = np.array([tx + AIRBASE_DEPTH,
                                 ty + rng.uniform(-AIRBASE_SPREAD_Y, AIRBASE_SPREAD_Y)])
        n_alert = int(round(c.hostile_alert_fraction * len(hostile)))
        self.scramble = np.zeros(n)  # time each fighter is airborne (inf: not yet ordered)
        self.alert_delay = np.zeros(n)
        if n_alert:
            alert = hostile[-n_alert:]
            home[alert] = self.airbase + rng.normal(0.0, AIRBASE_JITTER, size=(n_alert, 2))
            self.scramble[alert] = np.inf
            self.alert_delay[alert] = rng.uniform(*SCRAMBLE_DELAY, size=n_alert)
        self.home = home
        # Where each friendly pushes to: escorts sweep ahead of the target, SEAD hold off.
        self.station = np.zeros((n, 2))
        for r in (ESC, SEAD):
            idx = np.flatnonzero(self.role == r)
            self.station[idx, 0] = (tx - STATION_DEPTH[r]
                                    + rng.uniform(-STATION_JITTER, STATION_JITTER, size=len(idx)))
            self.station[idx, 1] = ty + STATION_LANE_FACTOR * self.lane[idx]
        self.ip = np.array([tx - IP_DISTANCE, ty])

    def _sam_sites(self):
        c, rng = self.c, self.rng
        tx, ty = self.target
        ns = c.n_sams
        if ns:
            x = tx - rng.uniform(*SAM_DEPTH, size=ns)
            y = ty + rng.uniform(-SAM_SPREAD_Y, SAM_SPREAD_Y, size=ns)
            self.sam_xy = np.column_stack([x, y])
        else:
            self.sam_xy = np.zeros((0, 2))
        self.sam_range = rng.uniform(*SAM_RANGE, size=ns)
        self.sam_detect = self.sam_range + rng.uniform(*SAM_DETECT_MARGIN, size=ns)
        self.sam_alive = np.ones(ns, dtype=bool)
        self.sam_missiles = np.full(ns, c.sam_missiles, dtype=np.int64)
        self.sam_ready = np.zeros(ns)
        self.sam_emitting = np.zeros(ns, dtype=bool)
        self.sam_names = [f"sam_{k + 1}" for k in range(ns)]

    def _timeline(self):
        c, rng = self.c, self.rng
        self.escort_push = c.escort_push_time + rng.uniform(-ESCORT_PUSH_JITTER,
                                                            ESCORT_PUSH_JITTER)
        self.sead_push = (self.escort_push + c.sead_push_delay
                          + rng.uniform(-SEAD_PUSH_JITTER, SEAD_PUSH_JITTER))
        # Strikers aim to release RELEASE_AIM s after the window opens: they push so as to
        # reach the initial point then, and hold there when early.
        self.run_in_time = (IP_DISTANCE - RELEASE_RANGE) / (SPEED["on_target"] / 1000.0)
        release_aim = self.tot_start + RELEASE_AIM
        transit = norm(*(self.ip - np.array(STRIKER_MARSHAL))) / (SPEED["push"] / 1000.0)
        self.striker_push_planned = max(0.0, release_aim - self.run_in_time - transit)
        self.striker_push = max(0.0, self.striker_push_planned + c.striker_push_offset
                                + rng.normal(0.0, STRIKER_PUSH_JITTER))
        self.run_in_start = release_aim - self.run_in_time

    def _initial_state(self):
        c, rng, n = self.c, self.rng, self.n
        roles = self.role.tolist()
        self.pos = self.home.copy()
        self.heading = (np.where(self.friendly, FRIENDLY_HEADING, HOSTILE_HEADING)
                        + rng.uniform(-HEADING_JITTER, HEADING_JITTER, size=n))
        self.speed = np.zeros(n)
        self.alt = (np.array([ALTITUDE[r] for r in roles])
                    + rng.uniform(-ALTITUDE_JITTER, ALTITUDE_JITTER, size=n))
        self.alt_pref = self.alt.copy()
        self.phase = np.where(self.friendly, PH["marshal"], PH["cap"]).astype(np.int64)
        self.alive = np.ones(n, dtype=bool)
        loads = {ESC: c.escort_missiles, SEAD: c.sead_harms, STK: c.bombs_per_striker,
                 FTR: c.hostile_missiles}
        self.ammo = np.array([loads[r] for r in roles], dtype=np.int64)
        self.ready = np.zeros(n)
        self.inbound = np.zeros(n, dtype=np.int64)  # weapons in flight at each aircraft
        self.inbound_sites = np.zeros(c.n_sams, dtype=np.int64)
        self.reached = np.zeros(n, dtype=bool)  # station / initial point reached
        self.aborted = False
        self.withdrawing = np.zeros(n, dtype=bool)
        self.hostile_withdraw = False
        self.n_hostile_lost = 0
        self.in_flight = []  # [impact, shot_index]
        self.shots = []  # rows of the weapons table
        self.pairs = set()  # (shooter, target) with a weapon in flight
        self.screen = None  # where escorts screen the strikers (set each step)
        self.gci_seen = np.zeros(n, dtype=bool)  # strikers hostile ground radar sees
