"""Tactics: what every aircraft and SAM site decides at each step.

Each role follows a scripted flight-phase machine and reacts to events (see
:func:`lfe.simulate_scenario`). A decision writes the aircraft's flight phase, its goal point
and its commanded speed (where to fly, how fast); firing goes through
:meth:`Weapons._fire`.
"""

from __future__ import annotations

import math

import numpy as np

from lfe.simulator._geometry import mean_position, norm, orbit_point
from lfe.simulator.config import (
    AAM_RANGE,
    BINGO,
    CAP_ORBIT_RADIUS,
    COOLDOWN,
    DETECT,
    EGRESS_LINE,
    ESC,
    EVADE_DISTANCE,
    FTR,
    GCI_RANGE,
    HARM_RANGE,
    HOME_RADIUS,
    HOSTILE_FLOOR_X,
    IP_REACHED,
    NO_THREAT_OFFSET,
    ORBIT_RADIUS,
    ORBIT_STEP,
    PH,
    PURSUIT_LIMIT_X,
    RELEASE_RANGE,
    SCREEN_AHEAD,
    SCREEN_CATCH_UP,
    SCREEN_LANE_FACTOR,
    SEAD,
    SEAD_APPROACH_MARGIN,
    SEAD_ORBIT_STEP,
    SEAD_STANDOFF,
    SPEED,
    STK,
    STRIKER_LATE,
    WITHDRAW_DEPTH,
)

__all__ = ["Tactics"]


class Tactics:
    """Decision methods of the simulation (a mixin over :class:`lfe.simulator._world.World`)."""

    def _away(self, i, threat_xy):
        d = self.pos[i] - threat_xy
        length = norm(*d) or 1.0
        return self.pos[i] + EVADE_DISTANCE * d / length

    def _orbit(self, i, center, radius=ORBIT_RADIUS, step_deg=ORBIT_STEP):
        return center + orbit_point(self.pos[i] - center, radius, step_deg)

    def _decide(self, t):
        c = self.c
        n = self.n
        pos = self.pos
        goal = pos.copy()
        want = np.zeros(n)
        friendly_alive = np.flatnonzero(self.friendly & self.alive)
        hostile_alive = np.flatnonzero(~self.friendly & self.alive)
        d_fh = norm(pos[friendly_alive, None, 0] - pos[None, hostile_alive, 0],
                        pos[friendly_alive, None, 1] - pos[None, hostile_alive, 1])
        row = {int(i): k for k, i in enumerate(friendly_alive)}
        col = {int(j): k for k, j in enumerate(hostile_alive)}
        sam_live = np.flatnonzero(self.sam_alive)
        d_sf = norm(self.sam_xy[sam_live, None, 0] - pos[None, friendly_alive, 0],
                        self.sam_xy[sam_live, None, 1] - pos[None, friendly_alive, 1])
        if len(sam_live) and len(friendly_alive):
            self.sam_emitting[sam_live] |= (d_sf <= self.sam_detect[sam_live, None]).any(axis=1)

        strikers = np.flatnonzero(self.role == STK)
        ph_s = self.phase[strikers]
        strikers_done = bool(np.all(
            ~self.alive[strikers] | (ph_s == PH["egress"]) | (ph_s == PH["rtb"])
        )) and t >= self.striker_push
        bingo = t > self.tot_end + BINGO

        if (c.n_hostile and not self.hostile_withdraw
                and self.n_hostile_lost >= math.ceil(c.hostile_withdraw_fraction * c.n_hostile)
                and self.n_hostile_lost > 0):
            self.hostile_withdraw = True  # the fighters airborne now break off
            self.withdrawing |= ~self.friendly & (self.scramble <= t)
        # Escorts screen 15 km ahead of the strikers between their push and their egress.
        ingress = strikers[self.alive[strikers] & (
            (ph_s == PH["push"]) | (ph_s == PH["on_target"]) | (ph_s == PH["defensive"]))]
        self.screen = None
        if len(ingress) and t >= self.striker_push:
            centre = mean_position(pos[ingress])
            ahead = self.target - centre
            dist = norm(*ahead)
            self.screen = centre + (SCREEN_AHEAD * ahead / dist if dist > 1e-9 else 0.0)
        # Ground-controlled interception: strikers near the target are seen by hostile radar.
        live_strikers = strikers[self.alive[strikers]]
        gci = norm(pos[live_strikers, 0] - self.target[0],
                       pos[live_strikers, 1] - self.target[1]) <= GCI_RANGE
        self.gci_seen = np.zeros(n, dtype=bool)
        self.gci_seen[live_strikers[gci]] = True
        if gci.any():
            waiting = np.isinf(self.scramble)
            self.scramble[waiting] = t + self.alert_delay[waiting]

        for i in range(n):
            if not self.alive[i]:
                continue
            r = self.role[i]
            if r == FTR:
                self._decide_fighter(t, i, goal, want, friendly_alive, d_fh[:, col[i]])
                continue
            if self.phase[i] in (PH["egress"], PH["rtb"]):
                self._go_home(i, goal, want)
                continue
            if r == ESC:
                self._decide_escort(t, i, goal, want, hostile_alive, d_fh[row[i]],
                                    strikers_done or bingo)
            elif r == SEAD:
                self._decide_sead(t, i, goal, want, sam_live, strikers_done or bingo)
            else:
                self._decide_striker(t, i, goal, want, hostile_alive, d_fh[row[i]])

        self._decide_sams(t, friendly_alive, sam_live, d_sf)
        return goal, want

    def _go_home(self, i, goal, want):
        if self.pos[i, 0] < EGRESS_LINE:
            self.phase[i] = PH["rtb"]
        d = norm(*(self.home[i] - self.pos[i]))
        if self.phase[i] == PH["rtb"] and d <= HOME_RADIUS:
            goal[i] = self.pos[i]
            want[i] = 0.0
            return
        goal[i] = self.home[i]
        want[i] = SPEED["egress"] if self.phase[i] == PH["egress"] else SPEED["rtb"]

    def _egress(self, i, goal, want):
        self.phase[i] = PH["egress"]
        self._go_home(i, goal, want)

    def _nearest_threat_xy(self, i, hostile_alive, d_row):
        candidates = [self.pos[j] for j in hostile_alive]
        distances = list(d_row)
        for k in np.flatnonzero(self.sam_alive):
            candidates.append(self.sam_xy[k])
            distances.append(norm(*(self.sam_xy[k] - self.pos[i])))
        if not candidates:
            return self.pos[i] + np.array(NO_THREAT_OFFSET)
        return candidates[int(np.argmin(distances))]

    def _decide_escort(self, t, i, goal, want, hostile_alive, d_row, done):
        c = self.c
        if t < self.escort_push:
            self.phase[i] = PH["marshal"]
            goal[i] = self._orbit(i, self.home[i])
            want[i] = SPEED["marshal"]
            return
        if done or self.ammo[i] == 0:
            self._egress(i, goal, want)
            return
        if self.inbound[i] > 0:
            self.phase[i] = PH["defensive"]
            goal[i] = self._away(i, self._nearest_threat_xy(i, hostile_alive, d_row))
            want[i] = SPEED["defensive"]
            return
        ok = ((d_row <= DETECT[ESC])
              & (self.pos[hostile_alive, 0] <= self.target[0] + PURSUIT_LIMIT_X)
              & (self.phase[hostile_alive] != PH["withdraw"])
              & (self.phase[hostile_alive] != PH["marshal"]))
        if ok.any():
            k = int(np.flatnonzero(ok)[np.argmin(d_row[ok])])
            j = int(hostile_alive[k])
            self.phase[i] = PH["engage"]
            goal[i] = self.pos[j]
            want[i] = SPEED["engage"]
            if (d_row[k] <= AAM_RANGE[ESC] and t >= self.ready[i]
                    and self.inbound[j] == 0):
                if self._fire(t, i, ("air", j), "aam", d_row[k], c.pk_escort):
                    self.ammo[i] -= 1
                    self.ready[i] = t + COOLDOWN["aam"]
            return
        if self.screen is not None:  # strikers on their way: screen ahead of them
            self.phase[i] = PH["push"]
            goal[i] = self.screen + np.array([0.0, SCREEN_LANE_FACTOR * self.lane[i]])
            far = norm(*(goal[i] - self.pos[i])) > SCREEN_CATCH_UP
            want[i] = SPEED["engage"] if far else SPEED["push"]
            return
        self._station(i, goal, want)

    def _station(self, i, goal, want):
        if not self.reached[i] and norm(*(self.station[i] - self.pos[i])) < 2 * ORBIT_RADIUS:
            self.reached[i] = True
        if self.reached[i]:
            self.phase[i] = PH["cap"]
            goal[i] = self._orbit(i, self.station[i])
            want[i] = SPEED["cap"]
        else:
            self.phase[i] = PH["push"]
            goal[i] = self.station[i]
            want[i] = SPEED["push"]

    def _decide_sead(self, t, i, goal, want, sam_live, done):
        c = self.c
        if t < self.sead_push:
            self.phase[i] = PH["marshal"]
            goal[i] = self._orbit(i, self.home[i])
            want[i] = SPEED["marshal"]
            return
        if done or (self.ammo[i] == 0 and t >= self.striker_push):
            self._egress(i, goal, want)
            return
        if self.inbound[i] > 0:
            self.phase[i] = PH["defensive"]
            goal[i] = self._away(i, self._nearest_threat_xy(
                i, np.zeros(0, dtype=np.int64), np.zeros(0)))
            want[i] = SPEED["defensive"]
            return
        live = sam_live[self.sam_emitting[sam_live]] if len(sam_live) else sam_live
        if len(live) and self.ammo[i] > 0:
            d = norm(self.sam_xy[live, 0] - self.pos[i, 0],
                         self.sam_xy[live, 1] - self.pos[i, 1])
            ok = d <= DETECT[SEAD]
            if ok.any():
                k = int(np.flatnonzero(ok)[np.argmin(d[ok])])
                s = int(live[k])
                self.phase[i] = PH["engage"]
                want[i] = SPEED["engage"]
                if d[k] > SEAD_STANDOFF + SEAD_APPROACH_MARGIN:
                    goal[i] = self.sam_xy[s]
                else:
                    goal[i] = self._orbit(i, self.sam_xy[s], radius=SEAD_STANDOFF,
                                          step_deg=SEAD_ORBIT_STEP)
                if (d[k] <= HARM_RANGE and t >= self.ready[i] and self.inbound_sites[s] == 0):
                    if self._fire(t, i, ("sam", s), "harm", d[k], c.pk_harm):
                        self.ammo[i] -= 1
                        self.ready[i] = t + COOLDOWN["harm"]
                return
        self._station(i, goal, want)

    def _decide_striker(self, t, i, goal, want, hostile_alive, d_row):
        c = self.c
        if self.aborted or self.ammo[i] == 0 or t > self.tot_end + STRIKER_LATE:
            self._egress(i, goal, want)
            return
        if t < self.striker_push:
            self.phase[i] = PH["marshal"]
            goal[i] = self._orbit(i, self.home[i])
            want[i] = SPEED["marshal"]
            return
        d_target = float(norm(*(self.target - self.pos[i])))
        if not self.reached[i] and norm(*(self.ip - self.pos[i])) < IP_REACHED:
            self.reached[i] = True
        if self.inbound[i] > 0:
            self.phase[i] = PH["defensive"]
            want[i] = SPEED["defensive"]
            if self.reached[i]:
                goal[i] = self.target  # press on, but no release while defensive
            else:
                goal[i] = self._away(i, self._nearest_threat_xy(i, hostile_alive, d_row))
            return
        if not self.reached[i]:
            self.phase[i] = PH["push"]
            goal[i] = self.ip
            want[i] = SPEED["push"]
            return
        if self.phase[i] != PH["on_target"] and t < self.run_in_start:
            self.phase[i] = PH["push"]  # early: hold at the initial point
            goal[i] = self._orbit(i, self.ip)
            want[i] = SPEED["cap"]
            return
        self.phase[i] = PH["on_target"]
        goal[i] = self.target
        want[i] = SPEED["on_target"]
        if d_target <= RELEASE_RANGE:
            while self.ammo[i] > 0 and self._fire(t, i, ("target", 0), "bomb", d_target,
                                                   c.pk_bomb):
                self.ammo[i] -= 1

    def _decide_fighter(self, t, i, goal, want, friendly_alive, d_col):
        c = self.c
        if t < self.scramble[i]:  # on ground alert at the airbase
            self.phase[i] = PH["marshal"]
            goal[i] = self.pos[i]
            want[i] = 0.0
            return
        if self.withdrawing[i] or self.ammo[i] == 0:
            self.phase[i] = PH["withdraw"]
            far = np.array([self.target[0] + WITHDRAW_DEPTH, self.cap[i, 1]])
            if norm(*(far - self.pos[i])) < 2 * ORBIT_RADIUS:
                goal[i] = self._orbit(i, far)
            else:
                goal[i] = far
            want[i] = SPEED["withdraw"]
            return
        if self.inbound[i] > 0 and len(friendly_alive):
            self.phase[i] = PH["defensive"]
            goal[i] = self._away(i, self.pos[friendly_alive[int(np.argmin(d_col))]])
            want[i] = SPEED["defensive"]
            return
        ok = (d_col <= DETECT[FTR]) | self.gci_seen[friendly_alive]
        ok &= self.pos[friendly_alive, 0] >= HOSTILE_FLOOR_X
        if ok.any():
            cand = np.flatnonzero(ok)
            strikers = cand[self.role[friendly_alive[cand]] == STK]
            if len(strikers):
                cand = strikers
            k = int(cand[np.argmin(d_col[cand])])
            j = int(friendly_alive[k])
            self.phase[i] = PH["engage"]
            goal[i] = self.pos[j]
            want[i] = SPEED["engage"]
            if (d_col[k] <= AAM_RANGE[FTR] and t >= self.ready[i]
                    and (i, ("air", j)) not in self.pairs):
                if self._fire(t, i, ("air", j), "aam", d_col[k], c.pk_hostile):
                    self.ammo[i] -= 1
                    self.ready[i] = t + COOLDOWN["aam"]
                    if (self.role[j] == STK and not self.reached[j] and not self.aborted
                            and self.rng.random_sample() < c.striker_abort_probability):
                        self.aborted = True
            return
        self.phase[i] = PH["cap"]
        goal[i] = self._orbit(i, self.cap[i], radius=CAP_ORBIT_RADIUS)
        want[i] = SPEED["cap"]

    def _decide_sams(self, t, friendly_alive, sam_live, d_sf):
        c = self.c
        for a, s in enumerate(sam_live):
            if self.sam_missiles[s] == 0 or t < self.sam_ready[s] or not len(friendly_alive):
                continue
            d = d_sf[a]
            ok = d <= self.sam_range[s]
            if not ok.any():
                continue
            order = np.flatnonzero(ok)[np.argsort(d[ok], kind="stable")]
            for k in order:
                j = int(friendly_alive[k])
                if (("site", s), ("air", j)) not in self.pairs:
                    if not self._fire(t, ("site", s), ("air", j), "sam", d[k], c.pk_sam):
                        return
                    self.sam_missiles[s] -= 1
                    self.sam_ready[s] = t + COOLDOWN["sam"]
                    break
