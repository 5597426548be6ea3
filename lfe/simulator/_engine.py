"""The simulation: :func:`simulate_scenario`, its time loop and the aircraft's motion."""

from __future__ import annotations

import math
import numbers

import numpy as np
from sklearn.utils import check_random_state

from lfe.simulator._geometry import heading_to, norm, step_along
from lfe.simulator._output import scenario_tables
from lfe.simulator._tactics import Tactics
from lfe.simulator._weapons import Weapons
from lfe.simulator._world import World
from lfe.simulator.config import (
    CLIMB_RATE,
    MAX_FLIGHT_TIME,
    MAX_TURN_RATE,
    ON_TARGET_ALTITUDE,
    PH,
    ScenarioConfig,
)

__all__ = ["simulate_scenario"]


def simulate_scenario(config=None, random_state=None, *, scenario_id=None):
    """Simulate one offensive-counter-air large-force exercise.

    Every aircraft follows a scripted flight-phase machine for its role and reacts to events:

    - *Escorts* hold in the marshal area, push at ``escort_push_time`` towards a sweep point in
      front of the target, engage the nearest airborne hostile fighter within radar range
      (90 km) that is not withdrawing and fire air-to-air missiles within 45 km (one missile
      in flight per hostile), go defensive while a weapon is inbound, screen
      15 km ahead of the strikers once those push, and egress once the strikers are off
      target or their missiles are spent.
    - *SEAD* aircraft push ``sead_push_delay`` later, attack emitting SAM sites (a site emits
      while a friendly aircraft is inside its detection range) with anti-radiation missiles
      from a 55 km stand-off orbit, and egress with the strikers or when out of missiles.
    - *Strikers* push at the planned time (computed to reach the release point just after
      ``tot_start``, shifted by ``striker_push_offset`` and a random jitter), hold at the
      initial point if early, fly the attack run in the ``on_target`` phase, and release all
      their munitions within 12 km of the target when not defensive. A hostile missile fired
      at a striker before the initial point may make the package abort; after
      ``tot_end + 300`` s they go home without releasing.
    - *Hostile fighters* fly combat air patrols, commit on friendly aircraft within 70 km,
      and on strikers anywhere within 110 km of the target (ground radar vectors them there),
      strikers first; they fire within 40 km. Those airborne when ``hostile_withdraw_fraction``
      of the hostile fighters has been shot down withdraw, as does any fighter out of
      missiles. A ``hostile_alert_fraction`` of them waits on ground alert (phase
      ``marshal``) at an airbase behind the target and scrambles when the strikers approach,
      threatening them late.
    - *SAM sites* fire on the nearest friendly aircraft inside their weapon range.

    Weapons fly at a finite speed; at impact they hit with their probability of kill when the
    target is still alive (times 0.6 when the target aircraft is defensive at that moment).
    A destroyed aircraft stays where it was (phase ``destroyed``).

    Parameters
    ----------
    config : ScenarioConfig, default=None
        The scenario; ``None`` uses ``ScenarioConfig()``.
    random_state : int, RandomState instance or None, default=None
        Seed of every random draw. A seed is drawn from a ``RandomState`` (or ``None``) and
        stored in ``meta["seed"]``, so ``simulate_scenario(config, meta["seed"])`` reproduces
        the scenario.
    scenario_id : str, default=None
        Identifier stored in ``meta``; ``None`` gives ``"lfe-<seed>"``.

    Returns
    -------
    scenario : Scenario
        Raw tables ``tracks``, ``weapons``, ``sites`` and ``meta`` (TOT window, counts, seed,
        configuration, planned push times).

    Examples
    --------
    >>> from lfe import ScenarioConfig, simulate_scenario
    >>> sc = simulate_scenario(ScenarioConfig(n_hostile=6), random_state=1)
    >>> sc.meta["n_friendly"], sc.meta["n_hostile"]
    (18, 6)
    >>> sorted(sc.tracks["role"].unique())
    ['escort', 'fighter', 'sead', 'striker']
    >>> bool(sc.tracks.groupby("aircraft_id")["alive"].is_monotonic_decreasing.all())
    True
    """
    if config is None:
        config = ScenarioConfig()
    if not isinstance(config, ScenarioConfig):
        raise ValueError(f"config must be a ScenarioConfig, got {type(config).__name__}")
    if isinstance(random_state, numbers.Integral) and not isinstance(random_state, bool):
        if not 0 <= int(random_state) < 2**32:
            raise ValueError(f"random_state must be in [0, 2**32), got {random_state!r}")
        seed = int(random_state)
    else:
        seed = int(check_random_state(random_state).randint(0, 2**31 - 1))
    if scenario_id is None:
        scenario_id = f"lfe-{seed}"
    return _Simulation(config, seed, str(scenario_id)).run()


class _Simulation(World, Weapons, Tactics):
    """One running scenario: set up by :class:`World`, stepped by :meth:`run`."""

    def _move(self, goal, want):
        moving = self.alive & (want > 0)
        dx = goal[:, 0] - self.pos[:, 0]
        dy = goal[:, 1] - self.pos[:, 1]
        desired = heading_to(dx, dy)
        delta = (desired - self.heading + 180.0) % 360.0 - 180.0
        max_turn = MAX_TURN_RATE * self.dt
        self.heading = np.where(moving, (self.heading + np.clip(delta, -max_turn, max_turn))
                                % 360.0, self.heading)
        self.speed = np.where(self.alive, want, 0.0)
        step = self.speed * self.dt / 1000.0
        dist = norm(dx, dy)
        step = np.minimum(step, np.where(np.abs(delta) <= max_turn, dist, step))
        step_x, step_y = step_along(self.heading, step)
        self.pos[:, 0] += np.where(moving, step_x, 0.0)
        self.pos[:, 1] += np.where(moving, step_y, 0.0)
        target_alt = np.where(self.phase == PH["on_target"], ON_TARGET_ALTITUDE, self.alt_pref)
        climb = np.clip(target_alt - self.alt, -CLIMB_RATE * self.dt, CLIMB_RATE * self.dt)
        self.alt = np.where(moving, self.alt + climb, self.alt)

    def run(self):
        c = self.c
        # After max_duration nothing fires; the run goes on until the last weapon lands.
        n_steps = int(math.floor(c.max_duration / self.dt)) + 1
        n_steps += int(math.ceil(MAX_FLIGHT_TIME / self.dt)) + 1
        rec_x = np.empty((n_steps, self.n))
        rec_y = np.empty((n_steps, self.n))
        rec_alt = np.empty((n_steps, self.n))
        rec_speed = np.empty((n_steps, self.n))
        rec_heading = np.empty((n_steps, self.n))
        rec_phase = np.empty((n_steps, self.n), dtype=np.int64)
        rec_alive = np.empty((n_steps, self.n), dtype=bool)
        home_friendly = self.friendly
        steps = 0
        for step in range(n_steps):
            t = step * self.dt
            self._resolve(t)
            goal, want = self._decide(t)
            self.speed = np.where(self.alive, want, 0.0)
            rec_x[step], rec_y[step] = self.pos[:, 0], self.pos[:, 1]
            rec_alt[step], rec_speed[step] = self.alt, self.speed
            rec_heading[step] = self.heading
            rec_phase[step], rec_alive[step] = self.phase, self.alive
            steps = step + 1
            settled = home_friendly & self.alive
            if not self.in_flight and (t >= c.max_duration or (
                    t >= self.tot_end and np.all(self.phase[settled] == PH["rtb"])
                    and np.all(self.speed[settled] == 0.0))):
                break
            self._move(goal, want)
        records = {"x": rec_x, "y": rec_y, "altitude": rec_alt, "speed": rec_speed,
                   "heading": rec_heading, "phase": rec_phase, "alive": rec_alive}
        return scenario_tables(self, steps, records)
