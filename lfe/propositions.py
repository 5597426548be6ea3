"""The LFE propositions: the sets, their roles, their descriptions and how each is computed.

The catalogue :class:`lfe.LFEPropositionExtractor` reads: :data:`PROPOSITION_SETS` (the
paper's eleven propositions and the extended set), :data:`PROPOSITION_DESCRIPTIONS` (a
commander's words for each), :func:`proposition_roles` (the roles of a set, before any fit)
and :func:`proposition_frame` (the truth of each proposition at every step of a scenario's
grid, from the extractor's per-aircraft state). A new proposition is added here, in all four.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from bsi_sklearn.param_validation import StrOptions, validate_params
from lfe.detmath import hypot
from lfe.scenario import FLIGHT_PHASES

__all__ = [
    "PROPOSITION_DESCRIPTIONS",
    "PROPOSITION_SETS",
    "proposition_frame",
    "proposition_roles",
]

_PAPER_GLOBALS = (
    "strikers_not_fired_upon",
    "strikers_not_shot_down",
    "friendly_attrition_below_25",
    "friendly_attrition_below_50",
    "friendly_attrition_below_75",
)
_PAPER_SUBTASKS = (
    "hostile_attrition_50",
    "hostile_attrition_75",
    "hostile_attrition_100",
    "last_munition_released",
    "strikers_on_target",
    "target_hit",
)
_PAPER_ORDER = (
    "hostile_attrition_50",
    "hostile_attrition_75",
    "hostile_attrition_100",
    "strikers_not_fired_upon",
    "strikers_not_shot_down",
    "last_munition_released",
    "strikers_on_target",
    "target_hit",
    "friendly_attrition_below_25",
    "friendly_attrition_below_50",
    "friendly_attrition_below_75",
)
_EXTRA_SUBTASKS = (
    "escorts_pushed",
    "strikers_pushed",
    "sams_suppressed",
    "tot_window_open",
    "tot_window_closed",
)
_EXTRA_GLOBALS = ("strikers_clear_of_fighters",)
_EXTRA_CONDITIONS = {
    "sams_suppressed": "sam_threat_briefed",
    "hostile_attrition_100": "light_air_threat_briefed",
}

#: The proposition sets: ``"paper"`` is the paper's eleven propositions (its sets T and
#: Omega); ``"extended"`` adds push, SAM-suppression and TOT-window subtasks, a global on
#: hostile fighters near the strikers, and two briefing conditions.
PROPOSITION_SETS = {
    "paper": {
        "columns": _PAPER_ORDER,
        "global_candidates": _PAPER_GLOBALS,
        "subtasks": _PAPER_SUBTASKS,
        "conditions": {},
    },
    "extended": {
        "columns": (_PAPER_ORDER + _EXTRA_SUBTASKS + _EXTRA_GLOBALS
                    + tuple(_EXTRA_CONDITIONS.values())),
        "global_candidates": _PAPER_GLOBALS + _EXTRA_GLOBALS,
        "subtasks": _PAPER_SUBTASKS + _EXTRA_SUBTASKS,
        "conditions": _EXTRA_CONDITIONS,
    },
}

#: A short present-tense phrase per proposition, in a mission commander's words (for
#: :func:`bsi_sklearn.report.explain`).
PROPOSITION_DESCRIPTIONS = {
    "hostile_attrition_50": "at least half of the hostile fighters have been shot down",
    "hostile_attrition_75": "at least 75% of the hostile fighters have been shot down",
    "hostile_attrition_100": "every hostile fighter has been shot down",
    "strikers_not_fired_upon": "no weapon has been fired at the strikers",
    "strikers_not_shot_down": "no striker has been shot down",
    "last_munition_released": "the strikers have released their last munition",
    "strikers_on_target": "a striker is flying its attack run (on-target phase)",
    "target_hit": "the assigned target has been hit",
    "friendly_attrition_below_25": "friendly losses are below 25% of the package",
    "friendly_attrition_below_50": "friendly losses are below 50% of the package",
    "friendly_attrition_below_75": "friendly losses are below 75% of the package",
    "escorts_pushed": "the escorts have pushed",
    "strikers_pushed": "the strikers have pushed",
    "sams_suppressed": "every SAM site has been destroyed",
    "tot_window_open": "the time-on-target window has opened",
    "tot_window_closed": "the time-on-target window has closed",
    "strikers_clear_of_fighters": "no hostile fighter is within 30 km of a striker",
    "sam_threat_briefed": "SAM sites were briefed",
    "light_air_threat_briefed": "a light air threat (six fighters or fewer) was briefed",
}

_LIGHT_AIR_THREAT = 6
_CLEAR_RADIUS = 30.0  # km


def proposition_roles(propositions="paper"):
    """Proposition roles for :class:`bsi_sklearn.BSIClassifier`, before any fit.

    Parameters
    ----------
    propositions : {"paper", "extended"}, default="paper"
        The proposition set (see :data:`PROPOSITION_SETS`).

    Returns
    -------
    roles : dict
        ``global_candidates`` (list), ``subtasks`` (list) and ``conditions`` (dict), ready to
        pass as ``BSIClassifier(**roles)``.

    Examples
    --------
    >>> from lfe import proposition_roles
    >>> roles = proposition_roles()
    >>> roles["global_candidates"][:2]
    ['strikers_not_fired_upon', 'strikers_not_shot_down']
    >>> len(roles["subtasks"]), roles["conditions"]
    (6, {})
    """
    spec = _proposition_set(propositions, "proposition_roles")
    return {
        "global_candidates": list(spec["global_candidates"]),
        "subtasks": list(spec["subtasks"]),
        "conditions": dict(spec["conditions"]),
    }


def _proposition_set(propositions, caller):
    validate_params({"propositions": propositions},
                    {"propositions": [StrOptions(PROPOSITION_SETS)]}, caller)
    return PROPOSITION_SETS[propositions]


def _event_time(values, mask, reduce):
    values = values[mask]
    if not len(values):
        return np.inf
    return float(reduce(values))


def proposition_frame(state, columns):
    """The propositions ``columns`` of one scenario on its output grid, as a boolean frame.

    ``state`` is the extractor's per-aircraft state of the scenario on the grid: ``grid``
    (times, s), ``scenario``, per aircraft ``ids``, ``side`` and ``role``, and per grid time
    and aircraft ``alive``, ``phase`` (codes of :data:`lfe.scenario.FLIGHT_PHASES`), ``x``
    and ``y`` (km). The frame's index is ``time``.
    """
    sc = state.scenario
    g = state.grid
    meta = sc.meta
    weapons, sites = sc.weapons, sc.sites
    friendly = state.side == "friendly"
    hostile = state.side == "hostile"
    strikers = state.role == "striker"
    striker_ids = set(state.ids[strikers])
    alive = state.alive

    n_f, n_h = int(friendly.sum()), int(hostile.sum())
    friendly_loss = (~alive[:, friendly]).sum(axis=1) / n_f
    hostile_loss = (~alive[:, hostile]).sum(axis=1) / n_h if n_h else np.ones(len(g))

    w_fired = weapons["time_fired"].to_numpy(dtype=float)
    w_impact = weapons["time_impact"].to_numpy(dtype=float)
    w_shooter = weapons["shooter"].astype(str).to_numpy()
    w_target = weapons["target"].astype(str).to_numpy()
    w_type = weapons["weapon_type"].astype(str).to_numpy()
    w_hit = weapons["outcome"].astype(str).to_numpy() == "hit"
    at_striker = np.isin(w_target, list(striker_ids))
    by_striker = np.isin(w_shooter, list(striker_ids)) & (w_type == "bomb")
    t_fired_upon = _event_time(w_fired, at_striker, np.min)
    t_last_release = _event_time(w_fired, by_striker, np.max)
    t_target_hit = _event_time(w_impact, (w_target == str(meta["target_id"])) & w_hit, np.min)
    on_target = FLIGHT_PHASES.index("on_target")

    out = {
        "hostile_attrition_50": hostile_loss >= 0.5 - 1e-12,
        "hostile_attrition_75": hostile_loss >= 0.75 - 1e-12,
        "hostile_attrition_100": hostile_loss >= 1.0 - 1e-12,
        "strikers_not_fired_upon": g < t_fired_upon,
        "strikers_not_shot_down": alive[:, strikers].all(axis=1),
        "last_munition_released": g >= t_last_release,
        "strikers_on_target": ((state.phase[:, strikers] == on_target)
                               & alive[:, strikers]).any(axis=1),
        "target_hit": g >= t_target_hit,
        "friendly_attrition_below_25": friendly_loss < 0.25 - 1e-12,
        "friendly_attrition_below_50": friendly_loss < 0.50 - 1e-12,
        "friendly_attrition_below_75": friendly_loss < 0.75 - 1e-12,
    }
    if len(columns) > len(out):
        marshal = FLIGHT_PHASES.index("marshal")
        for name, role in (("escorts_pushed", "escort"), ("strikers_pushed", "striker")):
            mask = state.role == role
            left = ((state.phase[:, mask] != marshal) & alive[:, mask]).any(axis=1)
            out[name] = np.logical_or.accumulate(left) if len(left) else left
        sam_ids = sites["site_id"].astype(str).to_numpy()[
            sites["site_type"].astype(str).to_numpy() == "sam"]
        if len(sam_ids):
            first_hits = [_event_time(w_impact, (w_target == s) & w_hit, np.min)
                          for s in sam_ids]
            out["sams_suppressed"] = g >= max(first_hits)
        else:
            out["sams_suppressed"] = np.zeros(len(g), dtype=bool)
        out["tot_window_open"] = g >= float(meta["tot_start"])
        out["tot_window_closed"] = g > float(meta["tot_end"])
        live_s = alive[:, strikers]
        live_h = alive[:, hostile]
        dx = state.x[:, strikers, None] - state.x[:, None, hostile]
        dy = state.y[:, strikers, None] - state.y[:, None, hostile]
        near = (hypot(dx, dy) <= _CLEAR_RADIUS) & live_s[:, :, None] & live_h[:, None, :]
        out["strikers_clear_of_fighters"] = ~near.any(axis=(1, 2))
        out["sam_threat_briefed"] = np.full(len(g), len(sam_ids) > 0)
        out["light_air_threat_briefed"] = np.full(len(g), n_h <= _LIGHT_AIR_THREAT)
    frame = pd.DataFrame({c: np.asarray(out[c], dtype=bool) for c in columns},
                         index=pd.Index(g, name="time"))
    return frame
