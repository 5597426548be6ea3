"""`LFEPropositionExtractor`: raw large-force-exercise scenarios to boolean proposition traces.

The scenarios' per-aircraft state on the output grid is built here; the propositions
themselves (sets, roles, descriptions, definitions) are in :mod:`lfe.propositions`, whose
public names this module re-exports.
"""

from __future__ import annotations

from numbers import Real

import numpy as np
import pandas as pd
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from bsi_sklearn.param_validation import Interval, StrOptions, validate_params
from lfe.annotate import PHASE_NAMES, phase_labels
from lfe.propositions import (
    PROPOSITION_DESCRIPTIONS,
    PROPOSITION_SETS,
    proposition_frame,
    proposition_roles,
)
from lfe.scenario import FLIGHT_PHASES, ROLES, check_scenarios, memoised

__all__ = [
    "LFEPropositionExtractor",
    "PROPOSITION_DESCRIPTIONS",
    "PROPOSITION_SETS",
    "proposition_roles",
]


class LFEPropositionExtractor(TransformerMixin, BaseEstimator, auto_wrap_output_keys=None):
    """Turn raw large-force-exercise scenarios into boolean proposition traces.

    Each scenario becomes one DataFrame: one row per time step of a fixed grid (from the first
    track time, every ``time_step`` seconds, up to the last track time), one boolean column per
    proposition, index ``time`` (s). The state at a grid time is the last recorded track row
    at or before it, and an event (weapon release, impact) counts from the first grid time at
    or after it.

    The paper's propositions (``propositions="paper"``), with their polarity chosen for the
    template ``G(tau) & (pi -> F omega) & (pi_a -> (!omega_b U omega_a))``:

    - ``hostile_attrition_50`` / ``_75`` / ``_100`` (subtasks): at least that fraction of the
      hostile fighters is not alive (true from the start when there is none);
    - ``strikers_not_fired_upon`` (global): no weapon aimed at a striker has been fired yet;
    - ``strikers_not_shot_down`` (global): every striker is alive;
    - ``last_munition_released`` (subtask): true from the strikers' last munition release on
      (false throughout when they released nothing);
    - ``strikers_on_target`` (subtask): a live striker is in the ``on_target`` flight phase
      at this step (not latched);
    - ``target_hit`` (subtask): a weapon has hit ``meta["target_id"]``;
    - ``friendly_attrition_below_25`` / ``_50`` / ``_75`` (globals): the fraction of friendly
      aircraft lost is below that threshold (turns false once it is reached).

    ``propositions="extended"`` adds subtasks ``escorts_pushed`` / ``strikers_pushed`` (an
    escort / striker has left the marshal phase), ``sams_suppressed`` (every SAM site has been
    hit; false when there is none), ``tot_window_open`` (time >= ``tot_start``),
    ``tot_window_closed`` (time > ``tot_end``); the global ``strikers_clear_of_fighters``
    (no live hostile fighter within 30 km of a live striker); and two conditions, constant
    over a scenario, with their subtasks: ``sam_threat_briefed`` (the scenario has SAM sites)
    for ``sams_suppressed``, ``light_air_threat_briefed`` (six hostile fighters or fewer) for
    ``hostile_attrition_100``. With it, "target hit inside the TOT window" is the orders
    ``tot_window_open`` before ``target_hit`` before ``tot_window_closed``.

    Parameters
    ----------
    propositions : {"paper", "extended"}, default="paper"
        The proposition set (see :data:`PROPOSITION_SETS`).
    time_step : float, default=None
        Spacing (s) of the output grid. ``None`` uses each scenario's own step
        (``meta["dt"]``). A coarser step shortens the traces; a phase shorter than the step
        can then fall between two grid times.

    Attributes
    ----------
    feature_names_out_ : ndarray of str
        The proposition names, in column order.
    global_candidates_ : list of str
        Propositions that may be required to hold always (the paper's set T).
    subtasks_ : list of str
        Subtask-completion propositions (the paper's set Omega).
    conditions_ : dict
        Subtask -> condition proposition (empty for the paper's set).
    n_scenarios_fit_ : int
        Number of scenarios seen by ``fit`` (all validated).

    See Also
    --------
    lfe.proposition_roles : the same roles without fitting.
    lfe.annotate_scenarios : the commander's verdicts, from the raw tables.

    Examples
    --------
    >>> from lfe import LFEPropositionExtractor, ScenarioConfig, simulate_scenario
    >>> scs = [simulate_scenario(ScenarioConfig(n_hostile=4, n_sams=1), random_state=s)
    ...        for s in range(2)]
    >>> ext = LFEPropositionExtractor().fit(scs)
    >>> traces = ext.transform(scs)
    >>> traces[0].shape[1], traces[0].dtypes.unique().tolist()
    (11, [dtype('bool')])
    >>> traces[0].index.name
    'time'
    >>> bool(traces[0]["strikers_not_shot_down"].iloc[0])
    True
    """

    def __init__(self, *, propositions="paper", time_step=None):
        self.propositions = propositions
        self.time_step = time_step

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.two_d_array = False
        tags.requires_fit = True
        return tags

    _parameter_constraints = {
        "propositions": [StrOptions(PROPOSITION_SETS)],
        "time_step": [None, Interval(Real, 0, None, closed="neither")],
    }

    def _check_params(self):
        validate_params(self.get_params(deep=False), self._parameter_constraints,
                        type(self).__name__)
        return PROPOSITION_SETS[self.propositions]

    def fit(self, X, y=None):
        """Validate the scenarios and fix the proposition names and roles.

        Parameters
        ----------
        X : list of Scenario
            Raw scenarios.
        y : ignored
            Accepted for pipeline compatibility.

        Returns
        -------
        self : LFEPropositionExtractor
        """
        spec = self._check_params()
        scenarios = check_scenarios(X)
        self.feature_names_out_ = np.asarray(spec["columns"], dtype=object)
        self.global_candidates_ = list(spec["global_candidates"])
        self.subtasks_ = list(spec["subtasks"])
        self.conditions_ = dict(spec["conditions"])
        self.n_scenarios_fit_ = len(scenarios)
        return self

    def transform(self, X):
        """Boolean proposition traces, one DataFrame per scenario.

        Parameters
        ----------
        X : list of Scenario
            Raw scenarios.

        Returns
        -------
        traces : list of DataFrame
            Boolean columns ``feature_names_out_``, index ``time`` (s).
        """
        check_is_fitted(self, "feature_names_out_")
        self._check_params()
        scenarios = check_scenarios(X)
        columns = list(self.feature_names_out_)
        return [proposition_frame(_state(sc, self.time_step), columns) for sc in scenarios]

    def get_feature_names_out(self, input_features=None):
        """Proposition names, in column order.

        Parameters
        ----------
        input_features : ignored
            Accepted for scikit-learn compatibility.

        Returns
        -------
        names : ndarray of str
        """
        check_is_fitted(self, "feature_names_out_")
        return self.feature_names_out_.copy()

    def flight_phase_features(self, X):
        """Per-time-step flight-phase data, on the same grid as :meth:`transform`.

        Column ``f"{role}_{phase}"`` (for every role in :data:`lfe.scenario.ROLES` and every
        phase in :data:`lfe.scenario.FLIGHT_PHASES`) is the fraction of that role's aircraft
        in that flight phase at the step (0 when the scenario has no aircraft of the role).
        These are the "collected flight phase data" the paper's coupled recurrent baselines
        read besides the propositions.

        Parameters
        ----------
        X : list of Scenario
            Raw scenarios.

        Returns
        -------
        features : list of DataFrame
            Float columns, index ``time`` (s), as many rows as the matching trace.

        Examples
        --------
        >>> from lfe import LFEPropositionExtractor, ScenarioConfig, simulate_scenario
        >>> sc = simulate_scenario(ScenarioConfig(n_hostile=4, n_sams=1), random_state=0)
        >>> ext = LFEPropositionExtractor().fit([sc])
        >>> f = ext.flight_phase_features([sc])[0]
        >>> f.shape[1], float(f["striker_marshal"].iloc[0])
        (40, 1.0)
        """
        check_is_fitted(self, "feature_names_out_")
        self._check_params()
        scenarios = check_scenarios(X)
        return [_flight_phases(_state(sc, self.time_step)) for sc in scenarios]

    def phase_labels(self, X, phases):
        """Scenario-phase label (0-3) at every time step of the traces.

        Phase ``k`` of :data:`lfe.annotate.PHASE_NAMES` runs from its marked start to the next
        one; steps before the escort push belong to phase 0.

        Parameters
        ----------
        X : list of Scenario
            Raw scenarios.
        phases : DataFrame or array-like of shape (n_scenarios, 4)
            Transition times (s). A DataFrame indexed by scenario id (as
            ``load_lfe_dataset().phases``) is matched by id; otherwise rows are matched by
            position.

        Returns
        -------
        labels : list of ndarray of int64
            One array per scenario, as long as its trace.

        Examples
        --------
        >>> from lfe import LFEPropositionExtractor, ScenarioConfig, simulate_scenario
        >>> from lfe import annotate_scenarios
        >>> sc = simulate_scenario(ScenarioConfig(n_hostile=4, n_sams=1), random_state=0)
        >>> _, phases = annotate_scenarios([sc])
        >>> ext = LFEPropositionExtractor().fit([sc])
        >>> y = ext.phase_labels([sc], phases)[0]
        >>> len(y) == len(ext.transform([sc])[0]), sorted(set(y.tolist()))
        (True, [0, 1, 2, 3])
        """
        check_is_fitted(self, "feature_names_out_")
        self._check_params()
        scenarios = check_scenarios(X)
        rows = _phase_rows(scenarios, phases)
        out = []
        for sc, row in zip(scenarios, rows):
            state = _state(sc, self.time_step)
            out.append(phase_labels(state.grid, row))
        return out


def _phase_rows(scenarios, phases):
    if isinstance(phases, pd.DataFrame):
        missing = [c for c in PHASE_NAMES if c not in phases.columns]
        if missing:
            raise ValueError(f"phases is missing column {missing[0]!r}")
        index = [str(i) for i in phases.index]
        if all(sc.scenario_id in index for sc in scenarios) and len(set(index)) == len(index):
            frame = phases.set_axis(index)
            return [frame.loc[sc.scenario_id, list(PHASE_NAMES)].to_numpy(dtype=float)
                    for sc in scenarios]
        if len(phases) != len(scenarios):
            absent = next(sc.scenario_id for sc in scenarios if sc.scenario_id not in index)
            raise ValueError(
                f"phases has no row for scenario {absent!r} and {len(phases)} rows for "
                f"{len(scenarios)} scenarios"
            )
        return list(phases[list(PHASE_NAMES)].to_numpy(dtype=float))
    arr = np.asarray(phases, dtype=float)
    if arr.ndim != 2 or arr.shape != (len(scenarios), len(PHASE_NAMES)):
        raise ValueError(
            f"phases must have shape ({len(scenarios)}, {len(PHASE_NAMES)}), got {arr.shape}"
        )
    return list(arr)


def _fill(arr, present, default):
    """Forward-fill ``arr`` along time where not ``present``; leading gaps: back-fill."""
    n_t = arr.shape[0]
    idx = np.where(present, np.arange(n_t)[:, None], -1)
    np.maximum.accumulate(idx, axis=0, out=idx)
    first = np.argmax(present, axis=0)
    idx = np.where(idx < 0, first[None, :], idx)
    out = np.take_along_axis(arr, idx, axis=0)
    never = ~present.any(axis=0)
    if never.any():
        out[:, never] = default
    return out


def _state(sc, time_step):
    """``_State(sc, time_step)``, built once per scenario inside ``checked_once``."""
    return memoised(sc, ("lfe.extractor._State", time_step), lambda: _State(sc, time_step))


class _State:
    """Per-aircraft state of one scenario on the output grid (read-only once built)."""

    def __init__(self, sc, time_step):
        tracks = sc.tracks
        time = tracks["time"].to_numpy(dtype=float)
        ids, uniques = pd.factorize(tracks["aircraft_id"].astype(str), sort=False)
        times_u = np.unique(time)
        ti = np.searchsorted(times_u, time)
        n_t, n_a = len(times_u), len(uniques)
        present = np.zeros((n_t, n_a), dtype=bool)
        present[ti, ids] = True
        alive = np.ones((n_t, n_a), dtype=bool)
        alive[ti, ids] = tracks["alive"].astype(bool).to_numpy()
        phase_codes = pd.Categorical(tracks["flight_phase"].astype(str),
                                     categories=FLIGHT_PHASES).codes
        phase = np.zeros((n_t, n_a), dtype=np.int64)
        phase[ti, ids] = phase_codes
        x = np.zeros((n_t, n_a))
        y = np.zeros((n_t, n_a))
        x[ti, ids] = tracks["x"].to_numpy(dtype=float)
        y[ti, ids] = tracks["y"].to_numpy(dtype=float)

        step = float(sc.meta["dt"]) if time_step is None else float(time_step)
        t0, t1 = float(times_u[0]), float(times_u[-1])
        n_grid = int(np.floor((t1 - t0) / step + 1e-9)) + 1
        self.grid = t0 + step * np.arange(n_grid)
        rows = np.searchsorted(times_u, self.grid + 1e-9, side="right") - 1

        self.alive = _fill(alive, present, True)[rows]
        self.phase = _fill(phase, present, 0)[rows]
        self.x = _fill(x, present, 0.0)[rows]
        self.y = _fill(y, present, 0.0)[rows]
        first = pd.DataFrame({"id": ids, "side": tracks["side"].astype(str).to_numpy(),
                              "role": tracks["role"].astype(str).to_numpy()})
        first = first.drop_duplicates("id").set_index("id").sort_index()
        self.side = first["side"].to_numpy()
        self.role = first["role"].to_numpy()
        self.ids = np.asarray(uniques, dtype=object)
        self.scenario = sc



def _flight_phases(state):
    n_g = len(state.grid)
    data = {}
    for role in ROLES:
        mask = state.role == role
        n = int(mask.sum())
        codes = state.phase[:, mask]
        for k, phase in enumerate(FLIGHT_PHASES):
            data[f"{role}_{phase}"] = ((codes == k).sum(axis=1) / n) if n else np.zeros(n_g)
    return pd.DataFrame(data, index=pd.Index(state.grid, name="time"))
