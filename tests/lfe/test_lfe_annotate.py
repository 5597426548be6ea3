"""The mission commander's rules on hand-built scenarios, one rule at a time."""

import numpy as np
import pytest
from lfe_build import aircraft, scenario

from lfe import MISSION_OBJECTIVES, PHASE_NAMES, annotate_scenario, annotate_scenarios

F, H = "friendly", "hostile"
ESCORT = ((0.0, "marshal"), (10.0, "push"))
STRIKE = ((0.0, "marshal"), (20.0, "push"), (50.0, "on_target"), (70.0, "egress"))
KILL = ("w1", 20.0, "escort_01", "fighter_01", "aam", 28.0, "hit")
BOMB = ("w2", 50.0, "striker_01", "target", "bomb", 55.0, "hit")


def _fleet(**changes):
    """6 escorts, 2 strikers (8 friendly), 2 hostile fighters, fighter_01 down at 30 s."""
    fleet = {f"escort_{k:02d}": aircraft(F, "escort", phases=ESCORT) for k in range(1, 7)}
    fleet["striker_01"] = aircraft(F, "striker", phases=STRIKE)
    fleet["striker_02"] = aircraft(F, "striker", phases=STRIKE, y0=2.0)
    fleet["fighter_01"] = aircraft(H, "fighter", phases=((0.0, "cap"),), death=30.0,
                                   x0=150.0, vx=0.0)
    fleet["fighter_02"] = aircraft(H, "fighter", phases=((0.0, "cap"),), x0=150.0, vx=0.0)
    fleet.update(changes)
    return fleet


def _case(weapons=(KILL, BOMB), scenario_id="hand", **changes):
    return scenario(_fleet(**changes), 100.0, list(weapons), scenario_id=scenario_id,
                    tot=(40.0, 70.0))


def _verdicts(sc, **kw):
    a = annotate_scenario(sc, **kw)
    return tuple(a[m] for m in MISSION_OBJECTIVES)


def _loss(shot_id, shooter, victim, impact, weapon="aam"):
    return (shot_id, impact - 5.0, shooter, victim, weapon, impact, "hit")


def _dead(role, t, phases=ESCORT):
    return aircraft(F, role, phases=phases, death=t)


def test_clean_mission_and_phase_times():
    a = annotate_scenario(_case())
    assert a == {"MO1": 1, "MO2": 1, "MO3": 1, "escort_push": 10.0, "strikers_push": 20.0,
                 "tot": 50.0, "egress": 70.0}


def test_mo1_needs_enough_fighters_out_at_the_attack_run():
    no_kill = _case([BOMB], fighter_01=aircraft(H, "fighter", phases=((0.0, "cap"),)))
    assert _verdicts(no_kill) == (0, 1, 1)
    # a withdrawing fighter is out of the fight, if it withdraws before the attack run
    early = aircraft(H, "fighter", phases=((0.0, "cap"), (40.0, "withdraw")))
    late = aircraft(H, "fighter", phases=((0.0, "cap"), (60.0, "withdraw")))
    assert _verdicts(_case([BOMB], fighter_01=early)) == (1, 1, 1)
    assert _verdicts(_case([BOMB], fighter_01=late)) == (0, 1, 1)
    # one of two fighters down is enough at 50 %, not at 100 %
    assert _verdicts(_case(), superiority_fraction=1.0) == (0, 1, 1)
    assert _verdicts(_case(), superiority_fraction=0.5) == (1, 1, 1)


def test_mo1_tolerates_max_air_losses_during_the_strike():
    losses = [_loss("w3", "fighter_02", "escort_05", 35.0),
              _loss("w4", "fighter_02", "escort_06", 45.0)]
    sc = _case([KILL, BOMB, *losses], escort_05=_dead("escort", 35.0),
               escort_06=_dead("escort", 45.0))
    assert _verdicts(sc) == (0, 1, 1)  # two air-to-air losses; 2 of 8 lost is still 25 %
    assert _verdicts(sc, max_air_losses=2) == (1, 1, 1)
    # a loss before the strikers push does not count against air superiority
    early = [_loss("w3", "fighter_02", "escort_05", 15.0), losses[1]]
    sc = _case([KILL, BOMB, *early], escort_05=_dead("escort", 15.0),
               escort_06=_dead("escort", 45.0))
    assert _verdicts(sc) == (1, 1, 1)
    # nor do losses to SAM sites
    sams = [_loss("w3", "sam_1", "escort_05", 35.0, "sam"),
            _loss("w4", "sam_1", "escort_06", 45.0, "sam")]
    sc = _case([KILL, BOMB, *sams], escort_05=_dead("escort", 35.0),
               escort_06=_dead("escort", 45.0))
    assert _verdicts(sc) == (1, 1, 1)


def test_mo1_fails_when_a_fighter_fires_at_a_striker():
    shot = ("w3", 30.0, "fighter_02", "striker_02", "aam", 36.0, "miss")
    assert _verdicts(_case([KILL, BOMB, shot])) == (0, 1, 1)
    sam_shot = ("w3", 30.0, "sam_1", "striker_02", "sam", 36.0, "miss")
    assert _verdicts(_case([KILL, BOMB, sam_shot])) == (1, 1, 1)


@pytest.mark.parametrize("impact, outcome, expected", [
    (55.0, "hit", 1),
    (70.0, "hit", 1),  # the window is closed at both ends
    (40.0, "hit", 1),
    (75.0, "hit", 0),  # after the window
    (35.0, "hit", 0),  # before it
    (55.0, "miss", 0),
])
def test_mo2_target_hit_inside_the_tot_window(impact, outcome, expected):
    bomb = ("w2", impact - 5.0, "striker_01", "target", "bomb", impact, outcome)
    assert _verdicts(_case([KILL, bomb]))[1] == expected


def test_mo2_min_target_hits():
    second = ("w3", 52.0, "striker_02", "target", "bomb", 60.0, "hit")
    assert _verdicts(_case(), min_target_hits=2)[1] == 0
    assert _verdicts(_case([KILL, BOMB, second]), min_target_hits=2)[1] == 1


def test_mo3_friendly_attrition():
    sams = [_loss(f"w{k}", "sam_1", f"escort_0{k}", 30.0 + 5 * k, "sam") for k in (3, 4, 5)]
    dead = {f"escort_0{k}": _dead("escort", 30.0 + 5 * k) for k in (3, 4, 5)}
    sc = _case([KILL, BOMB, *sams], **dead)  # 3 of 8 lost: 37.5 %
    assert _verdicts(sc) == (1, 1, 0)
    assert _verdicts(sc, max_attrition=0.4) == (1, 1, 1)
    two = _case([KILL, BOMB, *sams[:2]], **dict(list(dead.items())[:2]))  # exactly 25 %
    assert _verdicts(two) == (1, 1, 1)


def test_phase_times_without_a_strike():
    home = ((0.0, "marshal"), (20.0, "push"), (60.0, "egress"))
    sc = _case([KILL], striker_01=aircraft(F, "striker", phases=home),
               striker_02=aircraft(F, "striker", phases=home))
    a = annotate_scenario(sc)
    # no release, never on target: the planned TOT; egress when both turn home
    assert (a["escort_push"], a["strikers_push"], a["tot"], a["egress"]) == (10, 20, 40, 60)
    assert a["MO2"] == 0


def test_tot_is_the_first_release_or_attack_run_and_egress_counts_losses():
    early = ("w2", 45.0, "striker_01", "target", "bomb", 55.0, "hit")
    assert annotate_scenario(_case([KILL, early]))["tot"] == 45.0
    sc = _case([KILL, BOMB], striker_02=_dead("striker", 60.0, STRIKE),
               striker_01=aircraft(F, "striker", phases=STRIKE[:3] + ((80.0, "rtb"),)))
    assert annotate_scenario(sc)["egress"] == 80.0


def test_judgement_noise_flips_verdicts_reproducibly():
    scs = [_case(scenario_id=f"h{k:02d}") for k in range(30)]
    exact, _ = annotate_scenarios(scs)
    assert (exact.to_numpy() == 1).all()
    flipped, _ = annotate_scenarios(scs, noise=1.0)
    assert (flipped.to_numpy() == 0).all()
    a, _ = annotate_scenarios(scs, noise=0.5, random_state=3)
    b, _ = annotate_scenarios(scs, noise=0.5, random_state=3)
    c, _ = annotate_scenarios(scs, noise=0.5, random_state=4)
    assert a.equals(b)
    assert not a.equals(c)
    assert 0.3 < 1 - a.to_numpy().mean() < 0.7
    assert a.index.tolist() == [sc.scenario_id for sc in scs]


def test_time_noise_keeps_phases_ordered_and_reproducible():
    scs = [_case(scenario_id=f"h{k:02d}") for k in range(10)]
    _, exact = annotate_scenarios(scs)
    _, a = annotate_scenarios(scs, time_noise=30.0, random_state=0)
    _, b = annotate_scenarios(scs, time_noise=30.0, random_state=0)
    assert a.equals(b)
    assert list(a.columns) == list(PHASE_NAMES)
    marks = a.to_numpy()
    assert not np.array_equal(marks, exact.to_numpy())
    assert (np.diff(marks, axis=1) >= 0).all()
    assert ((marks >= 0) & (marks <= 100.0)).all()
    np.testing.assert_array_equal(marks, np.round(marks))


@pytest.mark.parametrize("kw, match", [
    ({"noise": 1.5}, "noise must be a number in"),
    ({"noise": True}, "noise must be a number in"),
    ({"time_noise": -1.0}, "time_noise must be a finite number >= 0"),
    ({"time_noise": float("inf")}, "time_noise must be a finite number >= 0"),
    ({"max_attrition": 2.0}, "max_attrition must be a number in"),
    ({"superiority_fraction": -0.1}, "superiority_fraction must be a number in"),
    ({"max_air_losses": -1}, "max_air_losses must be an integer >= 0"),
    ({"max_air_losses": 1.5}, "max_air_losses must be an integer >= 0"),
    ({"min_target_hits": 0}, "min_target_hits must be an integer >= 1"),
])
def test_bad_parameters_raise(kw, match):
    with pytest.raises(ValueError, match=match):
        annotate_scenarios([_case()], **kw)


def test_aircraft_that_stop_reporting_once_destroyed():
    """Raw data may drop a destroyed aircraft's rows: the verdicts must not change."""
    sams = [_loss(f"w{k}", "sam_1", f"escort_0{k}", 30.0 + 5 * k, "sam") for k in (3, 4, 5)]
    dead = {f"escort_0{k}": _dead("escort", 30.0 + 5 * k) for k in (3, 4, 5)}
    fleet = _fleet(**dead)
    full = scenario(fleet, 100.0, [KILL, BOMB, *sams], tot=(40.0, 70.0))
    sparse = scenario(fleet, 100.0, [KILL, BOMB, *sams], tot=(40.0, 70.0),
                      drop_after_death=True)
    assert len(sparse.tracks) < len(full.tracks)
    assert annotate_scenario(full) == annotate_scenario(sparse)
    assert _verdicts(sparse) == (1, 1, 0)  # fighter_01 down at the attack run; 3 of 8 lost
    # a fighter first reported after the attack run (scrambled late) is still a threat
    late = aircraft(H, "fighter", phases=((0.0, "cap"),), x0=150.0, vx=0.0)
    sc = _case(fighter_02=late)
    tracks = sc.tracks[~((sc.tracks["aircraft_id"] == "fighter_02")
                         & (sc.tracks["time"] < 60.0))].reset_index(drop=True)
    sc.tracks = tracks
    assert _verdicts(sc, superiority_fraction=0.6) == (0, 1, 1)
    assert _verdicts(sc, superiority_fraction=0.5) == (1, 1, 1)


def test_simulated_scenarios_without_rows_after_death(default_dataset):
    """Dropping every destroyed aircraft's later rows changes neither reader's output."""
    from lfe import LFEPropositionExtractor, Scenario

    full = default_dataset.scenarios[:6]
    sparse = []
    for sc in full:
        t = sc.tracks
        dead_before = t.groupby("aircraft_id")["alive"].transform(
            lambda a: (~a).cumsum().shift(fill_value=0) > 0)
        sparse.append(Scenario(t[~dead_before].reset_index(drop=True), sc.weapons, sc.sites,
                               sc.meta))
    assert sum(len(sc.tracks) for sc in sparse) < sum(len(sc.tracks) for sc in full)
    a_labels, a_phases = annotate_scenarios(full)
    b_labels, b_phases = annotate_scenarios(sparse)
    assert a_labels.equals(b_labels) and a_phases.equals(b_phases)
    ext = LFEPropositionExtractor().fit(full)
    for x, y in zip(ext.transform(full), ext.transform(sparse)):
        assert x.equals(y)
