"""Mission-commander debrief: mission-objective verdicts and phase transition times from raw data.

The commander reads the raw tables of a scenario (tracks, weapons, sites, meta), never the
boolean propositions of :class:`lfe.LFEPropositionExtractor`; the two are related, as a real
debrief and a proposition set defined by subject-matter experts are, but not identical.
"""

from __future__ import annotations

from numbers import Integral, Real

import numpy as np
import pandas as pd
from sklearn.utils import check_random_state

from bsi_sklearn.param_validation import Interval, validate_params
from lfe.draws import normal
from lfe.scenario import check_scenarios, memoised

__all__ = [
    "MISSION_OBJECTIVES",
    "PHASE_NAMES",
    "annotate_scenario",
    "annotate_scenarios",
    "phase_labels",
]

#: The three mission objectives of the paper's offensive-counter-air mission.
MISSION_OBJECTIVES = ("MO1", "MO2", "MO3")
#: The four scenario phases, in mission order; the commander marks the time each begins.
PHASE_NAMES = ("escort_push", "strikers_push", "tot", "egress")


_PROBABILITY = [Interval(Real, 0, 1, closed="both")]
_ANNOTATE_CONSTRAINTS = {
    "noise": _PROBABILITY,
    "time_noise": [Interval(Real, 0, None, closed="left")],
    "min_target_hits": [Interval(Integral, 1, None, closed="left")],
    "max_attrition": _PROBABILITY,
    "superiority_fraction": _PROBABILITY,
    "max_air_losses": [Interval(Integral, 0, None, closed="left")],
    "random_state": "no_validation",  # check_random_state
}


def _first_time(times, mask, default):
    idx = np.flatnonzero(mask)
    return float(times[idx[0]]) if len(idx) else float(default)


def _debrief(sc, min_target_hits, max_attrition, superiority_fraction, max_air_losses):
    """Verdicts and transition times of one validated scenario, without judgement noise."""
    tracks, weapons, meta = sc.tracks, sc.weapons, sc.meta
    time = tracks["time"].to_numpy(dtype=float)
    ids = tracks["aircraft_id"].astype(str).to_numpy()
    side = tracks["side"].astype(str).to_numpy()
    role = tracks["role"].astype(str).to_numpy()
    phase = tracks["flight_phase"].astype(str).to_numpy()
    alive = tracks["alive"].astype(bool).to_numpy()
    t_end = float(time[-1])
    tot_start, tot_end = float(meta["tot_start"]), float(meta["tot_end"])

    w_time = weapons["time_fired"].to_numpy(dtype=float)
    w_impact = weapons["time_impact"].to_numpy(dtype=float)
    w_shooter = weapons["shooter"].astype(str).to_numpy()
    w_target = weapons["target"].astype(str).to_numpy()
    w_type = weapons["weapon_type"].astype(str).to_numpy()
    w_hit = weapons["outcome"].astype(str).to_numpy() == "hit"
    aircraft_side = dict(zip(ids, side))
    aircraft_role = dict(zip(ids, role))

    # ----- phase transitions, read off the aircraft's flight phases and the weapon log
    escort = role == "escort"
    escort_push = _first_time(time, escort & (phase != "marshal") & alive, 0.0)
    striker = role == "striker"
    strikers_push = _first_time(time, striker & (phase != "marshal") & alive, escort_push)
    released = np.flatnonzero(
        (w_type == "bomb") & np.array([aircraft_role.get(s) == "striker" for s in w_shooter],
                                      dtype=bool))
    first_release = float(w_time[released].min()) if len(released) else np.inf
    on_target = _first_time(time, striker & (phase == "on_target") & alive, np.inf)
    tot = min(first_release, on_target)
    if not np.isfinite(tot):
        tot = tot_start  # the strike never happened: the commander uses the planned TOT
    tot = max(tot, strikers_push)
    after = time >= tot
    frame = pd.DataFrame({"t": time[after], "off": (~striker[after]) | (~alive[after])
                          | np.isin(phase[after], ("egress", "rtb"))})
    all_off = frame.groupby("t", sort=True)["off"].all()
    egress = float(all_off.index[all_off.to_numpy()][0]) if all_off.any() else t_end

    # ----- MO1: gain and maintain air superiority
    attack = _first_time(time, striker & (phase == "on_target") & alive, tot_start)
    hostile = side == "hostile"
    hostile_ids = np.unique(ids[hostile])
    if len(hostile_ids):
        # Each fighter's last report at or before the attack run: a fighter whose rows stop
        # once shot down is still down; one not reported yet (on the ground) is a threat.
        seen = hostile & (time <= attack + 1e-9)
        last_seen = pd.DataFrame({"id": ids[seen], "out": (~alive[seen])
                                  | (phase[seen] == "withdraw")}).groupby("id")["out"].last()
        gained = int(last_seen.sum()) >= superiority_fraction * len(hostile_ids) - 1e-9
    else:
        gained = True
    air_to_air = (w_type == "aam") & np.array(
        [aircraft_side.get(s) == "hostile" for s in w_shooter], dtype=bool)
    on_friendly = np.array([aircraft_side.get(s) == "friendly" for s in w_target], dtype=bool)
    on_striker = np.array([aircraft_role.get(s) == "striker" for s in w_target], dtype=bool)
    losses_in_strike = air_to_air & on_friendly & w_hit & (w_impact >= strikers_push) & (
        w_impact <= tot_end)
    maintained = losses_in_strike.sum() <= max_air_losses
    strikers_engaged = (air_to_air & on_striker).any()
    mo1 = bool(gained and maintained and not strikers_engaged)

    # ----- MO2: the assigned target destroyed within the TOT window
    on_target_site = w_target == str(meta["target_id"])
    hits_in_window = on_target_site & w_hit & (w_impact >= tot_start) & (w_impact <= tot_end)
    mo2 = bool(hits_in_window.sum() >= min_target_hits)

    # ----- MO3: friendly attrition not above max_attrition
    # An aircraft is lost once any of its rows says so (validation keeps the dead dead), so
    # losses count even when a destroyed aircraft stops being reported.
    friendly = side == "friendly"
    n_friendly = len(np.unique(ids[friendly]))
    lost = len(np.unique(ids[friendly & ~alive]))
    mo3 = bool(lost <= max_attrition * n_friendly + 1e-9)

    verdicts = {"MO1": int(mo1), "MO2": int(mo2), "MO3": int(mo3)}
    times = {"escort_push": escort_push, "strikers_push": strikers_push, "tot": tot,
             "egress": max(egress, tot)}
    return verdicts, times, t_end


def annotate_scenario(scenario, *, noise=0.0, time_noise=0.0, min_target_hits=1,
                      max_attrition=0.25, superiority_fraction=0.5, max_air_losses=1,
                      random_state=None):
    """Debrief one scenario as a mission commander: objective verdicts and phase times.

    The commander works from the raw tables (see :func:`annotate_scenarios` for the rules).

    Parameters
    ----------
    scenario : Scenario
        The raw scenario.
    noise : float, default=0.0
        Probability that the commander's verdict on each objective is the opposite of the
        rule's (judgement noise, drawn independently per objective).
    time_noise : float, default=0.0
        Standard deviation (s) of the Gaussian error on each marked transition time.
    min_target_hits : int, default=1
        Munition hits on the target inside the TOT window needed for MO2.
    max_attrition : float, default=0.25
        Largest acceptable fraction of friendly aircraft lost (MO3).
    superiority_fraction : float, default=0.5
        Fraction of hostile fighters that must be shot down or withdrawing when the strikers
        begin their attack run (MO1).
    max_air_losses : int, default=1
        Friendly aircraft that hostile fighters may shoot down during the strike (MO1).
    random_state : int, RandomState instance or None, default=None
        Source of the judgement and timing noise.

    Returns
    -------
    annotation : dict
        ``"MO1"``, ``"MO2"``, ``"MO3"`` (1 achieved, 0 failed) and the transition times
        ``"escort_push"``, ``"strikers_push"``, ``"tot"``, ``"egress"`` (s).

    Examples
    --------
    >>> from lfe import ScenarioConfig, simulate_scenario
    >>> from lfe.annotate import annotate_scenario
    >>> sc = simulate_scenario(ScenarioConfig(n_hostile=4, n_sams=1), random_state=3)
    >>> a = annotate_scenario(sc)
    >>> sorted(a)
    ['MO1', 'MO2', 'MO3', 'egress', 'escort_push', 'strikers_push', 'tot']
    >>> a["escort_push"] <= a["strikers_push"] <= a["tot"] <= a["egress"]
    True
    """
    labels, phases = annotate_scenarios(
        [scenario], noise=noise, time_noise=time_noise, min_target_hits=min_target_hits,
        max_attrition=max_attrition, superiority_fraction=superiority_fraction,
        max_air_losses=max_air_losses, random_state=random_state)
    out = {k: int(labels.iloc[0][k]) for k in MISSION_OBJECTIVES}
    out.update({k: float(phases.iloc[0][k]) for k in PHASE_NAMES})
    return out


def annotate_scenarios(scenarios, *, noise=0.0, time_noise=0.0, min_target_hits=1,
                       max_attrition=0.25, superiority_fraction=0.5, max_air_losses=1,
                       random_state=None):
    """Debrief scenarios as a mission commander: objective verdicts and phase times.

    The rules read only the raw tables of each scenario:

    **MO1 — gain and maintain air superiority.** Achieved when all three hold:

    1. *gained*: when the strikers begin their attack run (the first track time a live
       striker is ``on_target``; the planned ``meta["tot_start"]`` if that never happens), at
       least ``superiority_fraction`` of the hostile fighters are out of the fight — shot
       down (``alive`` false) or withdrawing (flight phase ``withdraw``); fighters still on
       the ground or not reported yet count as a threat; a scenario without hostile fighters
       passes;
    2. *maintained*: hostile fighters' air-to-air missiles (weapon type ``aam``, outcome
       ``hit``) shoot down at most ``max_air_losses`` friendly aircraft with impact between the
       strikers' push and the close of the TOT window; losses to SAMs do not count against air
       superiority;
    3. *strikers protected*: no hostile fighter ever fires an air-to-air missile at a
       striker (SAM shots at strikers do not count).

    **MO2 — destroy the assigned target within the TOT window.** Achieved when at least
    ``min_target_hits`` weapons aimed at ``meta["target_id"]`` hit it with an impact time in
    ``[tot_start, tot_end]`` (a hit after the window closes, or before it opens, does not
    count).

    **MO3 — friendly attrition should not exceed 25 %.** Achieved when the friendly aircraft
    shot down (a row with ``alive`` false) are at most ``max_attrition`` of all friendly
    aircraft (4 of 18 by default).

    Each aircraft's state at a time is its last row at or before it, so a destroyed aircraft
    whose rows stop counts as destroyed.

    **Phase transitions** (times in s, the start of each phase):

    - *Escort Push*: the first time an escort is out of its ``marshal`` phase;
    - *Strikers Push*: the first time a striker is out of ``marshal``;
    - *TOT*: the first munition release by a striker or the first time a striker is
      ``on_target``, whichever comes first (the planned ``tot_start`` when neither happens);
    - *Egress*: the first time at or after TOT when every striker is shot down or in
      ``egress`` / ``rtb`` (the end of the recording if that never happens).

    *Judgement noise.* Each verdict is flipped with probability ``noise``, and each marked
    time is moved by Gaussian error of standard deviation ``time_noise``, rounded to the
    second, clipped to the recording and sorted so the four phases stay in mission order.

    Parameters
    ----------
    scenarios : list of Scenario
        The raw scenarios.
    noise : float, default=0.0
        Probability of flipping each verdict.
    time_noise : float, default=0.0
        Standard deviation (s) of the error on each transition time.
    min_target_hits : int, default=1
        Hits on the target inside the TOT window needed for MO2.
    max_attrition : float, default=0.25
        Largest acceptable fraction of friendly aircraft lost (MO3).
    superiority_fraction : float, default=0.5
        Fraction of hostile fighters out of the fight at the attack run needed for MO1.
    max_air_losses : int, default=1
        Friendly aircraft hostile fighters may shoot down during the strike (MO1).
    random_state : int, RandomState instance or None, default=None
        Source of the noise (unused when both noises are 0).

    Returns
    -------
    labels : DataFrame
        Index ``scenario_id``, columns ``MO1``, ``MO2``, ``MO3`` (int, 1 achieved, 0 failed).
    phases : DataFrame
        Index ``scenario_id``, columns :data:`PHASE_NAMES` (float, s).

    Examples
    --------
    >>> from lfe import ScenarioConfig, simulate_scenario
    >>> from lfe.annotate import annotate_scenarios
    >>> scs = [simulate_scenario(ScenarioConfig(n_hostile=4, n_sams=1), random_state=s)
    ...        for s in range(2)]
    >>> labels, phases = annotate_scenarios(scs)
    >>> list(labels.columns), list(phases.columns)
    (['MO1', 'MO2', 'MO3'], ['escort_push', 'strikers_push', 'tot', 'egress'])
    >>> labels.shape
    (2, 3)
    """
    validate_params(
        {"noise": noise, "time_noise": time_noise, "min_target_hits": min_target_hits,
         "max_attrition": max_attrition, "superiority_fraction": superiority_fraction,
         "max_air_losses": max_air_losses}, _ANNOTATE_CONSTRAINTS, "annotate_scenarios",
    )
    noise, time_noise = float(noise), float(time_noise)
    max_attrition, superiority_fraction = float(max_attrition), float(superiority_fraction)
    scenarios = check_scenarios(scenarios)
    rng = check_random_state(random_state)
    ids, label_rows, phase_rows = [], [], []
    for sc in scenarios:
        args = (int(min_target_hits), max_attrition, superiority_fraction, int(max_air_losses))
        verdicts, times, t_end = memoised(sc, ("lfe.annotate._debrief", *args),
                                          lambda sc=sc, args=args: _debrief(sc, *args))
        verdicts = dict(verdicts)  # flipped below; the memoised debrief stays as it was
        flips = rng.random_sample(len(MISSION_OBJECTIVES)) < noise if noise > 0 else None
        if flips is not None:
            for k, name in enumerate(MISSION_OBJECTIVES):
                if flips[k]:
                    verdicts[name] = 1 - verdicts[name]
        marks = np.array([times[p] for p in PHASE_NAMES])
        if time_noise > 0:
            marks = marks + normal(rng, 0.0, time_noise, size=len(marks))
            marks = np.sort(np.clip(np.round(marks), 0.0, t_end))
        ids.append(sc.scenario_id)
        label_rows.append([verdicts[m] for m in MISSION_OBJECTIVES])
        phase_rows.append(marks.tolist())
    index = pd.Index(ids, name="scenario_id")
    labels = pd.DataFrame(np.array(label_rows, dtype=np.int64), index=index,
                          columns=list(MISSION_OBJECTIVES))
    phases = pd.DataFrame(np.array(phase_rows, dtype=float), index=index,
                          columns=list(PHASE_NAMES))
    return labels, phases


def phase_labels(times, transitions):
    """Scenario phase (0-3) at each time, from the four marked transition times.

    Phase ``k`` runs from transition ``k`` up to transition ``k + 1``; time before the escort
    push counts as phase 0 (the escort-push phase includes the marshal before it).

    Parameters
    ----------
    times : array-like of float
        Times (s).
    transitions : array-like of 4 floats
        Start times of :data:`PHASE_NAMES`, non-decreasing.

    Returns
    -------
    labels : ndarray of int64, same length as ``times``

    Examples
    --------
    >>> from lfe.annotate import phase_labels
    >>> phase_labels([0, 10, 20, 30, 40, 50], [5, 20, 35, 45]).tolist()
    [0, 0, 1, 1, 2, 3]
    """
    transitions = np.asarray(transitions, dtype=float)
    if transitions.shape != (len(PHASE_NAMES),) or not np.all(np.isfinite(transitions)):
        raise ValueError(
            f"transitions must be {len(PHASE_NAMES)} finite times ({', '.join(PHASE_NAMES)}), "
            f"got {transitions.tolist()!r}"
        )
    if np.any(np.diff(transitions) < 0):
        raise ValueError(
            f"transitions must be non-decreasing ({', '.join(PHASE_NAMES)}), got "
            f"{transitions.tolist()!r}"
        )
    times = np.asarray(times, dtype=float)
    k = np.searchsorted(transitions, times, side="right") - 1
    return np.clip(k, 0, len(PHASE_NAMES) - 1).astype(np.int64)
