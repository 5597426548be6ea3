"""MiniRocket for multivariate sequences of unequal lengths, in numpy and numba.

The transform of Dempster, Schmidt and Webb, "MiniRocket: a very fast (almost) deterministic
transform for time series classification" (KDD 2021), in the multivariate, variable-length
form of sktime's ``MiniRocketMultivariateVariable``, written here from the published
algorithm so that the project needs no further dependency (sktime 1.2 caps pandas below 3.1,
whose CSV reader this project relies on for bit-exact datasets):

- 84 fixed kernels of length 9: weight 2 at three of the nine positions (every combination),
  -1 at the six others; the weights sum to 0.
- Dilations: up to ``max_dilations_per_kernel`` values ``2 ** x`` (integer part, distinct), x
  evenly spaced in ``[0, log2((L - 1) / 8)]`` for the longest training sequence ``L``; the
  ``num_features // 84`` features of a kernel are shared among its dilations as evenly as the
  counts allow.
- Channels: each (dilation, kernel) pair draws ``floor(2 ** u)`` channels without replacement,
  ``u`` uniform in ``[0, log2(min(n_channels, 9) + 1))``; the kernel reads their sum.
- Convolution: centred, dilated, zero beyond either end of the sequence, one output per step.
- Biases: for each (dilation, kernel) pair, the convolution output of one training sequence
  drawn at random, at the quantiles of a low-discrepancy sequence (``k * golden ratio mod 1``).
- Features: the proportion of positive values (PPV) of ``output - bias``, over every step.

Every draw comes from ``numpy.random.RandomState(seed)`` (a frozen stream), in the order above.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numba
import numpy as np

__all__ = ["KERNEL_INDICES", "MiniRocketParameters", "fit_dilations", "fit_minirocket",
           "transform_minirocket"]

#: The positions (of 9) that weigh 2 in each of the 84 kernels; the six others weigh -1.
KERNEL_INDICES = np.array(list(itertools.combinations(range(9), 3)), dtype=np.int64)


def _jit(function):
    # cached where numba can write a cache (beside the module or in the user's cache folder);
    # compiled once per process otherwise (a read-only installation)
    try:
        return numba.njit(cache=True, nogil=True)(function)
    except RuntimeError:  # pragma: no cover - "no locator available"
        return numba.njit(nogil=True)(function)


@dataclass(frozen=True)
class MiniRocketParameters:
    """A fitted MiniRocket transform.

    Attributes
    ----------
    n_channels : int
    dilations : ndarray of int64
    features_per_dilation : ndarray of int64
        Features of each kernel at each dilation.
    channels_per_pair : ndarray of int64
        Channels read by each (dilation, kernel) pair, dilation-major.
    channels : ndarray of int64
        Their indices, pair after pair.
    biases : ndarray of float64
        One per feature, pair after pair.
    """

    n_channels: int
    dilations: np.ndarray
    features_per_dilation: np.ndarray
    channels_per_pair: np.ndarray
    channels: np.ndarray
    biases: np.ndarray

    @property
    def n_features(self):
        """Number of features of the transform (``84 * features_per_dilation.sum()``)."""
        return len(self.biases)


def fit_dilations(reference_length, num_features=10_000, max_dilations_per_kernel=32):
    """Dilations and features per dilation of each kernel, as in the paper's reference code.

    Parameters
    ----------
    reference_length : int
        Length of the longest training sequence (>= 9).
    num_features : int, default=10_000
        Requested features (at least 84; rounded down to a multiple of 84).
    max_dilations_per_kernel : int, default=32

    Returns
    -------
    dilations, features_per_dilation : ndarray of int64

    Examples
    --------
    >>> from baselines._minirocket import fit_dilations
    >>> d, f = fit_dilations(100, num_features=840, max_dilations_per_kernel=32)
    >>> d.tolist(), f.tolist(), int(f.sum())
    ([1, 2, 3, 4, 5, 7, 9, 12], [3, 1, 1, 1, 1, 1, 1, 1], 10)
    """
    per_kernel = max(int(num_features), 84) // 84
    n_dilations = min(per_kernel, int(max_dilations_per_kernel))
    multiplier = per_kernel / n_dilations
    top = np.log2((reference_length - 1) / 8)
    dilations, counts = np.unique(np.logspace(0, top, n_dilations, base=2).astype(np.int32),
                                  return_counts=True)
    counts = (counts * multiplier).astype(np.int64)
    remainder, i = per_kernel - int(counts.sum()), 0
    while remainder > 0:
        counts[i] += 1
        remainder -= 1
        i = (i + 1) % len(counts)
    return dilations.astype(np.int64), counts


def _quantiles(n):
    return (np.arange(1, n + 1) * ((np.sqrt(5) + 1) / 2)) % 1


@_jit
def _kernel_output(x, dilation, channels, top, out):
    """``out[t]``: the kernel with its 2-weights at ``top`` on the sum of ``x[:, channels]``."""
    n_steps = x.shape[0]
    summed = np.zeros(n_steps)
    for c in channels:
        for t in range(n_steps):
            summed[t] += x[t, c]
    out[:] = 0.0
    for j in range(9):
        shift = (j - 4) * dilation
        weight = 2.0 if (j == top[0] or j == top[1] or j == top[2]) else -1.0
        for t in range(max(0, -shift), min(n_steps, n_steps - shift)):
            out[t] += weight * summed[t + shift]


@_jit
def _transform(data, offsets, dilations, features_per_dilation, channels_per_pair, channels,
               biases, kernels, features):
    for i in range(len(offsets) - 1):
        x = data[offsets[i]:offsets[i + 1]]
        n_steps = x.shape[0]
        output = np.empty(n_steps)
        feature, pair, first_channel = 0, 0, 0
        for d in range(len(dilations)):
            m = features_per_dilation[d]
            for k in range(kernels.shape[0]):
                n_ch = channels_per_pair[pair]
                _kernel_output(x, dilations[d], channels[first_channel:first_channel + n_ch],
                               kernels[k], output)
                for f in range(m):
                    bias, count = biases[feature + f], 0
                    for t in range(n_steps):
                        count += output[t] > bias
                    features[i, feature + f] = count / n_steps
                feature += m
                pair += 1
                first_channel += n_ch


def fit_minirocket(data, offsets, *, num_features=10_000, max_dilations_per_kernel=32,
                   seed=None):
    """Fit MiniRocket's dilations, channel combinations and biases on training sequences.

    Parameters
    ----------
    data : ndarray of shape (sum of lengths, n_channels)
        The sequences stacked one after the other.
    offsets : ndarray of int of shape (n_sequences + 1,)
        Sequence ``i`` is ``data[offsets[i]:offsets[i + 1]]``; every length >= 9.
    num_features : int, default=10_000
    max_dilations_per_kernel : int, default=32
    seed : int or None

    Returns
    -------
    parameters : MiniRocketParameters
    """
    data = np.ascontiguousarray(data, dtype=np.float64)
    offsets = np.asarray(offsets, dtype=np.int64)
    lengths = np.diff(offsets)
    if lengths.min() < 9:
        raise ValueError(f"MiniRocket needs sequences of at least 9 steps; the shortest has "
                         f"{int(lengths.min())}")
    rng = np.random.RandomState(seed)
    n_channels = data.shape[1]
    dilations, per_dilation = fit_dilations(int(lengths.max()), num_features,
                                            max_dilations_per_kernel)
    n_pairs = len(KERNEL_INDICES) * len(dilations)
    top = np.log2(min(n_channels, 9) + 1)
    channels_per_pair = (2 ** rng.uniform(0, top, n_pairs)).astype(np.int64)
    channels = np.concatenate([rng.choice(n_channels, k, replace=False)
                               for k in channels_per_pair]).astype(np.int64)
    quantiles = _quantiles(len(KERNEL_INDICES) * int(per_dilation.sum()))
    biases = np.empty(len(quantiles))
    feature, pair, first_channel = 0, 0, 0
    for d, m in zip(dilations, per_dilation):
        for k in range(len(KERNEL_INDICES)):
            example = rng.randint(len(lengths))
            x = data[offsets[example]:offsets[example + 1]]
            output = np.empty(len(x))
            n_ch = channels_per_pair[pair]
            _kernel_output(x, d, channels[first_channel:first_channel + n_ch],
                           KERNEL_INDICES[k], output)
            biases[feature:feature + m] = np.quantile(output, quantiles[feature:feature + m])
            feature += m
            pair += 1
            first_channel += n_ch
    return MiniRocketParameters(n_channels, dilations, per_dilation, channels_per_pair,
                                channels, biases)


def transform_minirocket(data, offsets, parameters):
    """MiniRocket's features of sequences: PPV per (dilation, kernel, bias).

    Parameters
    ----------
    data : ndarray of shape (sum of lengths, n_channels)
    offsets : ndarray of int of shape (n_sequences + 1,)
    parameters : MiniRocketParameters

    Returns
    -------
    features : ndarray of shape (n_sequences, parameters.n_features)
        Values in [0, 1].
    """
    data = np.ascontiguousarray(data, dtype=np.float64)
    offsets = np.asarray(offsets, dtype=np.int64)
    if data.shape[1] != parameters.n_channels:
        raise ValueError(f"MiniRocket was fitted on {parameters.n_channels} channels, "
                         f"got {data.shape[1]}")
    p = parameters
    features = np.zeros((len(offsets) - 1, p.n_features))
    _transform(data, offsets, p.dilations, p.features_per_dilation, p.channels_per_pair,
               p.channels, p.biases, KERNEL_INDICES, features)
    return features
