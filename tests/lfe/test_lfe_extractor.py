"""`LFEPropositionExtractor` on hand-built scenarios with known proposition timelines."""

import pickle

import numpy as np
import pandas as pd
import pytest
from lfe_build import aircraft, scenario
from sklearn.base import clone
from sklearn.exceptions import NotFittedError
from sklearn.utils.estimator_checks import (
    check_get_params_invariance,
    check_no_attributes_set_in_init,
    check_parameters_default_constructible,
    check_set_params,
)

from lfe import (
    PROPOSITION_DESCRIPTIONS,
    PROPOSITION_SETS,
    LFEPropositionExtractor,
    annotate_scenarios,
    proposition_roles,
)

F, H = "friendly", "hostile"
STRIKE = ((0.0, "marshal"), (10.0, "push"), (50.0, "on_target"), (70.0, "egress"))
ESCORT = ((0.0, "marshal"), (10.0, "push"))


def _fleet():
    """4 friendly (one escort lost at 50 s) and 4 hostile fighters lost at 20/40/60/80 s."""
    return {
        "escort_01": aircraft(F, "escort", phases=ESCORT),
        "escort_02": aircraft(F, "escort", phases=ESCORT, death=50.0),
        "striker_01": aircraft(F, "striker", phases=STRIKE),
        "striker_02": aircraft(F, "striker", phases=STRIKE, y0=2.0),
        "fighter_01": aircraft(H, "fighter", phases=((0.0, "cap"),), death=20.0, x0=200.0,
                               vx=0.0),
        "fighter_02": aircraft(H, "fighter", phases=((0.0, "cap"),), death=40.0, x0=200.0,
                               vx=0.0),
        # parked 25 km east of the strikers' start: within 30 km of them until shot down
        "fighter_03": aircraft(H, "fighter", phases=((0.0, "engage"),), death=60.0, x0=25.0,
                               vx=0.0),
        "fighter_04": aircraft(H, "fighter", phases=((0.0, "cap"),), death=80.0, x0=200.0,
                               vx=0.0),
    }


WEAPONS = [
    ("w1", 10.0, "escort_01", "fighter_01", "aam", 20.0, "hit"),
    ("w2", 30.0, "escort_01", "fighter_02", "aam", 38.0, "hit"),
    # a striker fired upon but not hit
    ("w3", 35.0, "fighter_03", "striker_01", "aam", 42.0, "miss"),
    ("w4", 45.0, "fighter_04", "escort_02", "aam", 50.0, "hit"),
    ("w5", 50.0, "escort_01", "fighter_03", "aam", 60.0, "hit"),
    # munitions released after the TOT window (40-60 s) closed; the second one hits at 75 s
    ("w6", 65.0, "striker_01", "target", "bomb", 95.0, "miss"),
    ("w7", 70.0, "striker_02", "target", "bomb", 75.0, "hit"),
    ("w8", 72.0, "escort_01", "fighter_04", "aam", 80.0, "hit"),
]

ALL = list(range(0, 101, 10))
#: proposition -> grid times (s) where it holds, at the scenario's own 10 s step
EXPECTED = {
    "hostile_attrition_50": [40, 50, 60, 70, 80, 90, 100],
    "hostile_attrition_75": [60, 70, 80, 90, 100],
    "hostile_attrition_100": [80, 90, 100],
    "strikers_not_fired_upon": [0, 10, 20, 30],
    "strikers_not_shot_down": ALL,
    "last_munition_released": [70, 80, 90, 100],
    "strikers_on_target": [50, 60],
    "target_hit": [80, 90, 100],
    "friendly_attrition_below_25": [0, 10, 20, 30, 40],
    "friendly_attrition_below_50": ALL,
    "friendly_attrition_below_75": ALL,
}


def _true_times(trace, column):
    return [int(t) for t in trace.index[trace[column].to_numpy()]]


@pytest.fixture
def hand():
    return scenario(_fleet(), 100.0, WEAPONS)


def test_paper_propositions_known_timeline(hand):
    ext = LFEPropositionExtractor().fit([hand])
    (trace,) = ext.transform([hand])
    assert list(trace.columns) == list(PROPOSITION_SETS["paper"]["columns"])
    assert trace.index.name == "time"
    assert trace.index.tolist() == [float(t) for t in ALL]
    assert all(dtype == np.dtype(bool) for dtype in trace.dtypes)
    for column, times in EXPECTED.items():
        assert _true_times(trace, column) == times, column


def test_coarser_grid_reads_last_state_and_first_event_after(hand):
    (trace,) = LFEPropositionExtractor(time_step=15).fit_transform([hand])
    assert trace.index.tolist() == [0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0]
    # state at 45 s is the 40 s row: two of four fighters down, strikers still pushing
    assert _true_times(trace, "hostile_attrition_50") == [45, 60, 75, 90]
    assert _true_times(trace, "hostile_attrition_100") == [90]
    assert _true_times(trace, "strikers_on_target") == [60]
    # the hit at 75 s counts from the first grid time at or after it
    assert _true_times(trace, "target_hit") == [75, 90]
    assert _true_times(trace, "last_munition_released") == [75, 90]
    assert _true_times(trace, "strikers_not_fired_upon") == [0, 15, 30]


def test_rows_missing_after_death_are_carried_forward(hand):
    sparse = scenario(_fleet(), 100.0, WEAPONS, drop_after_death=True)
    assert len(sparse.tracks) < len(hand.tracks)
    ext = LFEPropositionExtractor().fit([hand])
    dense_trace, sparse_trace = ext.transform([hand, sparse])
    pd.testing.assert_frame_equal(dense_trace, sparse_trace)


def test_striker_shot_down_and_friendly_attrition_thresholds():
    fleet = _fleet()
    fleet["striker_01"] = aircraft(F, "striker", phases=STRIKE, death=30.0)
    fleet["escort_01"] = aircraft(F, "escort", phases=ESCORT, death=90.0)
    weapons = WEAPONS + [("w9", 22.0, "fighter_03", "striker_01", "aam", 30.0, "hit"),
                         ("w10", 85.0, "fighter_04", "escort_01", "aam", 88.0, "hit")]
    (trace,) = LFEPropositionExtractor().fit_transform([scenario(fleet, 100.0, weapons)])
    assert _true_times(trace, "strikers_not_shot_down") == [0, 10, 20]
    assert _true_times(trace, "strikers_not_fired_upon") == [0, 10, 20]
    # 4 friendly: 1 lost at 30 s (25 %), 2 at 50 s (50 %), 3 at 90 s (75 %)
    assert _true_times(trace, "friendly_attrition_below_25") == [0, 10, 20]
    assert _true_times(trace, "friendly_attrition_below_50") == [0, 10, 20, 30, 40]
    assert _true_times(trace, "friendly_attrition_below_75") == [0, 10, 20, 30, 40, 50, 60, 70,
                                                                  80]
    # the dead striker is not on target; the other one is
    assert _true_times(trace, "strikers_on_target") == [50, 60]


def test_no_release_no_hostiles():
    fleet = {k: v for k, v in _fleet().items() if v["side"] == F}
    weapons = [w for w in WEAPONS if w[4] != "bomb" and not w[2].startswith("fighter")
               and not w[3].startswith("fighter")]
    (trace,) = LFEPropositionExtractor().fit_transform([scenario(fleet, 100.0, weapons)])
    # no hostile fighter at all: the attrition subtasks hold from the start
    assert trace["hostile_attrition_100"].all()
    assert not trace["last_munition_released"].any()
    assert not trace["target_hit"].any()
    assert trace["strikers_not_fired_upon"].all()


def test_extended_propositions(hand):
    harm = ("w9", 20.0, "escort_01", "sam_1", "harm", 28.0, "hit")
    sc = scenario(_fleet(), 100.0, WEAPONS + [harm])
    ext = LFEPropositionExtractor(propositions="extended").fit([sc])
    (trace,) = ext.transform([sc])
    assert list(trace.columns) == list(PROPOSITION_SETS["extended"]["columns"])
    for column, times in EXPECTED.items():
        assert _true_times(trace, column) == times, column
    assert _true_times(trace, "escorts_pushed") == ALL[1:]
    assert _true_times(trace, "strikers_pushed") == ALL[1:]
    assert _true_times(trace, "sams_suppressed") == ALL[3:]
    assert _true_times(trace, "tot_window_open") == ALL[4:]
    assert _true_times(trace, "tot_window_closed") == ALL[7:]
    assert _true_times(trace, "strikers_clear_of_fighters") == ALL[6:]
    assert trace["sam_threat_briefed"].all() and trace["light_air_threat_briefed"].all()
    # one of two SAM sites hit: not suppressed; no SAM site: false, not briefed
    two = scenario(_fleet(), 100.0, WEAPONS + [harm], n_sams=2)
    none = scenario(_fleet(), 100.0, WEAPONS, n_sams=0)
    t_two, t_none = ext.transform([two, none])
    assert not t_two["sams_suppressed"].any()
    assert not t_none["sams_suppressed"].any() and not t_none["sam_threat_briefed"].any()
    assert ext.conditions_ == {"sams_suppressed": "sam_threat_briefed",
                               "hostile_attrition_100": "light_air_threat_briefed"}


def test_roles_match_the_paper_sets(hand):
    ext = LFEPropositionExtractor().fit([hand])
    roles = proposition_roles()
    assert ext.global_candidates_ == roles["global_candidates"]
    assert ext.subtasks_ == roles["subtasks"]
    assert ext.conditions_ == roles["conditions"] == {}
    assert set(ext.global_candidates_) == {
        "strikers_not_fired_upon", "strikers_not_shot_down", "friendly_attrition_below_25",
        "friendly_attrition_below_50", "friendly_attrition_below_75"}
    assert set(ext.subtasks_) == {
        "hostile_attrition_50", "hostile_attrition_75", "hostile_attrition_100",
        "last_munition_released", "strikers_on_target", "target_hit"}
    assert ext.n_scenarios_fit_ == 1
    assert list(ext.get_feature_names_out()) == list(ext.feature_names_out_)
    ext_x = LFEPropositionExtractor(propositions="extended").fit([hand])
    assert set(ext_x.get_feature_names_out()) <= set(PROPOSITION_DESCRIPTIONS)
    with pytest.raises(ValueError, match="propositions must be one of"):
        proposition_roles("nope")


def test_flight_phase_features_and_phase_labels(hand):
    ext = LFEPropositionExtractor().fit([hand])
    (feat,) = ext.flight_phase_features([hand])
    assert feat.shape == (11, 40)
    # fractions per role sum to one; three roles present (no SEAD aircraft)
    np.testing.assert_allclose(feat.sum(axis=1), 3.0)
    assert feat.loc[50.0, "striker_on_target"] == 1.0
    assert feat.loc[50.0, "escort_destroyed"] == 0.5
    assert feat["sead_marshal"].eq(0).all()
    labels, phases = annotate_scenarios([hand])
    (y,) = ext.phase_labels([hand], phases)
    row = phases.iloc[0]
    assert row["tot"] == 50.0
    np.testing.assert_array_equal(y, [0, 1, 1, 1, 1, 2, 2, 3, 3, 3, 3])
    (y_arr,) = ext.phase_labels([hand], phases.to_numpy())
    np.testing.assert_array_equal(y, y_arr)
    with pytest.raises(ValueError, match="phases must have shape"):
        ext.phase_labels([hand], [[0, 1, 2]])
    with pytest.raises(ValueError, match="phases is missing column 'egress'"):
        ext.phase_labels([hand], phases.drop(columns="egress"))


# ----------------------------------------------------------------- estimator API


def test_estimator_api(hand):
    ext = LFEPropositionExtractor(time_step=20)
    assert ext.get_params() == {"propositions": "paper", "time_step": 20}
    twin = clone(ext)
    assert twin is not ext and twin.get_params() == ext.get_params()
    assert ext.set_params(propositions="extended") is ext
    assert ext.propositions == "extended"
    with pytest.raises(ValueError, match="Invalid parameter"):
        ext.set_params(step=3)
    with pytest.raises(NotFittedError):
        ext.transform([hand])
    with pytest.raises(NotFittedError):
        ext.get_feature_names_out()
    assert ext.fit([hand]) is ext
    before = hand.tracks.copy()
    expected = ext.transform([hand])[0]
    pd.testing.assert_frame_equal(hand.tracks, before)  # input untouched
    restored = pickle.loads(pickle.dumps(ext))
    pd.testing.assert_frame_equal(restored.transform([hand])[0], expected)
    assert not hasattr(clone(ext), "feature_names_out_")
    assert ext.__sklearn_tags__().requires_fit


@pytest.mark.parametrize("check", [check_get_params_invariance, check_set_params,
                                   check_no_attributes_set_in_init,
                                   check_parameters_default_constructible])
def test_sklearn_checks_that_apply(check):
    check("LFEPropositionExtractor", LFEPropositionExtractor())


@pytest.mark.parametrize("params, match", [
    ({"propositions": "all"}, "propositions must be one of"),
    ({"time_step": 0}, "time_step must be None or a positive number"),
    ({"time_step": -5.0}, "time_step must be None or a positive number"),
    ({"time_step": True}, "time_step must be None or a positive number"),
    ({"time_step": float("nan")}, "time_step must be None or a positive number"),
])
def test_bad_parameters_raise_at_fit(hand, params, match):
    with pytest.raises(ValueError, match=match):
        LFEPropositionExtractor(**params).fit([hand])


def test_fitted_extractor_rechecks_parameters(hand):
    ext = LFEPropositionExtractor().fit([hand])
    ext.set_params(time_step=-1)
    with pytest.raises(ValueError, match="time_step"):
        ext.transform([hand])
