import numpy as np
import pytest

from bsi_sklearn.datasets.tsr import TaskSpaceRegion, make_pose, matrix_to_rpy, rpy_to_matrix

PI = np.pi


def box(x=0.1, y=0.1, z=0.1, roll=0.0, pitch=0.0, yaw=0.0):
    return [[-x, x], [-y, y], [-z, z], [-roll, roll], [-pitch, pitch], [-yaw, yaw]]


def test_rpy_round_trip():
    rng = np.random.default_rng(0)
    rpy = np.column_stack([rng.uniform(-3, 3, 500), rng.uniform(-1.5, 1.5, 500),
                           rng.uniform(-3, 3, 500)])
    np.testing.assert_allclose(matrix_to_rpy(rpy_to_matrix(*rpy.T)), rpy, atol=1e-12)


def test_rpy_convention_is_zyx():
    R = rpy_to_matrix(0.0, 0.0, PI / 2)
    np.testing.assert_allclose(R @ [1, 0, 0], [0, 1, 0], atol=1e-12)
    R = rpy_to_matrix(PI / 2, 0.0, 0.0)
    np.testing.assert_allclose(R @ [0, 1, 0], [0, 0, 1], atol=1e-12)


@pytest.mark.parametrize(
    "x, expected", [(0.0, True), (0.05, True), (0.1, True), (-0.1, True), (0.1 + 1e-6, False),
                    (-0.1 - 1e-6, False), (0.3, False)],
)
def test_translation_bounds(x, expected):
    tsr = TaskSpaceRegion(make_pose([1.0, 2.0, 3.0]), box())
    assert tsr.contains(make_pose([1.0 + x, 2.0, 3.0])) is expected


def test_rotated_frame_translation():
    # TSR frame yawed by 90 degrees: its x axis is the world y axis
    bounds = [[-0.2, 0.2], [-0.05, 0.05], [-0.01, 0.01], [0, 0], [0, 0], [-PI, PI]]
    tsr = TaskSpaceRegion(make_pose([0.0, 0.0, 0.0], [0.0, 0.0, PI / 2]), bounds)
    assert tsr.contains(make_pose([0.0, 0.15, 0.0]))
    assert not tsr.contains(make_pose([0.15, 0.0, 0.0]))
    np.testing.assert_allclose(tsr.displacement(make_pose([0.15, 0.0, 0.0]))[:3],
                               [0.0, -0.15, 0.0], atol=1e-12)


@pytest.mark.parametrize(
    "yaw, expected", [(0.0, True), (0.3, True), (-0.3, True), (0.3 + 1e-6, False),
                      (-0.3 - 1e-6, False), (PI, False)],
)
def test_yaw_bounds(yaw, expected):
    tsr = TaskSpaceRegion(None, box(yaw=0.3))
    assert tsr.contains(make_pose([0, 0, 0], [0, 0, yaw])) is expected


@pytest.mark.parametrize(
    "yaw, expected", [(PI, True), (-PI, True), (-PI + 0.19, True), (PI - 0.19, True),
                      (3 * PI - 0.1, True), (PI - 0.21, False), (-PI + 0.21, False),
                      (0.0, False)],
)
def test_yaw_wrap_around(yaw, expected):
    bounds = box()
    bounds[5] = [PI - 0.2, PI + 0.2]
    tsr = TaskSpaceRegion(None, bounds)
    assert tsr.contains(make_pose([0, 0, 0], [0, 0, yaw])) is expected


def test_rotation_bounds_relative_to_rotated_frame():
    frame = make_pose([0, 0, 0], [0, 0, 1.0])
    tsr = TaskSpaceRegion(frame, box(yaw=0.1, roll=0.05, pitch=0.05))
    assert tsr.contains(make_pose([0, 0, 0], [0, 0, 1.05]))
    assert not tsr.contains(make_pose([0, 0, 0], [0, 0, 0.0]))
    assert tsr.contains(make_pose([0, 0, 0], [0.0, 0.0, 1.0]) @ make_pose([0, 0, 0],
                                                                           [0.04, 0, 0]))
    assert not tsr.contains(make_pose([0, 0, 0], [0, 0, 1.0]) @ make_pose([0, 0, 0],
                                                                          [0.06, 0, 0]))
    assert not tsr.contains(make_pose([0, 0, 0], [0, 0.051, 1.0]))


def test_second_rpy_representation():
    # (pi, pi - 0.2, 0) is the same rotation as (0, 0.2, pi)
    bounds = box()
    bounds[3] = [PI - 0.1, PI + 0.1]
    bounds[4] = [PI - 0.25, PI - 0.15]
    bounds[5] = [-0.1, 0.1]
    tsr = TaskSpaceRegion(None, bounds)
    R = make_pose([0, 0, 0], [PI, PI - 0.2, 0.0])
    np.testing.assert_allclose(R, make_pose([0, 0, 0], [0.0, 0.2, PI]), atol=1e-12)
    assert tsr.contains(R)
    assert not tsr.contains(make_pose([0, 0, 0], [PI, PI - 0.3, 0.0]))


def test_gimbal_lock():
    bounds = box()
    bounds[3] = [0.0, 0.2]
    bounds[4] = [PI / 2 - 0.01, PI / 2 + 0.01]
    bounds[5] = [0.0, 0.2]
    tsr = TaskSpaceRegion(None, bounds)
    assert tsr.contains(make_pose([0, 0, 0], [0.1, PI / 2, 0.05]))
    # same rotation (roll - yaw = 0.05), written with angles outside the bounds
    same = make_pose([0, 0, 0], [0.9, PI / 2, 0.85])
    np.testing.assert_allclose(same, make_pose([0, 0, 0], [0.1, PI / 2, 0.05]), atol=1e-12)
    assert tsr.contains(same)
    # roll - yaw = 0.5 cannot be split into roll, yaw in [0, 0.2]
    assert not tsr.contains(make_pose([0, 0, 0], [0.5, PI / 2, 0.0]))
    # negative lock: roll + yaw is what matters
    bounds[4] = [-PI / 2 - 0.01, -PI / 2 + 0.01]
    tsr = TaskSpaceRegion(None, bounds)
    assert tsr.contains(make_pose([0, 0, 0], [0.3, -PI / 2, 0.0]))  # sum 0.3 = 0.15 + 0.15
    assert not tsr.contains(make_pose([0, 0, 0], [0.5, -PI / 2, 0.0]))


def test_end_effector_offset():
    # Berenson: T0_e = T0_w @ Tw @ Tw_e, so the allowed poses sit Tw_e away from the frame
    Tw_e = make_pose([0, 0, 0.1], [0, 0, PI / 2])
    tsr = TaskSpaceRegion(None, box(x=0.01, y=0.01, z=0.01), Tw_e=Tw_e)
    assert tsr.contains(Tw_e)
    assert tsr.contains(make_pose([0.005, 0, 0.1], [0, 0, PI / 2]))
    assert not tsr.contains(make_pose([0, 0, 0.1]))
    assert not tsr.contains(make_pose([0, 0, 0.0], [0, 0, PI / 2]))


def test_batches_and_infinite_bounds():
    tsr = TaskSpaceRegion(None, [[-np.inf, np.inf], [-0.1, 0.1], [-0.1, 0.1], [0, 0], [0, 0],
                                 [-PI, PI]])
    xyz = np.zeros((5, 3, 3))
    xyz[..., 0] = 1e6
    xyz[2, 1, 1] = 0.5
    out = tsr.contains(make_pose(xyz))
    assert out.shape == (5, 3)
    assert out.sum() == 14 and not out[2, 1]


def test_sample_inside_and_reproducible():
    bounds = box(0.05, 0.02, 0.01, 0.1, 0.1, 0.2)
    bounds[5] = [PI - 0.2, PI + 0.3]
    tsr = TaskSpaceRegion(make_pose([1, 2, 3], [0.3, -0.2, 2.0]), bounds)
    poses = tsr.sample(300, random_state=0)
    assert poses.shape == (300, 4, 4)
    assert tsr.contains(poses).all()
    np.testing.assert_array_equal(poses, tsr.sample(300, random_state=0))
    assert tsr.sample(random_state=1).shape == (4, 4)
    shrunk = bounds.copy()
    shrunk[0] = [0.06, 0.1]
    outside = TaskSpaceRegion(make_pose([1, 2, 3], [0.3, -0.2, 2.0]), shrunk).sample(50, 0)
    assert not tsr.contains(outside).any()


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"Bw": np.zeros((5, 2))}, "Bw must have shape"),
        ({"Bw": [[0, 1]] * 3 + [[0.2, 0.1]] + [[0, 0]] * 2}, "roll"),
        ({"Bw": [[0, 1]] * 5 + [[0, np.inf]]}, "infinite angle"),
        ({"T0_w": np.ones((4, 4))}, "T0_w"),
        ({"Tw_e": np.diag([1.0, 1.0, -1.0, 1.0])}, "Tw_e"),
        ({"atol": -1}, "atol"),
    ],
)
def test_bad_parameters(kwargs, match):
    with pytest.raises(ValueError, match=match):
        TaskSpaceRegion(**kwargs)


def test_bad_poses():
    tsr = TaskSpaceRegion(None, box())
    with pytest.raises(ValueError, match="pose"):
        tsr.contains(np.eye(3))
    bad = np.eye(4)
    bad[0, 0] = 2.0
    with pytest.raises(ValueError, match="rotation"):
        tsr.contains(bad)
    with pytest.raises(ValueError, match="non-finite"):
        tsr.contains(np.full((4, 4), np.nan))
    with pytest.raises(ValueError, match="n must"):
        tsr.sample(0)
