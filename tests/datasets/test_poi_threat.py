import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
import pytest

from bsi_sklearn.data.roles import resolve_roles
from bsi_sklearn.data.traces import check_traces
from bsi_sklearn.datasets import (
    make_poi_threat_demos,
    plot_demos,
    poi_threat_labels,
    poi_threat_specification,
)
from bsi_sklearn.specification import Specification


# ---------------------------------------------------------------- labelling functions
def test_labels_hand_made_trajectory():
    threats = [[5.0, 5.0], [9.0, 9.0]]
    pois = [[2.0, 2.0], [5.0, 5.5], [8.0, 9.0]]  # POI 2 and 3 lie in threat zones
    path = [
        [0.0, 0.0],  # far from everything
        [2.0, 2.4],  # exactly on POI 1's tolerance boundary
        [2.0, 2.41],  # just outside it
        [5.0, 4.0],  # exactly on threat 1's boundary: still outside the zone
        [5.0, 4.01],  # just inside threat 1's zone
        [5.0, 5.5],  # on POI 2, inside threat 1
    ]
    trace = poi_threat_labels(path, threats, pois, threat_radius=1.0, poi_radius=0.4)
    assert list(trace.columns) == ["tau_1", "tau_2", "omega_1", "omega_2", "omega_3",
                                   "pi_1", "pi_2", "pi_3"]
    expected = np.array([
        # tau1 tau2 om1 om2 om3 pi1 pi2 pi3
        [1, 1, 0, 0, 0, 1, 0, 0],
        [1, 1, 1, 0, 0, 1, 0, 0],
        [1, 1, 0, 0, 0, 1, 0, 0],
        [1, 1, 0, 0, 0, 1, 0, 0],
        [0, 1, 0, 0, 0, 1, 0, 0],
        [0, 1, 0, 1, 0, 1, 0, 0],
    ], dtype=bool)
    np.testing.assert_array_equal(trace.to_numpy(), expected)
    assert trace.dtypes.eq(bool).all()


def test_accessibility_boundary():
    # POI exactly at the threat radius is inaccessible (<=), just beyond is accessible
    trace = poi_threat_labels([[0, 0]], [[5.0, 5.0]], [[5.0, 6.0], [5.0, 6.001]])
    assert trace[["pi_1", "pi_2"]].iloc[0].tolist() == [False, True]


def test_labels_ignore_heading_column_and_no_threats():
    trace = poi_threat_labels([[1.0, 1.0, 0.3]], np.empty((0, 2)), [[1.0, 1.2]])
    assert list(trace.columns) == ["omega_1", "pi_1"]
    assert trace.iloc[0].tolist() == [True, True]


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"positions": [0, 0, 0]}, "positions"),
        ({"positions": np.empty((0, 2))}, "positions"),
        ({"threat_positions": [[1, 2, 3]]}, "threat_positions"),
        ({"poi_positions": [[np.nan, 1]]}, "poi_positions"),
        ({"threat_radius": 0}, "threat_radius"),
        ({"poi_radius": -1}, "poi_radius"),
    ],
)
def test_labels_bad_input(kwargs, match):
    args = {"positions": [[0, 0]], "threat_positions": [[1, 1]], "poi_positions": [[2, 2]]}
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        poi_threat_labels(**args)


# ---------------------------------------------------------------- ground truths
def test_scenario_specifications():
    s1, s2, s3 = (poi_threat_specification(k) for k in (1, 2, 3))
    om = [f"omega_{i}" for i in range(1, 6)]
    assert s1.globals == {f"tau_{i}" for i in range(1, 6)}
    assert s1.eventuals == set(om[:4])
    assert s1.orders == {(om[a], om[b]) for a in range(4) for b in range(a + 1, 4)}
    assert s2.orders == {(om[0], om[2]), (om[2], om[4]), (om[0], om[4])}
    assert s3.orders == frozenset()
    assert (s1.n_conjuncts, s2.n_conjuncts, s3.n_conjuncts) == (15, 13, 10)
    assert s2.conditions == {w: w.replace("omega", "pi") for w in om}
    with pytest.raises(ValueError, match="scenario"):
        poi_threat_specification(4)


# ---------------------------------------------------------------- generator
@pytest.fixture(scope="module", params=[1, 2, 3])
def demos(request):
    return make_poi_threat_demos(request.param, n_demos=40, n_negative=30, random_state=7)


def test_positives_satisfy_negatives_violate(demos):
    spec = demos.specification
    for trace, y in zip(demos.traces, demos.labels, strict=True):
        assert spec.satisfied_by(trace) == bool(y)
    assert demos.labels.tolist() == [1] * 40 + [0] * 30
    assert all(v == "" for v in demos.violations[:40])
    assert set(demos.violations[40:]) <= {"threat", "skip", "order"}


def test_structure_and_roles(demos):
    names = demos.feature_names
    n_pois = len(demos.poi_positions)
    assert len(names) == 5 + 2 * n_pois
    for trace, traj, threats in zip(demos.traces, demos.trajectories,
                                    demos.threat_positions, strict=True):
        assert isinstance(trace, pd.DataFrame)
        assert list(trace.columns) == names
        assert len(trace) == len(traj) >= 1
        assert threats.shape == (5, 2)
    roles = resolve_roles(demos.roles["global_candidates"], demos.roles["subtasks"],
                          demos.roles["conditions"], len(names), names)
    assert roles.condition_names() == demos.specification.conditions
    assert set(demos.roles["global_candidates"]) == demos.specification.globals
    traces = check_traces(demos.traces)
    assert traces.n_demos == len(demos.traces)


def test_traces_are_the_labelling_of_the_trajectories(demos):
    for i in range(0, len(demos.traces), 7):
        again = poi_threat_labels(demos.trajectories[i], demos.threat_positions[i],
                                  demos.poi_positions, threat_radius=demos.threat_radius,
                                  poi_radius=demos.poi_radius)
        pd.testing.assert_frame_equal(again, demos.traces[i])
        pis = demos.traces[i][[f"pi_{k + 1}" for k in range(len(demos.poi_positions))]]
        assert (pis.nunique() == 1).all()  # conditions hold constant
        np.testing.assert_array_equal(pis.iloc[0].to_numpy(), demos.accessible[i])


def test_dubins_dynamics(demos):
    for traj in demos.trajectories:
        step = np.linalg.norm(np.diff(traj[:, :2], axis=0), axis=1)
        np.testing.assert_allclose(step, 0.15, rtol=1e-9)
        turn = np.diff(traj[:, 2])
        assert np.all(np.abs(turn) <= 0.6 + 1e-12)
        heading = np.arctan2(np.diff(traj[:, 1]), np.diff(traj[:, 0]))
        wrapped = (heading - traj[1:, 2] + np.pi) % (2 * np.pi) - np.pi
        np.testing.assert_allclose(wrapped, 0.0, atol=1e-9)


def _first_visits(trace, n_pois):
    firsts = {}
    for k in range(1, n_pois + 1):
        col = trace[f"omega_{k}"].to_numpy()
        if col.any():
            firsts[k] = int(np.argmax(col))
    return firsts


def test_positives_visit_accessible_pois_in_planned_order(demos):
    n_pois = len(demos.poi_positions)
    for i in np.flatnonzero(demos.labels == 1):
        firsts = _first_visits(demos.traces[i], n_pois)
        plan = demos.visit_orders[i]
        assert sorted(plan) == [k + 1 for k in np.flatnonzero(demos.accessible[i])]
        assert sorted(firsts, key=firsts.get) == plan


def test_negative_kinds_break_what_they_say(demos):
    spec = demos.specification
    n_pois = len(demos.poi_positions)
    for i in np.flatnonzero(demos.labels == 0):
        trace, kind = demos.traces[i], demos.violations[i]
        if kind == "threat":
            assert not trace[sorted(spec.globals)].to_numpy().all()
        elif kind == "skip":
            missed = [k for k in range(1, n_pois + 1) if demos.accessible[i][k - 1]
                      and not trace[f"omega_{k}"].any()]
            assert missed
        else:
            firsts = _first_visits(trace, n_pois)
            broken = []
            for a, b in spec.orders:
                ia, ib = int(a.split("_")[1]), int(b.split("_")[1])
                if demos.accessible[i][ia - 1] and ib in firsts:
                    broken.append(ia not in firsts or firsts[ib] < firsts[ia])
            assert any(broken)


@pytest.mark.parametrize("kind", ["threat", "skip", "order"])
def test_single_negative_kind(kind):
    data = make_poi_threat_demos(2, n_demos=0, n_negative=6, negative_kinds=[kind],
                                 random_state=3)
    assert data.violations == [kind] * 6
    assert not any(data.specification.satisfied_by(t) for t in data.traces)


def test_scenario3_has_no_order_negatives():
    with pytest.raises(RuntimeError, match="negative"):
        make_poi_threat_demos(3, n_demos=0, n_negative=1, negative_kinds="order",
                              max_tries=5, random_state=0)


def test_reproducible():
    a = make_poi_threat_demos(2, n_demos=5, n_negative=3, random_state=11)
    b = make_poi_threat_demos(2, n_demos=5, n_negative=3, random_state=np.random.RandomState(11))
    c = make_poi_threat_demos(2, n_demos=5, n_negative=3, random_state=12)
    for ta, tb in zip(a.trajectories, b.trajectories, strict=True):
        np.testing.assert_array_equal(ta, tb)
    assert a.violations == b.violations
    assert any(len(ta) != len(tc) or not np.array_equal(ta, tc)
               for ta, tc in zip(a.trajectories, c.trajectories, strict=True))


def test_custom_specification():
    spec = Specification(globals=["tau_1", "tau_2"], eventuals=["omega_2"],
                         orders=[("omega_4", "omega_2")])
    data = make_poi_threat_demos(spec, n_demos=10, n_negative=6, random_state=0)
    truth = data.specification
    assert truth.conditions == {"omega_2": "pi_2", "omega_4": "pi_4"}
    assert truth.globals == spec.globals and truth.orders == spec.orders
    for t, y in zip(data.traces, data.labels, strict=True):
        assert truth.satisfied_by(t) == bool(y)
    # the agent only visits what the specification requires (omega_2 and its predecessor)
    assert all(set(v) <= {2, 4} for v in data.visit_orders[:10])


def test_custom_layout():
    pois = [[2.0, 5.0], [8.0, 5.0], [5.0, 9.0]]
    spec = Specification(eventuals=["omega_1", "omega_2", "omega_3"],
                         orders=[("omega_3", "omega_1")])
    data = make_poi_threat_demos(spec, n_demos=5, n_threats=3, poi_positions=pois,
                                 random_state=0)
    assert data.feature_names == ["tau_1", "tau_2", "tau_3", "omega_1", "omega_2", "omega_3",
                                  "pi_1", "pi_2", "pi_3"]
    assert all(data.specification.satisfied_by(t) for t in data.traces)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"scenario": 0}, "scenario"),
        ({"scenario": "1"}, "scenario"),
        ({"scenario": 1.0}, "scenario"),
        ({"start": (1.0, 2.0, 3.0)}, "start"),
        ({"n_demos": -1}, "n_demos"),
        ({"n_demos": 2.5}, "n_demos"),
        ({"n_demos": 0, "n_negative": 0}, "n_negative"),
        ({"n_negative": -2}, "n_negative"),
        ({"n_threats": 0}, "n_threats"),
        ({"threat_radius": -1.0}, "threat_radius"),
        ({"poi_radius": 0.1}, "poi_radius"),
        ({"speed": 0.0}, "speed"),
        ({"max_turn_rate": 3.0}, "max_turn_rate"),
        ({"max_turn_rate": 0.2}, "max_turn_rate"),
        ({"start": (11.0, 0.0)}, "start"),
        ({"poi_positions": [[1.0, 1.0]]}, "poi_positions"),
        ({"poi_positions": [[1.0, 1.0, 1.0]] * 4}, "poi_positions"),
        ({"poi_positions": [[20.0, 1.0]] * 4}, "poi_positions"),
        ({"negative_kinds": ["collide"], "n_negative": 1}, "negative_kinds"),
        ({"negative_kinds": [], "n_negative": 1}, "negative_kinds"),
        ({"max_tries": 0}, "max_tries"),
        ({"scenario": Specification(globals=["tau_9"])}, "tau_9"),
        ({"scenario": Specification(eventuals=["omega_6"])}, "omega_6"),
        ({"scenario": Specification(eventuals=["pi_1"])}, "pi_1"),
    ],
)
def test_bad_parameters(kwargs, match):
    with pytest.raises(ValueError, match=match):
        make_poi_threat_demos(**{"n_demos": 1, "random_state": 0, **kwargs})


def test_plot_demos(demos):
    import matplotlib.pyplot as plt

    axes = plot_demos(demos, indices=[0, 45], ncols=2)
    assert len(axes) == 2
    assert len(axes[0].patches) == 5 + len(demos.poi_positions)
    assert "negative" in axes[1].get_title()
    fig, ax = plt.subplots()
    assert plot_demos(demos, indices=3, ax=ax)[0] is ax
    with pytest.raises(ValueError, match="indices"):
        plot_demos(demos, indices=[1000])
    plt.close("all")


def test_plot_demos_rejects_other_objects():
    with pytest.raises(ValueError, match="data"):
        plot_demos({"traces": []})
