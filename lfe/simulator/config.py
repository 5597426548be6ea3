"""The simulator's configuration: :class:`ScenarioConfig` and every constant of the model.

Units: speeds in m/s, distances and positions in km (x east, y north), altitudes in m, angles
in degrees (headings clockwise from north), times in s. ``(low, high)`` pairs are the bounds of
a uniform draw; a single ``*_JITTER`` is the half-width of a uniform draw around a planned
value, or the standard deviation of a normal one where the comment says so.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import asdict, dataclass, fields

from lfe.scenario import FLIGHT_PHASES

__all__ = ["ScenarioConfig"]

#: Flight phase name -> its code (index in :data:`lfe.scenario.FLIGHT_PHASES`).
PH = {p: k for k, p in enumerate(FLIGHT_PHASES)}
#: Role codes, in the order aircraft are numbered, and their names.
ESC, SEAD, STK, FTR = range(4)
ROLE_NAMES = ("escort", "sead", "striker", "fighter")

# ----- kinematics
#: Commanded speed in each flight phase (m/s).
SPEED = {
    "marshal": 180.0, "push": 260.0, "cap": 200.0, "engage": 300.0, "defensive": 320.0,
    "on_target": 240.0, "egress": 290.0, "rtb": 230.0, "withdraw": 300.0,
}
MAX_TURN_RATE = 4.5  # degrees per second
CLIMB_RATE = 40.0  # m/s
#: Cruise altitude per role (m), each aircraft's drawn within +-ALTITUDE_JITTER.
ALTITUDE = {ESC: 9000.0, SEAD: 7500.0, STK: 6000.0, FTR: 8500.0}
ALTITUDE_JITTER = 300.0
ON_TARGET_ALTITUDE = 4000.0
#: Initial heading (degrees) of friendly and hostile aircraft, each drawn within
#: +-HEADING_JITTER.
FRIENDLY_HEADING, HOSTILE_HEADING = 90.0, 270.0
HEADING_JITTER = 20.0
ORBIT_RADIUS = 8.0  # km, holding patterns (marshal, station, initial point)
ORBIT_STEP = 40.0  # degrees ahead on the orbit an aircraft steers to
HOME_RADIUS = 5.0  # km: inside it an aircraft returning to base has landed

# ----- the world: where things start (km)
TARGET_SPREAD_Y = 20.0  # the target's y, uniform within +-this
#: x range of each friendly role's marshal area (uniform), the half-width of its lanes (its
#: aircraft spread evenly over [-w, w] in y) and the normal jitter (sd) on their y.
MARSHAL_X = {ESC: (5.0, 15.0), SEAD: (0.0, 10.0), STK: (-5.0, 0.0)}
LANE_HALF_WIDTH = {ESC: 40.0, SEAD: 30.0, STK: 6.0}
LANE_JITTER = 2.0
#: Hostile combat air patrols: this far west of the target (uniform), within +-CAP_SPREAD_Y of
#: its y; each fighter starts normally (sd CAP_JITTER) around its patrol's centre.
CAP_DEPTH = (15.0, 50.0)
CAP_SPREAD_Y = 40.0
CAP_JITTER = 3.0
CAP_ORBIT_RADIUS = 12.0
#: The hostile airbase: this far east of the target, within +-AIRBASE_SPREAD_Y of its y;
#: fighters on alert start normally (sd AIRBASE_JITTER) around it and scramble after a delay
#: drawn in SCRAMBLE_DELAY (s).
AIRBASE_DEPTH = 90.0
AIRBASE_SPREAD_Y = 20.0
AIRBASE_JITTER = 1.0
SCRAMBLE_DELAY = (30.0, 240.0)
#: Friendly stations: escorts sweep to STATION_DEPTH[ESC] km west of the target, SEAD hold
#: STATION_DEPTH[SEAD] km west (each within +-STATION_JITTER), spread over their lanes
#: scaled by STATION_LANE_FACTOR.
STATION_DEPTH = {ESC: 30.0, SEAD: 60.0}
STATION_JITTER = 5.0
STATION_LANE_FACTOR = 0.8
#: SAM sites: this far west of the target (uniform; negative is east of it), within
#: +-SAM_SPREAD_Y of its y; weapon range drawn in SAM_RANGE, detection range that plus a draw
#: in SAM_DETECT_MARGIN.
SAM_DEPTH = (-10.0, 50.0)
SAM_SPREAD_Y = 35.0
SAM_RANGE = (25.0, 40.0)
SAM_DETECT_MARGIN = (20.0, 30.0)
IP_DISTANCE = 45.0  # the initial point, this far west of the target

# ----- the timeline (s)
ESCORT_PUSH_JITTER = 30.0  # the escorts' push within +-this of the planned time
SEAD_PUSH_JITTER = 10.0  # the SEAD push within +-this of escort push + sead_push_delay
STRIKER_PUSH_JITTER = 20.0  # sd of the normal error on the strikers' push
STRIKER_MARSHAL = (-2.5, 0.0)  # where the strikers' planned transit starts (km)
RELEASE_AIM = 15.0  # planned release, s after the TOT window opens (impact 30 s later)
STRIKER_LATE = 300.0  # strikers go home this long after the TOT window closes
BINGO = 600.0  # escorts and SEAD go home this long after the TOT window closes

# ----- tactics (km)
DETECT = {ESC: 90.0, FTR: 70.0, SEAD: 100.0}  # radar range per role
SCREEN_AHEAD = 15.0  # escorts screen this far ahead of the strikers
SCREEN_LANE_FACTOR = 0.4  # ... spread over their lanes scaled by this
SCREEN_CATCH_UP = 10.0  # an escort further than this from its screen slot flies at engage speed
EVADE_DISTANCE = 30.0  # a defensive aircraft steers to a point this far from the threat
NO_THREAT_OFFSET = (10.0, 0.0)  # ... or this far east of itself when nothing threatens it
SEAD_STANDOFF = 55.0  # SEAD orbit emitting SAM sites at this range
SEAD_APPROACH_MARGIN = 5.0  # ... flying straight at a site until within standoff + this
SEAD_ORBIT_STEP = 15.0  # degrees ahead on the standoff orbit
IP_REACHED = 5.0  # a striker within this of the initial point has reached it
PURSUIT_LIMIT_X = 60.0  # escorts do not chase hostiles further east than target + this
HOSTILE_FLOOR_X = 40.0  # hostile fighters do not chase west of this line
GCI_RANGE = 110.0  # hostile ground radar sees strikers this close to the target
WITHDRAW_DEPTH = 120.0  # withdrawing fighters fly to this far east of the target
EGRESS_LINE = 60.0  # egress becomes rtb west of this line

# ----- weapons
AAM_RANGE = {ESC: 45.0, FTR: 40.0}  # km
HARM_RANGE = 60.0  # km
RELEASE_RANGE = 12.0  # km: strikers release their munitions this close to the target
EVASION = 0.6  # probability-of-kill factor against an aircraft that is defensive
WEAPON_SPEED = {"aam": 1.0, "harm": 0.7, "sam": 0.9}  # km/s
BOMB_FLIGHT_TIME = 30.0  # s
COOLDOWN = {"aam": 20.0, "harm": 30.0, "sam": 20.0}  # s between two shots of one shooter
MAX_FLIGHT_TIME = 300.0  # no weapon flies longer than this (s)
IMPACT_TOLERANCE = 1e-9  # s: a weapon due within this of a step lands at that step


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
        if self.target_distance < 2 * IP_DISTANCE:
            raise ValueError(
                f"{name('target_distance')} must be at least {2 * IP_DISTANCE:g} km, got "
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
