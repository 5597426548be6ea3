"""The raw large-force-exercise scenario: its four tables, their schema and their validation."""

from __future__ import annotations

import contextlib
import contextvars
import numbers
from collections.abc import Mapping

import numpy as np
import pandas as pd

from lfe._table_checks import check_frame, check_numeric, check_values

__all__ = [
    "Scenario",
    "check_scenario",
    "check_scenarios",
    "checked_once",
    "memoised",
    "SIDES",
    "ROLES",
    "FRIENDLY_ROLES",
    "HOSTILE_ROLES",
    "FLIGHT_PHASES",
    "WEAPON_TYPES",
    "OUTCOMES",
    "SITE_TYPES",
    "TRACK_COLUMNS",
    "WEAPON_COLUMNS",
    "SITE_COLUMNS",
    "META_KEYS",
    "normalise_table",
]

#: Sides of an aircraft.
SIDES = ("friendly", "hostile")
#: Friendly roles of the offensive-counter-air package (the paper's 8 / 8 / 2 split).
FRIENDLY_ROLES = ("escort", "sead", "striker")
#: Hostile aircraft roles.
HOSTILE_ROLES = ("fighter",)
#: Every aircraft role.
ROLES = FRIENDLY_ROLES + HOSTILE_ROLES
#: Per-aircraft flight phases, the discrete mission timeline of each aircraft. ``marshal``:
#: holding before the push; ``push``: flying the ingress route; ``cap``: holding a combat air
#: patrol; ``engage``: attacking an air or ground threat; ``defensive``: evading an inbound
#: weapon; ``on_target``: strikers' attack run; ``egress``: leaving the target area;
#: ``rtb``: returning to (or holding at) base; ``withdraw``: a hostile fighter fleeing;
#: ``destroyed``: shot down (the aircraft no longer moves).
FLIGHT_PHASES = (
    "marshal",
    "push",
    "cap",
    "engage",
    "defensive",
    "on_target",
    "egress",
    "rtb",
    "withdraw",
    "destroyed",
)
#: Weapon types: air-to-air missile, anti-radiation missile (SEAD against SAM radars),
#: surface-to-air missile and the strikers' guided bomb.
WEAPON_TYPES = ("aam", "harm", "sam", "bomb")
#: Outcomes of a weapon: ``hit`` destroys an aircraft or a SAM site (a bomb ``hit`` on the
#: target is a hit on the target); ``miss`` otherwise (including a target already destroyed).
OUTCOMES = ("hit", "miss")
#: Ground sites: surface-to-air missile sites and the assigned target.
SITE_TYPES = ("sam", "target")

#: Columns of ``Scenario.tracks``, one row per aircraft per time step. Units: time in s,
#: x (east) and y (north) in km, altitude in m, speed in m/s, heading in degrees clockwise
#: from north.
TRACK_COLUMNS = (
    "time",
    "aircraft_id",
    "side",
    "role",
    "x",
    "y",
    "altitude",
    "speed",
    "heading",
    "flight_phase",
    "alive",
)
#: Columns of ``Scenario.weapons``, one row per weapon released. ``target`` is an aircraft id
#: or a site id; times in s.
WEAPON_COLUMNS = (
    "shot_id",
    "time_fired",
    "shooter",
    "target",
    "weapon_type",
    "time_impact",
    "outcome",
)
#: Columns of ``Scenario.sites``: ground threats and the target; positions and ranges in km.
SITE_COLUMNS = ("site_id", "site_type", "x", "y", "detection_range", "weapon_range")
#: Keys every ``Scenario.meta`` holds.
META_KEYS = ("scenario_id", "dt", "tot_start", "tot_end", "target_id")

_FLOAT_TRACK = ("time", "x", "y", "altitude", "speed", "heading")
_TABLE_COLUMNS = {"tracks": TRACK_COLUMNS, "weapons": WEAPON_COLUMNS, "sites": SITE_COLUMNS}
_FLOAT_WEAPON = ("time_fired", "time_impact")
_FLOAT_SITE = ("x", "y", "detection_range", "weapon_range")


def normalise_table(frame, table):
    """Give a raw table its schema's columns and dtypes.

    The schema's columns in order, numbers as float64, ``alive`` as bool, everything else as
    strings (pandas' default string dtype).

    Parameters
    ----------
    frame : DataFrame
        A ``tracks``, ``weapons`` or ``sites`` table.
    table : {"tracks", "weapons", "sites"}
        Which one.

    Returns
    -------
    frame : DataFrame
        A new frame with a fresh ``RangeIndex``.
    """
    columns = _TABLE_COLUMNS[table]
    floats = {"tracks": _FLOAT_TRACK, "weapons": _FLOAT_WEAPON, "sites": _FLOAT_SITE}[table]
    types = {c: (float if c in floats else bool if c == "alive" else str) for c in columns}
    return frame.loc[:, list(columns)].astype(types).reset_index(drop=True)


class Scenario:
    """One simulated (or recorded) large-force exercise: raw tables and metadata.

    Parameters
    ----------
    tracks : DataFrame
        One row per aircraft per time step, columns :data:`TRACK_COLUMNS`, sorted by time.
    weapons : DataFrame
        One row per weapon released, columns :data:`WEAPON_COLUMNS`.
    sites : DataFrame
        Ground sites (SAM sites and exactly one target), columns :data:`SITE_COLUMNS`.
    meta : dict
        At least :data:`META_KEYS`: ``scenario_id`` (str), ``dt`` (the time step, s),
        ``tot_start`` / ``tot_end`` (the time-on-target window, s) and ``target_id`` (the site
        id of the assigned target). The simulator adds the counts, the seed and its
        configuration.

    Attributes
    ----------
    scenario_id : str
        ``meta["scenario_id"]``.

    Examples
    --------
    >>> from lfe import ScenarioConfig, simulate_scenario
    >>> sc = simulate_scenario(ScenarioConfig(n_hostile=4, n_sams=1), random_state=0)
    >>> sc.tracks["aircraft_id"].nunique()
    22
    >>> list(sc.sites["site_type"])
    ['sam', 'target']
    """

    def __init__(self, tracks, weapons, sites, meta):
        self.tracks = tracks
        self.weapons = weapons
        self.sites = sites
        self.meta = dict(meta)

    @property
    def scenario_id(self):
        """The scenario's identifier (``meta["scenario_id"]``)."""
        return str(self.meta.get("scenario_id", "?"))

    @property
    def duration(self):
        """The last recorded time (s)."""
        return float(self.tracks["time"].iloc[-1]) if len(self.tracks) else 0.0

    def __repr__(self):
        n = self.tracks["aircraft_id"].nunique() if "aircraft_id" in self.tracks else 0
        return (
            f"Scenario({self.scenario_id!r}, {n} aircraft, {len(self.weapons)} weapons, "
            f"{self.duration:g} s)"
        )

    def __eq__(self, other):
        if not isinstance(other, Scenario):
            return NotImplemented
        return (
            self.meta == other.meta
            and self.tracks.equals(other.tracks)
            and self.weapons.equals(other.weapons)
            and self.sites.equals(other.sites)
        )

    __hash__ = None


def _where(index, scenario):
    sid = None
    if isinstance(scenario, Scenario):
        sid = scenario.meta.get("scenario_id")
    return f"scenario {sid!r} (index {index})" if sid is not None else f"scenario {index}"


def check_scenario(scenario, index=0):
    """Validate one raw scenario, raising ``ValueError`` naming the scenario and the column.

    Parameters
    ----------
    scenario : Scenario or mapping
        A :class:`Scenario`, or a mapping with keys ``tracks``, ``weapons``, ``sites`` and
        ``meta``.
    index : int, default=0
        Position of the scenario in its list (used in messages).

    Returns
    -------
    scenario : Scenario
        The scenario (a mapping is wrapped in a :class:`Scenario`; tables are not copied).

    Examples
    --------
    >>> from lfe import ScenarioConfig, simulate_scenario
    >>> from lfe.scenario import check_scenario
    >>> sc = simulate_scenario(ScenarioConfig(n_hostile=4, n_sams=1), random_state=0)
    >>> check_scenario(sc) is sc
    True
    >>> bad = Scenario(sc.tracks.drop(columns="alive"), sc.weapons, sc.sites, sc.meta)
    >>> check_scenario(bad, 3)
    Traceback (most recent call last):
    ...
    ValueError: scenario ... (index 3): tracks is missing column 'alive' ...
    """
    if isinstance(scenario, Mapping):
        missing = [k for k in ("tracks", "weapons", "sites", "meta") if k not in scenario]
        if missing:
            raise ValueError(f"scenario {index}: mapping is missing key {missing[0]!r}")
        scenario = Scenario(scenario["tracks"], scenario["weapons"], scenario["sites"],
                            scenario["meta"])
    if not isinstance(scenario, Scenario):
        raise ValueError(
            f"scenario {index}: expected a Scenario (or a mapping with tracks, weapons, sites, "
            f"meta), got {type(scenario).__name__}"
        )
    if id(scenario) in _CHECKED.get()[0]:
        return scenario  # validated on entering checked_once; see there
    where = _where(index, scenario)
    meta = scenario.meta
    for key in META_KEYS:
        if key not in meta:
            raise ValueError(f"{where}: meta is missing key {key!r}")
    for key in ("dt", "tot_start", "tot_end"):
        value = meta[key]
        if (not isinstance(value, numbers.Real) or isinstance(value, bool)
                or not np.isfinite(value)):
            raise ValueError(f"{where}: meta[{key!r}] must be a finite number, got {value!r}")
    if meta["dt"] <= 0:
        raise ValueError(f"{where}: meta['dt'] must be positive, got {meta['dt']!r}")
    if meta["tot_end"] < meta["tot_start"]:
        raise ValueError(
            f"{where}: meta['tot_end'] ({meta['tot_end']}) is before meta['tot_start'] "
            f"({meta['tot_start']})"
        )

    tracks, weapons, sites = scenario.tracks, scenario.weapons, scenario.sites
    check_frame(tracks, "tracks", TRACK_COLUMNS, where)
    check_frame(weapons, "weapons", WEAPON_COLUMNS, where)
    check_frame(sites, "sites", SITE_COLUMNS, where)
    if len(tracks) == 0:
        raise ValueError(f"{where}: tracks is empty (column 'time' has no rows)")

    check_numeric(tracks, "tracks", _FLOAT_TRACK, where)
    check_values(tracks, "tracks", "side", SIDES, where)
    check_values(tracks, "tracks", "role", ROLES, where)
    check_values(tracks, "tracks", "flight_phase", FLIGHT_PHASES, where)
    alive = tracks["alive"]
    if alive.dtype != bool:
        values = alive.astype(object).to_numpy()
        ok = np.isin(values, np.asarray([True, False, 0, 1], dtype=object))
        if not ok.all():
            row = int(np.flatnonzero(~ok)[0])
            raise ValueError(
                f"{where}: tracks column 'alive' must be boolean, got {values[row]!r} at row {row}"
            )
    time = tracks["time"].to_numpy(dtype=float)
    if np.any(np.diff(time) < 0):
        row = int(np.flatnonzero(np.diff(time) < 0)[0]) + 1
        raise ValueError(
            f"{where}: tracks column 'time' is not non-decreasing (row {row}: {time[row]} after "
            f"{time[row - 1]})"
        )
    ids = tracks["aircraft_id"].astype(str).to_numpy()
    id_codes, id_uniques = pd.factorize(ids)
    time_codes = pd.factorize(time)[0]
    dup = pd.Series(time_codes.astype(np.int64) * len(id_uniques) + id_codes).duplicated()
    dup = dup.to_numpy()
    if dup.any():
        row = int(np.flatnonzero(dup)[0])
        raise ValueError(
            f"{where}: tracks has two rows for aircraft {ids[row]!r} at time {time[row]} "
            "(column 'time' must increase for each aircraft)"
        )
    sides = tracks["side"].astype(str).to_numpy()
    roles = tracks["role"].astype(str).to_numpy()
    friendly_role = tracks["role"].isin(FRIENDLY_ROLES).to_numpy()
    bad = ((sides == "friendly") & ~friendly_role) | ((sides == "hostile") & friendly_role)
    if bad.any():
        row = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"{where}: tracks column 'role' has {roles[row]!r} for a {sides[row]} aircraft at "
            f"row {row}"
        )
    per_aircraft = pd.DataFrame({"id": id_codes, "side": sides, "role": roles})
    n_labels = per_aircraft.drop_duplicates().groupby("id").size()
    if (n_labels > 1).any():
        aircraft = id_uniques[n_labels.index[np.flatnonzero(n_labels.to_numpy() > 1)[0]]]
        raise ValueError(
            f"{where}: aircraft {aircraft!r} changes column 'side' or 'role' over time"
        )
    order = np.argsort(id_codes, kind="stable")
    alive_sorted = tracks["alive"].astype(bool).to_numpy()[order]
    same = id_codes[order][1:] == id_codes[order][:-1]
    revived = same & ~alive_sorted[:-1] & alive_sorted[1:]
    if revived.any():
        row = int(order[np.flatnonzero(revived)[0] + 1])
        raise ValueError(
            f"{where}: tracks column 'alive' turns back to True for aircraft {ids[row]!r} at "
            f"time {time[row]} (a destroyed aircraft stays destroyed)"
        )
    if not (sides == "friendly").any():
        raise ValueError(f"{where}: tracks column 'side' has no friendly aircraft")
    if not (roles == "striker").any():
        raise ValueError(f"{where}: tracks column 'role' has no striker aircraft")

    site_ids = sites["site_id"].astype(str).to_numpy()
    check_values(sites, "sites", "site_type", SITE_TYPES, where)
    check_numeric(sites, "sites", _FLOAT_SITE, where)
    if len(set(site_ids)) != len(site_ids):
        raise ValueError(f"{where}: sites column 'site_id' has duplicate values")
    if str(meta["target_id"]) not in set(site_ids[sites["site_type"].astype(str) == "target"]):
        raise ValueError(
            f"{where}: meta['target_id'] {meta['target_id']!r} is not a site of type 'target' "
            "in sites column 'site_id'"
        )
    clash = set(site_ids) & set(ids)
    if clash:
        raise ValueError(
            f"{where}: sites column 'site_id' reuses aircraft id {sorted(clash)[0]!r}"
        )

    if len(weapons):
        check_numeric(weapons, "weapons", _FLOAT_WEAPON, where)
        check_values(weapons, "weapons", "weapon_type", WEAPON_TYPES, where)
        check_values(weapons, "weapons", "outcome", OUTCOMES, where)
        known = np.asarray(sorted(set(ids) | set(site_ids)), dtype=object)
        for col in ("shooter", "target"):
            values = weapons[col].astype(str).to_numpy().astype(object)
            ok = np.isin(values, known)
            if not ok.all():
                row = int(np.flatnonzero(~ok)[0])
                raise ValueError(
                    f"{where}: weapons column {col!r} names unknown aircraft or site "
                    f"{values[row]!r} at row {row}"
                )
        fired = weapons["time_fired"].to_numpy(dtype=float)
        impact = weapons["time_impact"].to_numpy(dtype=float)
        if np.any(impact < fired):
            row = int(np.flatnonzero(impact < fired)[0])
            raise ValueError(
                f"{where}: weapons column 'time_impact' is before 'time_fired' at row {row}"
            )
    return scenario


def check_scenarios(X):
    """Validate a list of raw scenarios; returns a list of :class:`Scenario`.

    Parameters
    ----------
    X : list of Scenario or mapping
        The scenarios.

    Returns
    -------
    scenarios : list of Scenario

    Examples
    --------
    >>> from lfe.scenario import check_scenarios
    >>> check_scenarios([])
    Traceback (most recent call last):
    ...
    ValueError: expected a non-empty list of scenarios, got 0 scenarios
    """
    if isinstance(X, (Scenario, Mapping, pd.DataFrame, str)) or not hasattr(X, "__len__"):
        raise ValueError(
            f"expected a list of scenarios (Scenario objects), got {type(X).__name__}"
        )
    if len(X) == 0:
        raise ValueError("expected a non-empty list of scenarios, got 0 scenarios")
    return [check_scenario(sc, i) for i, sc in enumerate(X)]


# (ids of the scenarios validated by the enclosing checked_once blocks, their memo); outside
# every block: no ids, no memo.
_CHECKED = contextvars.ContextVar("lfe_checked_scenarios", default=(frozenset(), None))


@contextlib.contextmanager
def checked_once(scenarios):
    """Validate scenarios once; inside the block, checking them again and re-deriving is free.

    Simulating and extracting a dataset passes the same scenarios through several validating
    functions (:func:`lfe.annotate_scenarios`, every method of
    :class:`lfe.LFEPropositionExtractor`, :class:`lfe.LFEDataset`), and each used to check
    every table again (about 10 ms a scenario each time) and to rebuild the same per-scenario
    intermediate results (the commander's debrief, the extractor's per-aircraft grid). Code
    that owns the scenarios and does not modify them in between wraps those calls in this
    block: the scenarios are checked on entry; inside the block :func:`check_scenario` returns
    these very objects (the same ``Scenario`` instances, compared by identity) unchecked, and
    :func:`memoised` computes each intermediate result once per scenario; any other scenario is
    checked and computed as usual. Modifying a scenario's tables inside the block is not
    detected, so the block must not do it. The setting is local to the thread (a context
    variable) and ends with the block, which releases the memo.

    Parameters
    ----------
    scenarios : list of Scenario or mapping
        The scenarios, as for :func:`check_scenarios`.

    Yields
    ------
    scenarios : list of Scenario
        The checked scenarios (mappings wrapped in :class:`Scenario`); use these inside the
        block.

    Examples
    --------
    >>> from lfe import ScenarioConfig, simulate_scenario
    >>> from lfe.scenario import check_scenarios, checked_once
    >>> sc = simulate_scenario(ScenarioConfig(n_hostile=4, n_sams=1), random_state=0)
    >>> with checked_once([sc]) as scenarios:
    ...     check_scenarios(scenarios)[0] is sc
    True
    """
    checked = check_scenarios(scenarios)
    ids, memo = _CHECKED.get()
    token = _CHECKED.set((ids | {id(sc) for sc in checked}, {} if memo is None else memo))
    try:
        yield checked  # `checked` keeps them alive, so no other object takes their ids
    finally:
        _CHECKED.reset(token)


def memoised(scenario, key, compute):
    """``compute()``, computed once per scenario and ``key`` inside :func:`checked_once`.

    Outside such a block, or for a scenario the block did not check, it simply returns
    ``compute()``. ``compute`` must be a pure function of the scenario (and of what ``key``
    names), and its result must not be modified by the caller (it is shared).

    Parameters
    ----------
    scenario : Scenario
        The scenario the result derives from.
    key : hashable
        What is computed, with every argument besides the scenario.
    compute : callable
        Computes it, without arguments.

    Returns
    -------
    value : object
    """
    ids, memo = _CHECKED.get()
    if memo is None or id(scenario) not in ids:
        return compute()
    slot = (id(scenario), key)
    if slot not in memo:
        memo[slot] = compute()
    return memo[slot]
