"""lfe.draws: RandomState's stream, uniform and normal rebuilt from its frozen random_sample."""

import platform

import numpy as np
import pytest

from lfe.draws import Draws, normal, uniform

X86 = platform.machine().lower() in {"x86_64", "amd64", "i386", "i686"}


@pytest.mark.skipif(not X86, reason="numpy's C uniform may be fused into a multiply-add here")
def test_uniform_is_randomstates_bit_for_bit():
    ours, numpys = np.random.RandomState(7), np.random.RandomState(7)
    for low, high, size in ((0.0, 1.0, None), (-20, 20, 5), (5, 15, (3, 2)), (30.0, 240.0, 0),
                            (-3.7, 12.1, 1000)):
        a, b = uniform(ours, low, high, size), numpys.uniform(low, high, size)
        np.testing.assert_array_equal(np.asarray(a).view(np.int64), np.asarray(b).view(np.int64))
        assert type(a) is type(b) if size is None else a.shape == b.shape
    assert ours.random_sample() == numpys.random_sample()


def test_normal_follows_randomstates_stream():
    ours, numpys = np.random.RandomState(3), np.random.RandomState(3)
    differ = 0
    for k in range(300):  # odd and even counts, so the cached second value is used too
        size = (None, 1, 2, 3, (2, 3))[k % 5]
        a, b = normal(ours, 1.5, 20.0, size), numpys.normal(1.5, 20.0, size)
        np.testing.assert_allclose(a, b, rtol=1e-14, atol=1e-13)
        differ += int(np.sum(np.asarray(a) != np.asarray(b)))
        if k % 7 == 0:  # interleaved uniform draws stay in step
            assert ours.random_sample() == numpys.random_sample()
    # the same state afterwards, cached value included: numpy's own normal continues it
    assert ours.get_state()[2:4] == numpys.get_state()[2:4]
    np.testing.assert_allclose(ours.normal(), numpys.normal(), rtol=1e-14)
    # only the platform's log can make them differ, and then in the last bits
    assert differ < 300


def test_normal_uses_and_leaves_the_cached_value():
    rs = np.random.RandomState(11)
    first = rs.normal()  # numpy keeps the pair's second value in the RandomState
    assert rs.get_state()[3] == 1
    cached = rs.get_state()[4]
    assert normal(rs, 0.0, 1.0) == cached  # ours returns it first, as numpy would
    assert rs.get_state()[3] == 0
    normal(rs, 0.0, 1.0)
    assert rs.get_state()[3] == 1
    assert first != cached


def test_draws_wraps_one_random_state():
    a, b = Draws(np.random.RandomState(5)), np.random.RandomState(5)
    assert a.uniform(-1.0, 1.0) == uniform(b, -1.0, 1.0)
    assert a.normal(0.0, 2.0, size=3).tolist() == normal(b, 0.0, 2.0, size=3).tolist()
    assert a.random_sample() == b.random_sample()
