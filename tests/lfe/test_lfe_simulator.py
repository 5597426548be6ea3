"""Simulator invariants, on the default dataset's 24 scenarios and on direct runs."""

import numpy as np
import pandas as pd
import pytest

from lfe import ScenarioConfig, check_scenario, simulate_scenario
from lfe.scenario import TRACK_COLUMNS, WEAPON_COLUMNS


def _deaths(sc):
    """aircraft id -> time of its first row with ``alive`` false."""
    dead = sc.tracks[~sc.tracks["alive"]]
    return dead.groupby("aircraft_id")["time"].min().to_dict()


def test_tables_follow_the_schema(default_dataset):
    for sc in default_dataset.scenarios:
        assert check_scenario(sc) is sc
        assert tuple(sc.tracks.columns) == TRACK_COLUMNS
        assert tuple(sc.weapons.columns) == WEAPON_COLUMNS
        tracks = sc.tracks
        n_aircraft = sc.meta["n_friendly"] + sc.meta["n_hostile"]
        assert tracks["aircraft_id"].nunique() == n_aircraft
        steps = np.unique(tracks["time"].to_numpy())
        np.testing.assert_allclose(np.diff(steps), sc.meta["dt"])
        assert steps[0] == 0.0
        assert (tracks.groupby("time").size() == n_aircraft).all()
        counts = tracks.drop_duplicates("aircraft_id")["role"].value_counts().to_dict()
        assert counts == {"escort": 8, "sead": 8, "striker": 2,
                          "fighter": sc.meta["n_hostile"]}
        assert (sc.sites["site_type"] == "sam").sum() == sc.meta["n_sams"]


def test_dead_aircraft_stay_dead_and_stop_moving(default_dataset):
    n_dead = 0
    for sc in default_dataset.scenarios:
        for name, track in sc.tracks.groupby("aircraft_id"):
            alive = track["alive"].to_numpy()
            assert (np.diff(alive.astype(int)) <= 0).all(), (sc.scenario_id, name)
            if alive.all():
                continue
            n_dead += 1
            after = track[~alive]
            assert (after["flight_phase"] == "destroyed").all()
            assert (after["speed"] == 0.0).all()
            for col in ("x", "y", "altitude", "heading"):
                assert after[col].nunique() == 1, (sc.scenario_id, name, col)
            assert not (track.loc[alive, "flight_phase"] == "destroyed").any()
    assert n_dead > 20  # the dataset has real attrition on both sides


def test_every_kill_has_a_weapon_event(default_dataset):
    for sc in default_dataset.scenarios:
        dt = sc.meta["dt"]
        deaths = _deaths(sc)
        w = sc.weapons
        aircraft = set(sc.tracks["aircraft_id"])
        hits = w[(w["outcome"] == "hit") & w["target"].isin(aircraft)]
        # one killing hit per dead aircraft, landing in the step before it shows as dead
        assert sorted(hits["target"]) == sorted(deaths), sc.scenario_id
        for _, shot in hits.iterrows():
            t = deaths[shot["target"]]
            assert t - dt < shot["time_impact"] <= t + 1e-9
        # nobody fires after being shot down
        for _, shot in w.iterrows():
            assert shot["time_fired"] < deaths.get(shot["shooter"], np.inf)
        # SAM sites: destroyed at most once, silent after the killing hit
        site_hits = w[(w["outcome"] == "hit") & w["target"].str.startswith("sam_")]
        assert site_hits["target"].is_unique
        for _, hit in site_hits.iterrows():
            later = w[(w["shooter"] == hit["target"]) & (w["time_fired"] > hit["time_impact"])]
            assert later.empty


def test_weapons_match_shooters_and_targets(default_dataset):
    for sc in default_dataset.scenarios:
        role = sc.tracks.drop_duplicates("aircraft_id").set_index("aircraft_id")["role"]
        side = sc.tracks.drop_duplicates("aircraft_id").set_index("aircraft_id")["side"]
        w = sc.weapons
        assert (w["time_impact"] >= w["time_fired"]).all()
        assert w["shot_id"].is_unique
        bombs = w[w["weapon_type"] == "bomb"]
        assert (bombs["shooter"].map(role) == "striker").all()
        assert (bombs["target"] == sc.meta["target_id"]).all()
        harms = w[w["weapon_type"] == "harm"]
        assert (harms["shooter"].map(role) == "sead").all()
        assert harms["target"].str.startswith("sam_").all()
        aams = w[w["weapon_type"] == "aam"]
        assert (aams["shooter"].map(side) != aams["target"].map(side)).all()
        sams = w[w["weapon_type"] == "sam"]
        assert (sams["target"].map(side) == "friendly").all()
        assert (bombs.groupby("shooter").size() <= sc.meta["bombs_per_striker"]).all()


def test_attrition_never_decreases(default_dataset, default_traces):
    for sc, trace in zip(default_dataset.scenarios, default_traces):
        lost = (~sc.tracks["alive"]).groupby([sc.tracks["time"], sc.tracks["side"]]).sum()
        lost = lost.unstack("side")
        assert (lost.diff().dropna() >= 0).all().all()
        for col in ("hostile_attrition_50", "hostile_attrition_75", "hostile_attrition_100",
                    "target_hit", "last_munition_released"):
            assert trace[col].is_monotonic_increasing, (sc.scenario_id, col)
        for col in ("friendly_attrition_below_25", "friendly_attrition_below_50",
                    "friendly_attrition_below_75", "strikers_not_fired_upon",
                    "strikers_not_shot_down"):
            assert trace[col].is_monotonic_decreasing, (sc.scenario_id, col)


def test_scenarios_vary(default_dataset):
    hostile = {sc.meta["n_hostile"] for sc in default_dataset.scenarios}
    lengths = {len(sc.tracks) for sc in default_dataset.scenarios}
    assert len(hostile) > 3 and len(lengths) > 10
    # strikers release inside the TOT window in some missions and outside it in others
    inside = []
    for sc in default_dataset.scenarios:
        bombs = sc.weapons[sc.weapons["weapon_type"] == "bomb"]
        inside += list((bombs["time_fired"] >= sc.meta["tot_start"] - 60)
                       & (bombs["time_fired"] <= sc.meta["tot_end"]))
    assert any(inside)


CONFIG = ScenarioConfig(n_hostile=5, n_sams=2)


def test_same_seed_same_tables_different_seed_different():
    a = simulate_scenario(CONFIG, random_state=11)
    b = simulate_scenario(CONFIG, random_state=11)
    c = simulate_scenario(CONFIG, random_state=12)
    assert a == b
    for table in ("tracks", "weapons", "sites"):
        pd.testing.assert_frame_equal(getattr(a, table), getattr(b, table))
    assert a != c
    assert not a.tracks["x"].equals(c.tracks["x"]) or not a.weapons.equals(c.weapons)
    assert a.meta["seed"] == 11 and a.scenario_id == "lfe-11"


def test_drawn_seed_is_stored_and_reproduces():
    a = simulate_scenario(CONFIG, random_state=np.random.RandomState(5), scenario_id="x")
    b = simulate_scenario(CONFIG, random_state=a.meta["seed"], scenario_id="x")
    assert a == b
    assert a.meta["config"] == CONFIG.to_dict()


def test_forces_and_tot_from_config():
    cfg = ScenarioConfig(n_escorts=2, n_sead=0, n_strikers=1, n_hostile=0, n_sams=0,
                         tot_start=600.0, tot_window=120.0, max_duration=1500.0)
    sc = simulate_scenario(cfg, random_state=0)
    assert sc.meta["n_friendly"] == 3 and sc.tracks["aircraft_id"].nunique() == 3
    assert (sc.meta["tot_start"], sc.meta["tot_end"]) == (600.0, 720.0)
    assert sc.duration <= 1500.0 + 300.0 + 2 * cfg.dt
    # nothing shoots at an unopposed package, so nobody is lost
    assert sc.tracks["alive"].all()
    assert set(sc.weapons["weapon_type"]) <= {"bomb"}


@pytest.mark.parametrize("kw, match", [
    ({"n_hostile": -1}, "n_hostile must be >= 0"),
    ({"n_strikers": 0}, "n_strikers must be >= 1"),
    ({"n_escorts": 2.5}, "n_escorts must be an integer"),
    ({"pk_sam": 1.2}, r"pk_sam must be a probability in \[0, 1\]"),
    ({"dt": 0.0}, "dt must be positive"),
    ({"tot_start": float("nan")}, "tot_start must be finite"),
    ({"target_distance": 50.0}, "target_distance must be at least"),
    ({"max_duration": 1000.0}, "max_duration .* must exceed the end of the time-on-target"),
    ({"dt": 0.01}, "dt .* is too small"),
])
def test_bad_config_raises(kw, match):
    with pytest.raises(ValueError, match=match):
        ScenarioConfig(**kw)


def test_bad_simulate_arguments():
    with pytest.raises(ValueError, match="config must be a ScenarioConfig"):
        simulate_scenario({"n_hostile": 4})
    with pytest.raises(ValueError, match="random_state must be in"):
        simulate_scenario(CONFIG, random_state=-3)
