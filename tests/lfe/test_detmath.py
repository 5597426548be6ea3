"""lfe.detmath: accurate against numpy, exact at the special values, the same bits everywhere."""

import math
import re
import struct
from pathlib import Path

import numpy as np
import pytest

from lfe import detmath
from lfe.detmath import atan2, cos, hypot, log, sin, sincos

INF, NAN = math.inf, math.nan
RNG = np.random.default_rng(20261202)


def _ulps(got, ref):
    """|got - ref| in units of the last place of ref (0 where both are the same NaN / inf)."""
    got, ref = np.asarray(got, dtype=float), np.asarray(ref, dtype=float)
    with np.errstate(invalid="ignore"):
        same = (got == ref) | (np.isnan(got) & np.isnan(ref))
        err = np.abs(got - ref) / np.spacing(np.maximum(np.abs(ref), np.finfo(float).tiny))
    return np.where(same, 0.0, err)


def _bits(a):
    return np.ascontiguousarray(a, dtype=np.float64).view(np.int64)


def test_constants_match_their_bit_patterns():
    # every fdlibm constant is written in decimal with its bits in a comment: they must agree
    source = Path(detmath.__file__).read_text(encoding="utf-8")
    pairs = re.findall(r"([-+]?\d\.\d+e[-+]\d+)[,)]*\s*#[^\n]*?0x([0-9A-F]{8}) ([0-9A-F]{8})",
                       source)
    assert len(pairs) >= 40
    for text, hi, lo in pairs:
        bits = struct.unpack(">Q", struct.pack(">d", float(text)))[0]
        assert f"{bits:016X}" == hi + lo, text


@pytest.mark.parametrize("scale", [1.0, 10.0, 1e3, 1e6, 1e9, 1e15, 1e100, 1e300])
def test_sin_cos_within_one_ulp_of_numpy(scale):
    x = RNG.uniform(-scale, scale, 5000)
    s, c = sincos(x)
    # numpy's own sin / cos are within an ulp of the truth; ours too: 2 ulps apart at most
    assert _ulps(s, np.sin(x)).max() <= 2
    assert _ulps(c, np.cos(x)).max() <= 2
    np.testing.assert_array_equal(s, sin(x))
    np.testing.assert_array_equal(c, cos(x))


def test_sin_cos_near_multiples_of_half_pi():
    # arguments whose reduction cancels many bits: k * pi/2 rounded to a double, and neighbours
    k = np.arange(-2000, 2001, dtype=float)
    x = np.concatenate([k * (np.pi / 2), np.nextafter(k * (np.pi / 2), INF),
                        np.nextafter(k * (np.pi / 2), -INF)])
    s, c = sincos(x)
    assert np.abs(s - np.sin(x)).max() < 1e-15
    assert np.abs(c - np.cos(x)).max() < 1e-15


def test_sin_cos_special_values():
    assert math.copysign(1.0, sin(-0.0)) == -1.0 and sin(-0.0) == 0.0
    assert math.copysign(1.0, sin(0.0)) == 1.0
    assert cos(0.0) == cos(-0.0) == 1.0
    for tiny in (5e-324, -5e-324, 1e-310, 1e-20):
        assert sin(tiny) == tiny and cos(tiny) == 1.0
    for bad in (INF, -INF, NAN):
        assert math.isnan(sin(bad)) and math.isnan(cos(bad))
    x = np.array([0.0, -0.0, INF, -INF, NAN, 5e-324])
    s, c = sincos(x)
    np.testing.assert_array_equal(np.signbit(s[:2]), [False, True])
    assert np.isnan(s[2:5]).all() and np.isnan(c[2:5]).all()
    # quadrants
    for q, (s_ref, c_ref) in enumerate(((1.0, 0.0), (0.0, -1.0), (-1.0, 0.0), (0.0, 1.0))):
        s, c = sincos((q + 1) * math.pi / 2)
        assert abs(s - s_ref) < 1e-15 and abs(c - c_ref) < 1e-15


def test_sin_cos_of_huge_arguments_are_reduced_exactly():
    # sin(1e22) is a classic test of argument reduction: -0.8522008497671888017727...
    assert sin(1e22) == -0.8522008497671888
    for x in (1647098.9, 1647099.0, 1e7, 2.0**60, 1e200, 2.0**1023, np.finfo(float).max):
        assert _ulps(sin(x), np.sin(x)) <= 2 and _ulps(cos(x), np.cos(x)) <= 2
        assert sin(-x) == -sin(x) and cos(-x) == cos(x)


def test_atan2_within_one_ulp_of_numpy_in_every_quadrant():
    y = RNG.normal(size=20000) * np.exp(RNG.uniform(-50, 50, 20000))
    x = RNG.normal(size=20000) * np.exp(RNG.uniform(-50, 50, 20000))
    got = atan2(y, x)
    assert _ulps(got, np.arctan2(y, x)).max() <= 2
    for sy in (1, -1):
        for sx in (1, -1):
            a = atan2(sy * np.abs(y), sx * np.abs(x))
            assert np.all(np.sign(a) == sy)
            half = np.pi / 2  # |y/x| beyond 2**53 rounds to pi/2 on either side
            assert np.all(np.abs(a) <= half) if sx > 0 else np.all(np.abs(a) >= half)


SPECIAL = [0.0, -0.0, 1.0, -1.0, 3.5, -2.0, INF, -INF, NAN, 5e-324, -5e-324, 1e-310, 1e308,
           -1e308, 2.0**60, 2.0**-60, 1e-300]


def test_atan2_special_values_are_numpys():
    ys, xs = np.meshgrid(SPECIAL, SPECIAL)
    ys, xs = ys.ravel(), xs.ravel()
    with np.errstate(all="ignore"):
        ref = np.arctan2(ys, xs)
    got = atan2(ys, xs)
    assert _ulps(got, ref).max() <= 2
    finite = ~np.isnan(ref)
    np.testing.assert_array_equal(np.signbit(got[finite]), np.signbit(ref[finite]))
    assert atan2(0.0, 0.0) == 0.0 and not math.copysign(1.0, atan2(0.0, 0.0)) < 0
    assert atan2(-0.0, 0.0) == 0.0 and math.copysign(1.0, atan2(-0.0, 0.0)) < 0
    assert atan2(0.0, -0.0) == math.pi and atan2(-0.0, -0.0) == -math.pi
    assert atan2(1.0, 0.0) == math.pi / 2 and atan2(-1.0, -0.0) == -math.pi / 2
    assert atan2(INF, -INF) == 3 * math.pi / 4 and atan2(-INF, INF) == -math.pi / 4
    assert math.isnan(atan2(NAN, 1.0)) and math.isnan(atan2(1.0, NAN))


def test_log_and_hypot_against_numpy():
    v = np.exp(RNG.uniform(-700, 700, 5000))
    assert _ulps(log(v), np.log(v)).max() <= 2
    u = RNG.uniform(0, 1, 5000)
    assert _ulps(log(u), np.log(u)).max() <= 2
    with np.errstate(all="ignore"):
        special = np.array([0.0, -0.0, -1.0, INF, -INF, NAN, 1.0, 5e-324])
        np.testing.assert_array_equal(log(special), np.log(special))
    assert log(0.0) == -INF and math.isnan(log(-1.0)) and log(1.0) == 0.0
    dx, dy = RNG.uniform(-300, 300, (2, 5000))
    assert _ulps(hypot(dx, dy), np.hypot(dx, dy)).max() <= 2
    assert hypot(3.0, 4.0) == 5.0 and hypot(-0.0, 0.0) == 0.0


def test_scalars_give_python_floats():
    for value in (sin(1.0), cos(np.float64(1.0)), atan2(1.0, 2.0), log(2.0), hypot(1, 2)):
        assert type(value) is float
    assert sincos(np.array([1.0, 2.0]))[0].dtype == np.float64


@pytest.mark.parametrize("func", ["sin", "cos", "atan2", "log", "hypot"])
def test_same_bits_alone_or_in_arrays_of_any_length_and_alignment(func):
    # one value alone (a Python float), and the same value at every position of arrays of
    # every length (both sides of the scalar-path threshold), contiguous, strided, 2-D and
    # misaligned (numpy's SIMD loops take other paths for these): always the same bits
    values = np.concatenate([RNG.uniform(-400, 400, 150), RNG.uniform(0.5, 2.5, 50),
                             [0.0, -0.0, 1e-300, 1e7, 3e9]])
    if func == "log":
        values = np.abs(values) + 1e-3
    other = values[::-1].copy()
    two = func in ("atan2", "hypot")

    def call(a, b=None):
        f = getattr(detmath, func)
        return f(a, b) if two else f(a)

    alone = np.array([call(float(a), float(b)) for a, b in zip(values, other)])
    for n in (1, 2, 3, 7, 8, 16, 31, 63, 64, 65, 100, len(values)):
        np.testing.assert_array_equal(_bits(call(values[:n], other[:n])), _bits(alone[:n]))
        np.testing.assert_array_equal(_bits(call(list(values[-n:]), list(other[-n:]))),
                                      _bits(alone[-n:]))
    np.testing.assert_array_equal(_bits(call(values[::3], other[::3])), _bits(alone[::3]))
    grid = call(values[:200].reshape(20, 10), other[:200].reshape(20, 10))
    np.testing.assert_array_equal(_bits(grid.ravel()), _bits(alone[:200]))
    # an array whose data starts one byte past an 8-byte boundary (unaligned)
    raw = b"\0" + values.astype("<f8").tobytes()
    unaligned = np.frombuffer(bytes(raw), dtype="<f8", count=len(values), offset=1)
    assert not unaligned.flags.aligned
    np.testing.assert_array_equal(_bits(call(unaligned, other)), _bits(alone))


def test_degrees_and_radians_are_numpys():
    x = RNG.uniform(-1000, 1000, 1000)
    np.testing.assert_array_equal(x * detmath.DEG, np.degrees(x))
    np.testing.assert_array_equal(x * detmath.RAD, np.radians(x))
