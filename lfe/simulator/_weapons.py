"""Weapons: releasing one (its flight time and bookkeeping) and resolving those that land."""

from __future__ import annotations

from lfe.simulator.config import (
    BOMB_FLIGHT_TIME,
    EVASION,
    IMPACT_TOLERANCE,
    PH,
    WEAPON_SPEED,
)

__all__ = ["Weapons"]


class Weapons:
    """Weapon methods of the simulation (a mixin over :class:`lfe.simulator._world.World`)."""

    def _fire(self, t, shooter, target, weapon, distance, pk):
        """Release one weapon; returns False (and fires nothing) after ``max_duration``."""
        if t >= self.c.max_duration:
            return False
        if weapon == "bomb":
            flight = BOMB_FLIGHT_TIME
        else:
            flight = distance / WEAPON_SPEED[weapon]
        impact = t + flight
        k = len(self.shots)
        self.shots.append([k, t, shooter, target, weapon, impact, None, pk])
        self.in_flight.append((impact, k))
        self.pairs.add((shooter, target))
        kind, idx = target
        if kind == "air":
            self.inbound[idx] += 1
        elif kind == "sam":
            self.inbound_sites[idx] += 1
        return True

    def _resolve(self, t):
        """Land every weapon due by ``t``, in order of impact; one draw per live target."""
        due = sorted(w for w in self.in_flight if w[0] <= t + IMPACT_TOLERANCE)
        if not due:
            return
        self.in_flight = [w for w in self.in_flight if w[0] > t + IMPACT_TOLERANCE]
        for _, k in due:
            shot = self.shots[k]
            shooter, target, pk = shot[2], shot[3], shot[7]
            self.pairs.discard((shooter, target))
            kind, idx = target
            hit = False
            if kind == "air":
                self.inbound[idx] -= 1
                if self.alive[idx]:
                    if self.phase[idx] == PH["defensive"]:
                        pk *= EVASION
                    hit = self.rng.random_sample() < pk
                    if hit:
                        self.alive[idx] = False
                        self.phase[idx] = PH["destroyed"]
                        self.speed[idx] = 0.0
                        if not self.friendly[idx]:
                            self.n_hostile_lost += 1
            elif kind == "sam":
                self.inbound_sites[idx] -= 1
                if self.sam_alive[idx]:
                    hit = self.rng.random_sample() < pk
                    if hit:
                        self.sam_alive[idx] = False
            else:  # the target
                hit = self.rng.random_sample() < pk
            shot[6] = "hit" if hit else "miss"
