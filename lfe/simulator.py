"""Large-force-exercise simulator: an offensive-counter-air mission at a fixed time step."""

from __future__ import annotations

import math
import numbers
from dataclasses import asdict, dataclass, fields

import numpy as np
import pandas as pd
from sklearn.utils import check_random_state

from lfe.scenario import (
    FLIGHT_PHASES,
    SITE_COLUMNS,
    TRACK_COLUMNS,
    WEAPON_COLUMNS,
    Scenario,
    normalise_table,
)

__all__ = ["ScenarioConfig", "simulate_scenario"]

_PH = {p: k for k, p in enumerate(FLIGHT_PHASES)}
_ROLE_NAMES = ("escort", "sead", "striker", "fighter")
_ESC, _SEAD, _STK, _FTR = range(4)

# Kinematics (speeds in m/s, distances in km, angles in degrees).
_SPEED = {
    "marshal": 180.0, "push": 260.0, "cap": 200.0, "engage": 300.0, "defensive": 320.0,
    "on_target": 240.0, "egress": 290.0, "rtb": 230.0, "withdraw": 300.0,
}
_MAX_TURN_RATE = 4.5  # degrees per second
_CLIMB_RATE = 40.0  # m/s
_ALTITUDE = {_ESC: 9000.0, _SEAD: 7500.0, _STK: 6000.0, _FTR: 8500.0}
_ON_TARGET_ALTITUDE = 4000.0
_ORBIT_RADIUS = 8.0
# Sensors and weapons (km, km/s).
_DETECT = {_ESC: 90.0, _FTR: 70.0, _SEAD: 100.0}
_AAM_RANGE = {_ESC: 45.0, _FTR: 40.0}
_HARM_RANGE = 60.0
_SEAD_STANDOFF = 55.0
_RELEASE_RANGE = 12.0
_IP_DISTANCE = 45.0
_RELEASE_AIM = 15.0  # planned release, s after the TOT window opens (impact 30 s later)
_EVASION = 0.6  # probability-of-kill factor against an aircraft that is defensive
_WEAPON_SPEED = {"aam": 1.0, "harm": 0.7, "sam": 0.9}
_BOMB_FLIGHT_TIME = 30.0
_COOLDOWN = {"aam": 20.0, "harm": 30.0, "sam": 20.0}
_GCI_RANGE = 110.0  # hostile ground radar sees strikers this close to the target
_HOSTILE_FLOOR_X = 40.0  # hostile fighters do not chase west of this line
_PURSUIT_LIMIT_X = 60.0  # escorts do not chase hostiles further east than target + this
_HOME_RADIUS = 5.0
_MAX_FLIGHT_TIME = 300.0  # no weapon flies longer than this (s)
_EGRESS_LINE = 60.0  # egress becomes rtb west of this line (km)


@dataclass(frozen=True)
class ScenarioConfig:
    """Configuration of one offensive-counter-air scenario.

    Friendly forces start in the west (x near 0 km), the assigned target lies
    ``target_distance`` km east; hostile fighters hold combat air patrols in front of it and
    SAM sites defend it. Escorts push first to sweep the hostile fighters, SEAD aircraft follow
    to suppress the SAM sites, and the strikers push so as to reach the target in the
    time-on-target window ``[tot_start, tot_start + tot_window]``. The random draws of
    :func:`simulate_scenario` (positions, ranges, timing jitter, every shot's outcome) make
    each run different.

    Parameters
    ----------
    n_escorts, n_sead, n_strikers : int, default=8, 8, 2
        Friendly aircraft per role (the paper's 18-aircraft package).
    n_hostile : int, default=8
        Hostile fighters.
    n_sams : int, default=3
        SAM sites.
    dt : float, default=10.0
        Simulation and recording time step (s).
    max_duration : float, default=3600.0
        The mission ends at the latest at this time (s); it ends earlier once every surviving
        friendly aircraft is home and no weapon is in flight.
    escort_push_time : float, default=180.0
        Planned time the escorts leave the marshal area (s).
    sead_push_delay : float, default=60.0
        SEAD aircraft push this long after the escorts (s).
    striker_push_offset : float, default=0.0
        Added to the strikers' planned push time (s): positive pushes late, negative early.
    tot_start : float, default=1500.0
        Opening of the time-on-target window (s).
    tot_window : float, default=300.0
        Length of the time-on-target window (s).
    escort_missiles, hostile_missiles, sead_harms, sam_missiles : int, default=4, 2, 2, 6
        Weapon loads: air-to-air missiles per escort and per hostile fighter, anti-radiation
        missiles per SEAD aircraft, surface-to-air missiles per SAM site.
    bombs_per_striker : int, default=2
        Munitions each striker carries to the target.
    pk_escort, pk_hostile, pk_harm, pk_sam, pk_bomb : float, default=0.55, 0.4, 0.5, 0.3, 0.4
        Probabilities of kill (of hitting the target for ``pk_bomb``) per weapon.
    hostile_withdraw_fraction : float, default=0.5
        Hostile fighters still alive withdraw once this fraction of them has been shot down.
    hostile_alert_fraction : float, default=0.25
        Fraction of the hostile fighters (rounded) held on ground alert at an airbase behind
        the target; they scramble 30-240 s (a random delay each) after hostile ground radar
        first sees a striker within 110 km of the target.
    striker_abort_probability : float, default=0.3
        Chance that the strike package aborts when a hostile fighter fires on a striker
        before the strikers reach the initial point.
    target_distance : float, default=160.0
        East-west distance from the friendly marshal area to the target (km).

    Examples
    --------
    >>> from lfe import ScenarioConfig
    >>> ScenarioConfig(n_hostile=12).n_friendly
    18
    >>> ScenarioConfig(pk_bomb=1.5)
    Traceback (most recent call last):
    ...
    ValueError: ScenarioConfig.pk_bomb must be a probability in [0, 1], got 1.5
    """

    n_escorts: int = 8
    n_sead: int = 8
    n_strikers: int = 2
    n_hostile: int = 8
    n_sams: int = 3
    dt: float = 10.0
    max_duration: float = 3600.0
    escort_push_time: float = 180.0
    sead_push_delay: float = 60.0
    striker_push_offset: float = 0.0
    tot_start: float = 1500.0
    tot_window: float = 300.0
    escort_missiles: int = 4
    hostile_missiles: int = 2
    sead_harms: int = 2
    sam_missiles: int = 6
    bombs_per_striker: int = 2
    pk_escort: float = 0.55
    pk_hostile: float = 0.4
    pk_harm: float = 0.5
    pk_sam: float = 0.3
    pk_bomb: float = 0.4
    hostile_withdraw_fraction: float = 0.5
    hostile_alert_fraction: float = 0.25
    striker_abort_probability: float = 0.3
    target_distance: float = 160.0

    def __post_init__(self):
        def name(f):
            return f"ScenarioConfig.{f}"

        for f in fields(self):
            value = getattr(self, f.name)
            if f.type in ("int", int):
                if isinstance(value, bool) or not isinstance(value, numbers.Integral):
                    raise ValueError(f"{name(f.name)} must be an integer, got {value!r}")
                if value < 0:
                    raise ValueError(f"{name(f.name)} must be >= 0, got {value!r}")
            else:
                if isinstance(value, bool) or not isinstance(value, numbers.Real):
                    raise ValueError(f"{name(f.name)} must be a number, got {value!r}")
                if not math.isfinite(value):
                    raise ValueError(f"{name(f.name)} must be finite, got {value!r}")
        for f in ("n_strikers", "bombs_per_striker"):
            if getattr(self, f) < 1:
                raise ValueError(f"{name(f)} must be >= 1, got {getattr(self, f)!r}")
        for f in ("dt", "tot_window", "target_distance", "max_duration"):
            if getattr(self, f) <= 0:
                raise ValueError(f"{name(f)} must be positive, got {getattr(self, f)!r}")
        for f in ("escort_push_time", "sead_push_delay", "tot_start"):
            if getattr(self, f) < 0:
                raise ValueError(f"{name(f)} must be >= 0, got {getattr(self, f)!r}")
        for f in ("pk_escort", "pk_hostile", "pk_harm", "pk_sam", "pk_bomb",
                  "hostile_withdraw_fraction", "hostile_alert_fraction",
                  "striker_abort_probability"):
            value = getattr(self, f)
            if not 0.0 <= value <= 1.0:
                raise ValueError(f"{name(f)} must be a probability in [0, 1], got {value!r}")
        if self.target_distance < 2 * _IP_DISTANCE:
            raise ValueError(
                f"{name('target_distance')} must be at least {2 * _IP_DISTANCE:g} km, got "
                f"{self.target_distance!r}"
            )
        if self.max_duration <= self.tot_start + self.tot_window:
            raise ValueError(
                f"{name('max_duration')} ({self.max_duration!r}) must exceed the end of the "
                f"time-on-target window ({self.tot_start + self.tot_window!r})"
            )
        if self.max_duration / self.dt > 100_000:
            raise ValueError(
                f"{name('dt')} ({self.dt!r}) is too small for max_duration "
                f"({self.max_duration!r}): more than 100000 steps"
            )

    @property
    def n_friendly(self):
        """Number of friendly aircraft."""
        return self.n_escorts + self.n_sead + self.n_strikers

    def to_dict(self):
        """The configuration as a plain dict (JSON-serialisable)."""
        return asdict(self)


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


def _heading_to(dx, dy):
    return np.degrees(np.arctan2(dx, dy)) % 360.0


class _Simulation:
    """State of one running scenario (arrays over aircraft, lists of weapons)."""

    def __init__(self, config, seed, scenario_id):
        self.c = c = config
        self.seed = seed
        self.scenario_id = scenario_id
        self.rng = rng = np.random.RandomState(seed)
        self.dt = float(c.dt)
        self.tot_start = float(c.tot_start)
        self.tot_end = float(c.tot_start + c.tot_window)

        # ----- geometry
        self.target = np.array([c.target_distance, rng.uniform(-20.0, 20.0)])
        tx, ty = self.target
        roles = ([_ESC] * c.n_escorts + [_SEAD] * c.n_sead + [_STK] * c.n_strikers
                 + [_FTR] * c.n_hostile)
        self.role = np.array(roles, dtype=np.int64)
        n = self.n = len(roles)
        self.friendly = self.role != _FTR
        names, counters = [], dict.fromkeys(range(4), 0)
        for r in roles:
            counters[r] += 1
            names.append(f"{_ROLE_NAMES[r]}_{counters[r]:02d}")
        self.names = names

        home = np.zeros((n, 2))
        self.lane = np.zeros(n)
        for r, xr, yr in ((_ESC, (5, 15), 40.0), (_SEAD, (0, 10), 30.0), (_STK, (-5, 0), 6.0)):
            idx = np.flatnonzero(self.role == r)
            if len(idx):
                lanes = np.linspace(-yr, yr, len(idx)) if len(idx) > 1 else np.zeros(1)
                home[idx, 0] = rng.uniform(*xr, size=len(idx))
                home[idx, 1] = lanes + rng.normal(0.0, 2.0, size=len(idx))
                self.lane[idx] = lanes
        hostile = np.flatnonzero(self.role == _FTR)
        self.cap = np.zeros((n, 2))
        self.cap[hostile, 0] = tx - rng.uniform(15.0, 50.0, size=len(hostile))
        self.cap[hostile, 1] = ty + rng.uniform(-40.0, 40.0, size=len(hostile))
        home[hostile] = self.cap[hostile] + rng.normal(0.0, 3.0, size=(len(hostile), 2))
        self.airbase = np.array([tx + 90.0, ty + rng.uniform(-20.0, 20.0)])
        n_alert = int(round(c.hostile_alert_fraction * len(hostile)))
        self.scramble = np.zeros(n)  # time each fighter is airborne (inf: not yet ordered)
        self.alert_delay = np.zeros(n)
        if n_alert:
            alert = hostile[-n_alert:]
            home[alert] = self.airbase + rng.normal(0.0, 1.0, size=(n_alert, 2))
            self.scramble[alert] = np.inf
            self.alert_delay[alert] = rng.uniform(30.0, 240.0, size=n_alert)
        self.home = home
        # Where each friendly pushes to: escorts sweep ahead of the target, SEAD hold off.
        self.station = np.zeros((n, 2))
        esc = np.flatnonzero(self.role == _ESC)
        self.station[esc, 0] = tx - 30.0 + rng.uniform(-5.0, 5.0, size=len(esc))
        self.station[esc, 1] = ty + 0.8 * self.lane[esc]
        sead = np.flatnonzero(self.role == _SEAD)
        self.station[sead, 0] = tx - 60.0 + rng.uniform(-5.0, 5.0, size=len(sead))
        self.station[sead, 1] = ty + 0.8 * self.lane[sead]
        self.ip = np.array([tx - _IP_DISTANCE, ty])

        ns = c.n_sams
        self.sam_xy = np.column_stack([
            tx - rng.uniform(-10.0, 50.0, size=ns), ty + rng.uniform(-35.0, 35.0, size=ns)
        ]) if ns else np.zeros((0, 2))
        self.sam_range = rng.uniform(25.0, 40.0, size=ns)
        self.sam_detect = self.sam_range + rng.uniform(20.0, 30.0, size=ns)
        self.sam_alive = np.ones(ns, dtype=bool)
        self.sam_missiles = np.full(ns, c.sam_missiles, dtype=np.int64)
        self.sam_ready = np.zeros(ns)
        self.sam_emitting = np.zeros(ns, dtype=bool)
        self.sam_names = [f"sam_{k + 1}" for k in range(ns)]

        # ----- timeline
        self.escort_push = c.escort_push_time + rng.uniform(-30.0, 30.0)
        self.sead_push = self.escort_push + c.sead_push_delay + rng.uniform(-10.0, 10.0)
        # Strikers aim to release _RELEASE_AIM s after the window opens: they push so as to
        # reach the initial point then, and hold there when early.
        self.run_in_time = (_IP_DISTANCE - _RELEASE_RANGE) / (_SPEED["on_target"] / 1000.0)
        release_aim = self.tot_start + _RELEASE_AIM
        transit = np.hypot(*(self.ip - np.array([-2.5, 0.0]))) / (_SPEED["push"] / 1000.0)
        self.striker_push_planned = max(0.0, release_aim - self.run_in_time - transit)
        self.striker_push = max(
            0.0, self.striker_push_planned + c.striker_push_offset + rng.normal(0.0, 20.0)
        )
        self.run_in_start = release_aim - self.run_in_time

        # ----- state
        self.pos = home.copy()
        self.heading = np.where(self.friendly, 90.0, 270.0) + rng.uniform(-20, 20, size=n)
        self.speed = np.zeros(n)
        self.alt = np.array([_ALTITUDE[r] for r in roles]) + rng.uniform(-300, 300, size=n)
        self.alt_pref = self.alt.copy()
        self.phase = np.where(self.friendly, _PH["marshal"], _PH["cap"]).astype(np.int64)
        self.alive = np.ones(n, dtype=bool)
        loads = {_ESC: c.escort_missiles, _SEAD: c.sead_harms, _STK: c.bombs_per_striker,
                 _FTR: c.hostile_missiles}
        self.ammo = np.array([loads[r] for r in roles], dtype=np.int64)
        self.ready = np.zeros(n)
        self.inbound = np.zeros(n, dtype=np.int64)  # weapons in flight at each aircraft
        self.inbound_sites = np.zeros(ns, dtype=np.int64)
        self.reached = np.zeros(n, dtype=bool)  # station / initial point reached
        self.aborted = False
        self.withdrawing = np.zeros(n, dtype=bool)
        self.hostile_withdraw = False
        self.n_hostile_lost = 0

        self.in_flight = []  # [impact, shot_index]
        self.shots = []  # rows of the weapons table
        self.pairs = set()  # (shooter, target) with a weapon in flight

    # ------------------------------------------------------------------ weapons
    def _fire(self, t, shooter, target, weapon, distance, pk):
        """Release one weapon; returns False (and fires nothing) after ``max_duration``."""
        if t >= self.c.max_duration:
            return False
        if weapon == "bomb":
            flight = _BOMB_FLIGHT_TIME
        else:
            flight = distance / _WEAPON_SPEED[weapon]
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
        due = sorted(w for w in self.in_flight if w[0] <= t + 1e-9)
        if not due:
            return
        self.in_flight = [w for w in self.in_flight if w[0] > t + 1e-9]
        for _, k in due:
            shot = self.shots[k]
            shooter, target, pk = shot[2], shot[3], shot[7]
            self.pairs.discard((shooter, target))
            kind, idx = target
            hit = False
            if kind == "air":
                self.inbound[idx] -= 1
                if self.alive[idx]:
                    if self.phase[idx] == _PH["defensive"]:
                        pk *= _EVASION
                    hit = self.rng.random_sample() < pk
                    if hit:
                        self.alive[idx] = False
                        self.phase[idx] = _PH["destroyed"]
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

    # ------------------------------------------------------------------ decisions
    def _away(self, i, threat_xy):
        d = self.pos[i] - threat_xy
        norm = np.hypot(*d) or 1.0
        return self.pos[i] + 30.0 * d / norm

    def _orbit(self, i, center, radius=_ORBIT_RADIUS, step_deg=40.0):
        d = self.pos[i] - center
        angle = math.atan2(d[1], d[0]) - math.radians(step_deg)
        return center + radius * np.array([math.cos(angle), math.sin(angle)])

    def _decide(self, t):
        c = self.c
        n = self.n
        pos = self.pos
        goal = pos.copy()
        want = np.zeros(n)
        friendly_alive = np.flatnonzero(self.friendly & self.alive)
        hostile_alive = np.flatnonzero(~self.friendly & self.alive)
        d_fh = np.hypot(pos[friendly_alive, None, 0] - pos[None, hostile_alive, 0],
                        pos[friendly_alive, None, 1] - pos[None, hostile_alive, 1])
        row = {int(i): k for k, i in enumerate(friendly_alive)}
        col = {int(j): k for k, j in enumerate(hostile_alive)}
        sam_live = np.flatnonzero(self.sam_alive)
        d_sf = np.hypot(self.sam_xy[sam_live, None, 0] - pos[None, friendly_alive, 0],
                        self.sam_xy[sam_live, None, 1] - pos[None, friendly_alive, 1])
        if len(sam_live) and len(friendly_alive):
            self.sam_emitting[sam_live] |= (d_sf <= self.sam_detect[sam_live, None]).any(axis=1)

        strikers = np.flatnonzero(self.role == _STK)
        ph_s = self.phase[strikers]
        strikers_done = bool(np.all(
            ~self.alive[strikers] | (ph_s == _PH["egress"]) | (ph_s == _PH["rtb"])
        )) and t >= self.striker_push
        bingo = t > self.tot_end + 600.0

        if (c.n_hostile and not self.hostile_withdraw
                and self.n_hostile_lost >= math.ceil(c.hostile_withdraw_fraction * c.n_hostile)
                and self.n_hostile_lost > 0):
            self.hostile_withdraw = True  # the fighters airborne now break off
            self.withdrawing |= ~self.friendly & (self.scramble <= t)
        # Escorts screen 15 km ahead of the strikers between their push and their egress.
        ingress = strikers[self.alive[strikers] & (
            (ph_s == _PH["push"]) | (ph_s == _PH["on_target"]) | (ph_s == _PH["defensive"]))]
        self.screen = None
        if len(ingress) and t >= self.striker_push:
            centre = pos[ingress].mean(axis=0)
            ahead = self.target - centre
            dist = np.hypot(*ahead)
            self.screen = centre + (15.0 * ahead / dist if dist > 1e-9 else 0.0)
        # Ground-controlled interception: strikers near the target are seen by hostile radar.
        live_strikers = strikers[self.alive[strikers]]
        gci = np.hypot(pos[live_strikers, 0] - self.target[0],
                       pos[live_strikers, 1] - self.target[1]) <= _GCI_RANGE
        self.gci_seen = np.zeros(n, dtype=bool)
        self.gci_seen[live_strikers[gci]] = True
        if gci.any():
            waiting = np.isinf(self.scramble)
            self.scramble[waiting] = t + self.alert_delay[waiting]

        for i in range(n):
            if not self.alive[i]:
                continue
            r = self.role[i]
            if r == _FTR:
                self._decide_fighter(t, i, goal, want, friendly_alive, d_fh[:, col[i]])
                continue
            if self.phase[i] in (_PH["egress"], _PH["rtb"]):
                self._go_home(i, goal, want)
                continue
            if r == _ESC:
                self._decide_escort(t, i, goal, want, hostile_alive, d_fh[row[i]],
                                    strikers_done or bingo)
            elif r == _SEAD:
                self._decide_sead(t, i, goal, want, sam_live, strikers_done or bingo)
            else:
                self._decide_striker(t, i, goal, want, hostile_alive, d_fh[row[i]])

        self._decide_sams(t, friendly_alive, sam_live, d_sf)
        return goal, want

    def _go_home(self, i, goal, want):
        if self.pos[i, 0] < _EGRESS_LINE:
            self.phase[i] = _PH["rtb"]
        d = np.hypot(*(self.home[i] - self.pos[i]))
        if self.phase[i] == _PH["rtb"] and d <= _HOME_RADIUS:
            goal[i] = self.pos[i]
            want[i] = 0.0
            return
        goal[i] = self.home[i]
        want[i] = _SPEED["egress"] if self.phase[i] == _PH["egress"] else _SPEED["rtb"]

    def _egress(self, i, goal, want):
        self.phase[i] = _PH["egress"]
        self._go_home(i, goal, want)

    def _nearest_threat_xy(self, i, hostile_alive, d_row):
        candidates = [self.pos[j] for j in hostile_alive]
        distances = list(d_row)
        for k in np.flatnonzero(self.sam_alive):
            candidates.append(self.sam_xy[k])
            distances.append(np.hypot(*(self.sam_xy[k] - self.pos[i])))
        if not candidates:
            return self.pos[i] + np.array([10.0, 0.0])
        return candidates[int(np.argmin(distances))]

    def _decide_escort(self, t, i, goal, want, hostile_alive, d_row, done):
        c = self.c
        if t < self.escort_push:
            self.phase[i] = _PH["marshal"]
            goal[i] = self._orbit(i, self.home[i])
            want[i] = _SPEED["marshal"]
            return
        if done or self.ammo[i] == 0:
            self._egress(i, goal, want)
            return
        if self.inbound[i] > 0:
            self.phase[i] = _PH["defensive"]
            goal[i] = self._away(i, self._nearest_threat_xy(i, hostile_alive, d_row))
            want[i] = _SPEED["defensive"]
            return
        ok = ((d_row <= _DETECT[_ESC])
              & (self.pos[hostile_alive, 0] <= self.target[0] + _PURSUIT_LIMIT_X)
              & (self.phase[hostile_alive] != _PH["withdraw"])
              & (self.phase[hostile_alive] != _PH["marshal"]))
        if ok.any():
            k = int(np.flatnonzero(ok)[np.argmin(d_row[ok])])
            j = int(hostile_alive[k])
            self.phase[i] = _PH["engage"]
            goal[i] = self.pos[j]
            want[i] = _SPEED["engage"]
            if (d_row[k] <= _AAM_RANGE[_ESC] and t >= self.ready[i]
                    and self.inbound[j] == 0):
                if self._fire(t, i, ("air", j), "aam", d_row[k], c.pk_escort):
                    self.ammo[i] -= 1
                    self.ready[i] = t + _COOLDOWN["aam"]
            return
        if self.screen is not None:  # strikers on their way: screen ahead of them
            self.phase[i] = _PH["push"]
            goal[i] = self.screen + np.array([0.0, 0.4 * self.lane[i]])
            far = np.hypot(*(goal[i] - self.pos[i])) > 10.0
            want[i] = _SPEED["engage"] if far else _SPEED["push"]
            return
        self._station(i, goal, want)

    def _station(self, i, goal, want):
        if not self.reached[i] and np.hypot(*(self.station[i] - self.pos[i])) < 2 * _ORBIT_RADIUS:
            self.reached[i] = True
        if self.reached[i]:
            self.phase[i] = _PH["cap"]
            goal[i] = self._orbit(i, self.station[i])
            want[i] = _SPEED["cap"]
        else:
            self.phase[i] = _PH["push"]
            goal[i] = self.station[i]
            want[i] = _SPEED["push"]

    def _decide_sead(self, t, i, goal, want, sam_live, done):
        c = self.c
        if t < self.sead_push:
            self.phase[i] = _PH["marshal"]
            goal[i] = self._orbit(i, self.home[i])
            want[i] = _SPEED["marshal"]
            return
        if done or (self.ammo[i] == 0 and t >= self.striker_push):
            self._egress(i, goal, want)
            return
        if self.inbound[i] > 0:
            self.phase[i] = _PH["defensive"]
            goal[i] = self._away(i, self._nearest_threat_xy(
                i, np.zeros(0, dtype=np.int64), np.zeros(0)))
            want[i] = _SPEED["defensive"]
            return
        live = sam_live[self.sam_emitting[sam_live]] if len(sam_live) else sam_live
        if len(live) and self.ammo[i] > 0:
            d = np.hypot(self.sam_xy[live, 0] - self.pos[i, 0],
                         self.sam_xy[live, 1] - self.pos[i, 1])
            ok = d <= _DETECT[_SEAD]
            if ok.any():
                k = int(np.flatnonzero(ok)[np.argmin(d[ok])])
                s = int(live[k])
                self.phase[i] = _PH["engage"]
                want[i] = _SPEED["engage"]
                if d[k] > _SEAD_STANDOFF + 5.0:
                    goal[i] = self.sam_xy[s]
                else:
                    goal[i] = self._orbit(i, self.sam_xy[s], radius=_SEAD_STANDOFF, step_deg=15.0)
                if (d[k] <= _HARM_RANGE and t >= self.ready[i] and self.inbound_sites[s] == 0):
                    if self._fire(t, i, ("sam", s), "harm", d[k], c.pk_harm):
                        self.ammo[i] -= 1
                        self.ready[i] = t + _COOLDOWN["harm"]
                return
        self._station(i, goal, want)

    def _decide_striker(self, t, i, goal, want, hostile_alive, d_row):
        c = self.c
        if self.aborted or self.ammo[i] == 0 or t > self.tot_end + 300.0:
            self._egress(i, goal, want)
            return
        if t < self.striker_push:
            self.phase[i] = _PH["marshal"]
            goal[i] = self._orbit(i, self.home[i])
            want[i] = _SPEED["marshal"]
            return
        d_target = float(np.hypot(*(self.target - self.pos[i])))
        if not self.reached[i] and np.hypot(*(self.ip - self.pos[i])) < 5.0:
            self.reached[i] = True
        if self.inbound[i] > 0:
            self.phase[i] = _PH["defensive"]
            want[i] = _SPEED["defensive"]
            if self.reached[i]:
                goal[i] = self.target  # press on, but no release while defensive
            else:
                goal[i] = self._away(i, self._nearest_threat_xy(i, hostile_alive, d_row))
            return
        if not self.reached[i]:
            self.phase[i] = _PH["push"]
            goal[i] = self.ip
            want[i] = _SPEED["push"]
            return
        if self.phase[i] != _PH["on_target"] and t < self.run_in_start:
            self.phase[i] = _PH["push"]  # early: hold at the initial point
            goal[i] = self._orbit(i, self.ip)
            want[i] = _SPEED["cap"]
            return
        self.phase[i] = _PH["on_target"]
        goal[i] = self.target
        want[i] = _SPEED["on_target"]
        if d_target <= _RELEASE_RANGE:
            while self.ammo[i] > 0 and self._fire(t, i, ("target", 0), "bomb", d_target,
                                                   c.pk_bomb):
                self.ammo[i] -= 1

    def _decide_fighter(self, t, i, goal, want, friendly_alive, d_col):
        c = self.c
        if t < self.scramble[i]:  # on ground alert at the airbase
            self.phase[i] = _PH["marshal"]
            goal[i] = self.pos[i]
            want[i] = 0.0
            return
        if self.withdrawing[i] or self.ammo[i] == 0:
            self.phase[i] = _PH["withdraw"]
            far = np.array([self.target[0] + 120.0, self.cap[i, 1]])
            if np.hypot(*(far - self.pos[i])) < 2 * _ORBIT_RADIUS:
                goal[i] = self._orbit(i, far)
            else:
                goal[i] = far
            want[i] = _SPEED["withdraw"]
            return
        if self.inbound[i] > 0 and len(friendly_alive):
            self.phase[i] = _PH["defensive"]
            goal[i] = self._away(i, self.pos[friendly_alive[int(np.argmin(d_col))]])
            want[i] = _SPEED["defensive"]
            return
        ok = (d_col <= _DETECT[_FTR]) | self.gci_seen[friendly_alive]
        ok &= self.pos[friendly_alive, 0] >= _HOSTILE_FLOOR_X
        if ok.any():
            cand = np.flatnonzero(ok)
            strikers = cand[self.role[friendly_alive[cand]] == _STK]
            if len(strikers):
                cand = strikers
            k = int(cand[np.argmin(d_col[cand])])
            j = int(friendly_alive[k])
            self.phase[i] = _PH["engage"]
            goal[i] = self.pos[j]
            want[i] = _SPEED["engage"]
            if (d_col[k] <= _AAM_RANGE[_FTR] and t >= self.ready[i]
                    and (i, ("air", j)) not in self.pairs):
                if self._fire(t, i, ("air", j), "aam", d_col[k], c.pk_hostile):
                    self.ammo[i] -= 1
                    self.ready[i] = t + _COOLDOWN["aam"]
                    if (self.role[j] == _STK and not self.reached[j] and not self.aborted
                            and self.rng.random_sample() < c.striker_abort_probability):
                        self.aborted = True
            return
        self.phase[i] = _PH["cap"]
        goal[i] = self._orbit(i, self.cap[i], radius=12.0)
        want[i] = _SPEED["cap"]

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
                    self.sam_ready[s] = t + _COOLDOWN["sam"]
                    break

    # ------------------------------------------------------------------ motion
    def _move(self, goal, want):
        moving = self.alive & (want > 0)
        dx = goal[:, 0] - self.pos[:, 0]
        dy = goal[:, 1] - self.pos[:, 1]
        desired = _heading_to(dx, dy)
        delta = (desired - self.heading + 180.0) % 360.0 - 180.0
        max_turn = _MAX_TURN_RATE * self.dt
        self.heading = np.where(moving, (self.heading + np.clip(delta, -max_turn, max_turn))
                                % 360.0, self.heading)
        self.speed = np.where(self.alive, want, 0.0)
        step = self.speed * self.dt / 1000.0
        dist = np.hypot(dx, dy)
        step = np.minimum(step, np.where(np.abs(delta) <= max_turn, dist, step))
        rad = np.radians(self.heading)
        self.pos[:, 0] += np.where(moving, step * np.sin(rad), 0.0)
        self.pos[:, 1] += np.where(moving, step * np.cos(rad), 0.0)
        target_alt = np.where(self.phase == _PH["on_target"], _ON_TARGET_ALTITUDE, self.alt_pref)
        climb = np.clip(target_alt - self.alt, -_CLIMB_RATE * self.dt, _CLIMB_RATE * self.dt)
        self.alt = np.where(moving, self.alt + climb, self.alt)

    # ------------------------------------------------------------------ run
    def run(self):
        c = self.c
        # After max_duration nothing fires; the run goes on until the last weapon lands.
        n_steps = int(math.floor(c.max_duration / self.dt)) + 1
        n_steps += int(math.ceil(_MAX_FLIGHT_TIME / self.dt)) + 1
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
                    t >= self.tot_end and np.all(self.phase[settled] == _PH["rtb"])
                    and np.all(self.speed[settled] == 0.0))):
                break
            self._move(goal, want)
        return self._tables(steps, rec_x, rec_y, rec_alt, rec_speed, rec_heading, rec_phase,
                            rec_alive)

    def _tables(self, steps, rx, ry, ralt, rspeed, rheading, rphase, ralive):
        c = self.c
        n = self.n
        time = np.repeat(np.arange(steps) * self.dt, n)
        side = np.where(self.friendly, "friendly", "hostile")
        role = np.array(_ROLE_NAMES)[self.role]
        phases = np.array(FLIGHT_PHASES)
        tracks = pd.DataFrame({
            "time": time,
            "aircraft_id": np.tile(np.array(self.names), steps),
            "side": np.tile(side, steps),
            "role": np.tile(role, steps),
            "x": rx[:steps].ravel(),
            "y": ry[:steps].ravel(),
            "altitude": ralt[:steps].ravel(),
            "speed": rspeed[:steps].ravel(),
            "heading": rheading[:steps].ravel(),
            "flight_phase": phases[rphase[:steps].ravel()],
            "alive": ralive[:steps].ravel(),
        }, columns=list(TRACK_COLUMNS))

        def ident(who):
            kind, idx = who
            if kind == "air":
                return self.names[idx]
            if kind in ("sam", "site"):
                return self.sam_names[idx]
            return "target"

        rows = []
        for k, t_fired, shooter, target, weapon, impact, outcome, _ in self.shots:
            shooter_id = ident(shooter) if isinstance(shooter, tuple) else self.names[shooter]
            rows.append((f"w{k + 1:04d}", float(t_fired), shooter_id, ident(target), weapon,
                         float(impact), outcome))
        weapons = pd.DataFrame(rows, columns=list(WEAPON_COLUMNS))

        sites = pd.DataFrame({
            "site_id": self.sam_names + ["target"],
            "site_type": ["sam"] * c.n_sams + ["target"],
            "x": np.append(self.sam_xy[:, 0], self.target[0]),
            "y": np.append(self.sam_xy[:, 1], self.target[1]),
            "detection_range": np.append(self.sam_detect, 0.0),
            "weapon_range": np.append(self.sam_range, 0.0),
        }, columns=list(SITE_COLUMNS))

        meta = {
            "scenario_id": self.scenario_id,
            "seed": self.seed,
            "dt": self.dt,
            "tot_start": self.tot_start,
            "tot_end": self.tot_end,
            "target_id": "target",
            "n_friendly": int(c.n_friendly),
            "n_escorts": int(c.n_escorts),
            "n_sead": int(c.n_sead),
            "n_strikers": int(c.n_strikers),
            "n_hostile": int(c.n_hostile),
            "n_sams": int(c.n_sams),
            "bombs_per_striker": int(c.bombs_per_striker),
            "escort_push_planned": float(self.escort_push),
            "striker_push_planned": float(self.striker_push_planned),
            "config": c.to_dict(),
        }
        return Scenario(normalise_table(tracks, "tracks"), normalise_table(weapons, "weapons"),
                        normalise_table(sites, "sites"), meta)
