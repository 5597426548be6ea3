"""Bad raw input: ValueError naming the scenario and the column, whoever reads it."""

import numpy as np
import pandas as pd
import pytest
from lfe_build import aircraft, scenario

from lfe import LFEDataset, LFEPropositionExtractor, Scenario, annotate_scenarios
from lfe.scenario import check_scenario, check_scenarios

F, H = "friendly", "hostile"


def _good(scenario_id="bad"):
    fleet = {"escort_01": aircraft(F, "escort"), "striker_01": aircraft(F, "striker"),
             "fighter_01": aircraft(H, "fighter", death=20.0, x0=50.0)}
    shot = ("w1", 5.0, "escort_01", "fighter_01", "aam", 15.0, "hit")
    return scenario(fleet, 40.0, [shot], scenario_id=scenario_id)


def _with(table, frame, sc=None):
    sc = sc or _good()
    parts = {"tracks": sc.tracks, "weapons": sc.weapons, "sites": sc.sites, "meta": sc.meta}
    parts[table] = frame
    return Scenario(parts["tracks"], parts["weapons"], parts["sites"], parts["meta"])


def _tracks(edit):
    """``edit`` changes a copy of good tracks in place, or returns the new frame."""
    t = _good().tracks.copy()
    new = edit(t)
    return _with("tracks", t if new is None else new)


def _set(column, row, value):
    def edit(t):
        if t[column].dtype != object and not isinstance(value, type(t[column].iloc[0])):
            t[column] = t[column].astype(object)
        t.loc[row, column] = value
    return edit


PREFIX = r"scenario 'bad' \(index 1\): "
CASES = {
    "missing tracks column": (
        lambda: _with("tracks", _good().tracks.drop(columns="alive")),
        "tracks is missing column 'alive'"),
    "misspelt tracks column": (
        lambda: _with("tracks", _good().tracks.rename(columns={"heading": "headnig"})),
        "tracks is missing column 'heading'"),
    "misspelt weapons column": (
        lambda: _with("weapons", _good().weapons.rename(columns={"outcome": "result"})),
        "weapons is missing column 'outcome'"),
    "missing sites column": (
        lambda: _with("sites", _good().sites.drop(columns="weapon_range")),
        "sites is missing column 'weapon_range'"),
    "unknown side": (lambda: _tracks(_set("side", 0, "neutral")),
                     "tracks column 'side' has unknown value 'neutral' at row 0"),
    "unknown role": (lambda: _tracks(_set("role", 4, "bomber")),
                     "tracks column 'role' has unknown value 'bomber' at row 4"),
    "role of the other side": (lambda: _tracks(_set("role", 2, "escort")),
                               "tracks column 'role' has 'escort' for a hostile aircraft"),
    "unknown flight phase": (lambda: _tracks(_set("flight_phase", 1, "loiter")),
                             "tracks column 'flight_phase' has unknown value 'loiter'"),
    "non-monotonic time": (lambda: _tracks(_set("time", 4, 0.0)),
                           "tracks column 'time' is not non-decreasing"),
    "repeated time": (lambda: _tracks(lambda t: t.__setitem__("time", 0.0)),
                      r"tracks has two rows for aircraft 'escort_01' at time 0.0 \(column 'time'"),
    "not a number": (lambda: _tracks(_set("x", 3, "far")),
                     "tracks column 'x' has a non-numeric or non-finite value 'far' at row 3"),
    "missing value": (lambda: _tracks(_set("altitude", 5, np.nan)),
                      "tracks column 'altitude' has a non-numeric or non-finite value"),
    "alive not boolean": (lambda: _tracks(_set("alive", 0, "yes")),
                          "tracks column 'alive' must be boolean, got 'yes' at row 0"),
    "revived aircraft": (lambda: _tracks(_set("alive", 14, True)),
                         "tracks column 'alive' turns back to True for aircraft 'fighter_01'"),
    "role changes": (lambda: _tracks(_set("role", 9, "sead")),
                     "aircraft 'escort_01' changes column 'side' or 'role' over time"),
    "no friendly aircraft": (
        lambda: _tracks(lambda t: t[t["side"] != F]),
        "tracks column 'side' has no friendly aircraft"),
    "no striker": (
        lambda: _tracks(lambda t: t[t["role"] != "striker"]),
        "tracks column 'role' has no striker aircraft"),
    "empty tracks": (lambda: _tracks(lambda t: t.iloc[:0]),
                     "tracks is empty .*column 'time'"),
    "unknown shooter": (
        lambda: _with("weapons", _good().weapons.replace({"shooter": {"escort_01": "ghost"}})),
        "weapons column 'shooter' names unknown aircraft or site 'ghost' at row 0"),
    "unknown weapon type": (
        lambda: _with("weapons", _good().weapons.replace({"weapon_type": {"aam": "gun"}})),
        "weapons column 'weapon_type' has unknown value 'gun'"),
    "unknown outcome": (
        lambda: _with("weapons", _good().weapons.replace({"outcome": {"hit": "kill"}})),
        "weapons column 'outcome' has unknown value 'kill'"),
    "impact before firing": (
        lambda: _with("weapons", _good().weapons.assign(time_impact=1.0)),
        "weapons column 'time_impact' is before 'time_fired' at row 0"),
    "unknown site type": (
        lambda: _with("sites", _good().sites.replace({"site_type": {"sam": "radar"}})),
        "sites column 'site_type' has unknown value 'radar'"),
    "duplicate site": (
        lambda: _with("sites", _good().sites.replace({"site_id": {"sam_1": "target"}})),
        "sites column 'site_id' has duplicate values"),
    "target not a site": (
        lambda: _with("meta", {**_good().meta, "target_id": "bridge"}),
        r"meta\['target_id'\] 'bridge' is not a site of type 'target' in sites column"),
    "meta key missing": (
        lambda: _with("meta", {k: v for k, v in _good().meta.items() if k != "dt"}),
        "meta is missing key 'dt'"),
    "meta not a number": (lambda: _with("meta", {**_good().meta, "tot_start": "noon"}),
                          r"meta\['tot_start'\] must be a finite number"),
    "tot reversed": (lambda: _with("meta", {**_good().meta, "tot_end": 10.0}),
                     r"meta\['tot_end'\] \(10.0\) is before meta\['tot_start'\]"),
}


@pytest.fixture(params=sorted(CASES))
def bad(request):
    make, match = CASES[request.param]
    return make(), match


def _readers():
    def annotate(X):
        return annotate_scenarios(X)

    def fit(X):
        return LFEPropositionExtractor().fit(X)

    def transform(X):
        return LFEPropositionExtractor().fit([_good("ok")]).transform(X)

    def dataset(X):
        labels, phases = annotate_scenarios([X[0]])
        return LFEDataset(X, labels, phases)

    return {"check_scenarios": check_scenarios, "annotate": annotate, "fit": fit,
            "transform": transform, "dataset": dataset}


def test_bad_input_names_scenario_and_column(bad):
    sc, match = bad
    for read in _readers().values():
        with pytest.raises(ValueError, match=PREFIX + match):
            read([_good("ok"), sc])


def test_check_scenario_accepts_mappings_and_rejects_other_things():
    sc = _good()
    wrapped = check_scenario({"tracks": sc.tracks, "weapons": sc.weapons, "sites": sc.sites,
                              "meta": sc.meta}, 2)
    assert isinstance(wrapped, Scenario) and wrapped.scenario_id == "bad"
    with pytest.raises(ValueError, match="scenario 2: mapping is missing key 'meta'"):
        check_scenario({"tracks": sc.tracks, "weapons": sc.weapons, "sites": sc.sites}, 2)
    with pytest.raises(ValueError, match="scenario 0: expected a Scenario"):
        check_scenario(sc.tracks)
    with pytest.raises(ValueError, match="tracks must be a pandas DataFrame, got list"):
        check_scenario(_with("tracks", [1, 2]))
    with pytest.raises(ValueError, match="expected a list of scenarios"):
        check_scenarios(sc)
    with pytest.raises(ValueError, match="non-empty list of scenarios"):
        LFEPropositionExtractor().fit([])


def test_checked_once_checks_on_entry_and_skips_only_those_scenarios(monkeypatch):
    import lfe.scenario as scenario_module
    from lfe.scenario import checked_once

    good, bad = _good("ok"), _tracks(_set("x", 0, np.nan))
    with pytest.raises(ValueError, match="non-finite"):  # checked on entry
        with checked_once([good, bad]):
            pass
    calls = []
    real = scenario_module._where
    monkeypatch.setattr(scenario_module, "_where", lambda i, sc: calls.append(sc) or real(i, sc))
    with checked_once([good]) as scenarios:
        assert scenarios[0] is good and calls == [good]
        annotate_scenarios(scenarios)
        LFEPropositionExtractor().fit(scenarios).transform(scenarios)
        assert calls == [good]  # not checked again inside the block
        with pytest.raises(ValueError, match="non-finite"):  # others still are
            check_scenarios([good, bad])
    check_scenarios([good])  # checked again after the block
    assert calls.count(good) == 2


def test_checked_once_memoises_per_scenario_work_without_changing_results(monkeypatch):
    import lfe.extractor as extractor_module
    from lfe.scenario import checked_once

    scenarios = [_good("a"), _good("b")]
    ext = LFEPropositionExtractor().fit(scenarios)
    outside = (annotate_scenarios(scenarios, noise=0.5, random_state=3),
               annotate_scenarios(scenarios), ext.transform(scenarios),
               ext.flight_phase_features(scenarios))
    built = []
    real = extractor_module._State
    monkeypatch.setattr(extractor_module, "_State", lambda sc, step: built.append(sc) or
                        real(sc, step))
    with checked_once(scenarios) as checked:
        inside = (annotate_scenarios(checked, noise=0.5, random_state=3),
                  annotate_scenarios(checked), ext.transform(checked),
                  ext.flight_phase_features(checked))
        ext.phase_labels(checked, inside[1][1])
    assert built == scenarios  # one grid per scenario for every extractor call
    for a, b in zip(outside[:2], inside[:2]):  # flipped verdicts do not leak into the memo
        pd.testing.assert_frame_equal(a[0], b[0])
        pd.testing.assert_frame_equal(a[1], b[1])
    for a, b in zip(outside[2] + outside[3], inside[2] + inside[3]):
        pd.testing.assert_frame_equal(a, b)
