import numpy as np
import pandas as pd
import pytest

from bsi_sklearn.data.roles import resolve_roles
from bsi_sklearn.data.traces import check_traces
from bsi_sklearn.datasets import (
    dinner_table_labels,
    dinner_table_specification,
    dinner_table_tsrs,
    make_dinner_table_demos,
    make_pose,
)
from bsi_sklearn.datasets.dinner_table import MEALS, PIECES, STACK

TABLE = 0.75


def _targets_pose():
    """Every piece exactly at its TSR frame (the ideal placement)."""
    tsrs = dinner_table_tsrs()
    return np.stack([tsrs[p].T0_w for p in PIECES])[None]


def _rest_wrists():
    return make_pose([[[-0.3, -0.62, 0.95], [0.3, -0.62, 0.95]]])


# ---------------------------------------------------------------- labelling functions
def test_labels_ideal_placement_and_conditions():
    trace = dinner_table_labels(_targets_pose(), _rest_wrists(), ["fork", "mug"])
    assert list(trace.columns) == (["tau_c"] + [f"omega_{p}" for p in PIECES]
                                   + [f"pi_{p}" for p in PIECES])
    row = trace.iloc[0]
    assert row["tau_c"]
    assert all(row[f"omega_{p}"] for p in PIECES)
    assert [row[f"pi_{p}"] for p in PIECES] == [p in ("fork", "mug") for p in PIECES]
    needed = np.array([p == "bowl" for p in PIECES])
    assert dinner_table_labels(_targets_pose(), _rest_wrists(), needed)["pi_bowl"].all()


def test_labels_misplaced_and_rotated_pieces():
    tsrs = dinner_table_tsrs()
    poses = np.repeat(_targets_pose(), 5, axis=0)
    k_fork, k_plate, k_mug = PIECES.index("fork"), PIECES.index("dinner_plate"), \
        PIECES.index("mug")
    shift = make_pose([0.031, 0.0, 0.0])  # fork's x tolerance is 0.03
    poses[1, k_fork] = tsrs["fork"].T0_w @ shift
    poses[2, k_fork] = tsrs["fork"].T0_w @ make_pose([0, 0, 0], [0, 0, np.pi])  # reversed
    poses[3, k_plate] = tsrs["dinner_plate"].T0_w @ make_pose([0, 0, 0.02], [0, 0, 2.5])
    poses[4, k_mug] = tsrs["mug"].T0_w @ make_pose([0, 0, 0], [0, 0, 0.59])
    poses[4, k_plate] = tsrs["dinner_plate"].T0_w @ make_pose([0, 0, 0], [0.2, 0, 0])  # tilted
    trace = dinner_table_labels(poses, np.repeat(_rest_wrists(), 5, axis=0), PIECES)
    assert trace["omega_fork"].tolist() == [True, False, False, True, True]
    assert trace["omega_dinner_plate"].tolist() == [True, True, True, True, False]
    assert trace["omega_mug"].all()  # 0.59 rad is within the mug's 0.6 rad yaw tolerance


def test_labels_centerpiece():
    wrists = np.repeat(_rest_wrists(), 4, axis=0)
    wrists[1, 0] = make_pose([0.0, 0.24, 0.9])  # left wrist over the centerpiece
    wrists[2, 1] = make_pose([0.13, 0.24, TABLE + 0.35], [1.0, 2.0, 3.0])  # corner, rotated
    wrists[3, 1] = make_pose([0.1301, 0.24, 0.9])  # just outside
    trace = dinner_table_labels(np.repeat(_targets_pose(), 4, axis=0), wrists, [])
    assert trace["tau_c"].tolist() == [True, False, False, True]


@pytest.mark.parametrize(
    "args, match",
    [
        ((np.zeros((3, 7, 4, 4)), np.zeros((3, 2, 4, 4)), []), "object_poses"),
        ((np.zeros((3, 8, 4, 4)), np.zeros((2, 2, 4, 4)), []), "wrist_poses"),
        ((np.tile(np.eye(4), (1, 8, 1, 1)), np.tile(np.eye(4), (1, 2, 1, 1)), ["plate"]),
         "plate"),
        ((np.tile(np.eye(4), (1, 8, 1, 1)), np.tile(np.eye(4), (1, 2, 1, 1)),
          np.ones(3, bool)), "needed"),
    ],
)
def test_labels_bad_input(args, match):
    with pytest.raises(ValueError, match=match):
        dinner_table_labels(*args)


def test_ground_truth():
    spec = dinner_table_specification()
    assert spec.globals == {"tau_c"}
    assert spec.eventuals == {f"omega_{p}" for p in PIECES}
    assert spec.orders == {("omega_dinner_plate", "omega_small_plate"),
                           ("omega_small_plate", "omega_bowl"),
                           ("omega_dinner_plate", "omega_bowl")}
    assert spec.n_conjuncts == 12


# ---------------------------------------------------------------- generator
@pytest.fixture(scope="module")
def demos():
    return make_dinner_table_demos(random_state=0, n_negative=24)


def test_default_size_and_labels(demos):
    assert len(demos.traces) == 71 + 24
    assert demos.labels.tolist() == [1] * 71 + [0] * 24
    spec = demos.specification
    for trace, y in zip(demos.traces, demos.labels, strict=True):
        assert spec.satisfied_by(trace) == bool(y)
    assert set(demos.violations[71:]) <= {"centerpiece", "skip", "misplace", "order"}
    assert len(set(demos.violations[71:])) == 4


def test_participants_and_meals(demos):
    assert sorted(set(demos.participants)) == [1, 2, 3, 4, 5, 6]
    for meal in MEALS:
        per = {p for p, m in zip(demos.participants[:71], demos.meals[:71], strict=True)
               if m == meal}
        assert per == {1, 2, 3, 4, 5, 6}  # every participant serves every meal
    counts = pd.Series(list(zip(demos.participants[:71], demos.meals[:71], strict=True)))
    assert counts.value_counts().min() >= 2  # several demonstrations each


def test_structure_roles_and_poses(demos):
    names = demos.feature_names
    assert len(names) == 17
    roles = resolve_roles(demos.roles["global_candidates"], demos.roles["subtasks"],
                          demos.roles["conditions"], len(names), names)
    assert roles.condition_names() == demos.specification.conditions
    assert check_traces(demos.traces).n_demos == len(demos.traces)
    for i in range(0, len(demos.traces), 9):
        obj, wr, t = demos.object_poses[i], demos.wrist_poses[i], demos.times[i]
        assert obj.shape == (len(t), 8, 4, 4) and wr.shape == (len(t), 2, 4, 4)
        np.testing.assert_allclose(np.diff(t), 0.1)
        R = wr[..., :3, :3]
        np.testing.assert_allclose(np.einsum("...ki,...kj->...ij", R, R), np.broadcast_to(
            np.eye(3), R.shape), atol=1e-9)
        speed = np.linalg.norm(np.diff(wr[..., :3, 3], axis=0), axis=-1) / 0.1
        assert speed.max() < 3.0  # metres per second: human-like
        again = dinner_table_labels(obj, wr, MEALS[demos.meals[i]])
        pd.testing.assert_frame_equal(again, demos.traces[i])


def test_conditions_follow_the_meal_and_unneeded_pieces_stay(demos):
    for i in range(71):
        trace, meal = demos.traces[i], demos.meals[i]
        for k, p in enumerate(PIECES):
            assert trace[f"pi_{p}"].nunique() == 1
            assert trace[f"pi_{p}"].iloc[0] == (p in MEALS[meal])
            if p not in MEALS[meal]:
                assert not trace[f"omega_{p}"].any()
                xyz = demos.object_poses[i][:, k, :3, 3]
                assert np.ptp(xyz, axis=0).max() < 0.02  # only tracking noise
            else:
                assert trace[f"omega_{p}"].iloc[-1]  # placed and left in place


def _first(trace, piece):
    col = trace[f"omega_{piece}"].to_numpy()
    return int(np.argmax(col)) if col.any() else None


def test_positive_placements_and_stacking(demos):
    for i in range(71):
        trace, placed = demos.traces[i], demos.placements[i]
        assert sorted(placed) == sorted(MEALS[demos.meals[i]])
        firsts = [_first(trace, p) for p in placed]
        assert firsts == sorted(firsts)
        stack = [p for p in placed if p in STACK]
        assert stack == [p for p in STACK if p in stack]


def test_carried_piece_follows_the_wrist(demos):
    obj, wr = demos.object_poses[0], demos.wrist_poses[0]
    placed = demos.placements[0][0]
    k = PIECES.index(placed)
    moving = np.linalg.norm(np.diff(obj[:, k, :3, 3], axis=0), axis=1) > 0.01
    assert moving.any()
    t = np.flatnonzero(moving)[len(np.flatnonzero(moving)) // 2]
    gaps = np.linalg.norm(wr[t, :, :3, 3] - obj[t, k, :3, 3], axis=1)
    assert gaps.min() == pytest.approx(0.07, abs=0.01)


def test_fork_before_spoon_habit(demos):
    both = [pl for pl in demos.placements[:71] if "fork" in pl and "spoon" in pl]
    before = sum(pl.index("fork") < pl.index("spoon") for pl in both)
    assert 0.6 * len(both) <= before < len(both)  # a strong habit with a few exceptions


@pytest.mark.parametrize("kind", ["centerpiece", "skip", "misplace", "order"])
def test_negative_kinds(kind):
    data = make_dinner_table_demos(0, n_negative=8, negative_kinds=kind, random_state=5)
    assert data.violations == [kind] * 8
    spec = data.specification
    for i, trace in enumerate(data.traces):
        assert not spec.satisfied_by(trace)
        needed = MEALS[data.meals[i]]
        if kind == "centerpiece":
            assert not trace["tau_c"].all()
        else:
            assert trace["tau_c"].all()
        if kind in ("skip", "misplace"):
            assert any(not trace[f"omega_{p}"].any() for p in needed)
        if kind == "order":
            firsts = {p: _first(trace, p) for p in STACK if p in needed}
            stack = sorted(firsts, key=firsts.get)
            assert stack != [p for p in STACK if p in needed]


def test_order_negatives_skip_meals_without_two_stack_pieces():
    data = make_dinner_table_demos(0, n_negative=6, negative_kinds="order", random_state=0)
    assert all(sum(p in STACK for p in MEALS[m]) >= 2 for m in data.meals)


def test_reproducible():
    a = make_dinner_table_demos(6, n_negative=2, random_state=3)
    b = make_dinner_table_demos(6, n_negative=2, random_state=3)
    c = make_dinner_table_demos(6, n_negative=2, random_state=4)
    for x, y in zip(a.wrist_poses, b.wrist_poses, strict=True):
        np.testing.assert_array_equal(x, y)
    assert a.violations == b.violations
    assert not np.array_equal(a.wrist_poses[0], c.wrist_poses[0])


def test_sampling_rate():
    data = make_dinner_table_demos(1, sampling_rate=30.0, random_state=0)
    np.testing.assert_allclose(np.diff(data.times[0]), 1 / 30)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"n_demos": -1}, "n_demos"),
        ({"n_demos": 1.5}, "n_demos"),
        ({"n_demos": 0}, "n_negative"),
        ({"n_negative": -1}, "n_negative"),
        ({"negative_kinds": ["spill"], "n_negative": 1}, "negative_kinds"),
        ({"negative_kinds": [], "n_negative": 1}, "negative_kinds"),
        ({"sampling_rate": 0}, "sampling_rate"),
        ({"sampling_rate": "10"}, "sampling_rate"),
        ({"max_tries": 0}, "max_tries"),
    ],
)
def test_bad_parameters(kwargs, match):
    with pytest.raises(ValueError, match=match):
        make_dinner_table_demos(**{"random_state": 0, **kwargs})


def test_plot_dinner_demos(demos):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from bsi_sklearn.datasets import plot_demos

    axes = plot_demos(demos, indices=[0, 80])
    assert len(axes) == 2
    assert len(axes[0].patches) == 2 + 9  # table, side table, 8 pieces + centerpiece
    assert len(axes[0].lines) == 3
    assert "negative" in axes[1].get_title()
    plt.close("all")
