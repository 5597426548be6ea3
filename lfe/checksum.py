"""Checksums of simulated missions: a canonical byte form of a dataset and its sha256.

The simulator is bit-identical on every IEEE-754 machine (:mod:`lfe.detmath`,
:mod:`lfe.draws`), so two machines that print the same digest hold the same missions, bit for
bit. ``bsi-lfe simulate --checksum`` prints the digests of the built-in dataset and of the
default study's first repeat; ``tests/lfe/test_lfe_checksum.py`` records them.

The canonical form does not depend on pandas' or numpy's version: every float is written as
its IEEE-754 binary64 bits (little-endian; ``-0.0`` and ``0.0`` differ), every integer as a
little-endian int64, every string as its UTF-8 bytes behind a length, the metadata as JSON with
sorted keys (Python writes a float as the shortest text that reads back to the same bits).
"""

from __future__ import annotations

import hashlib
import json
import platform
import struct

import numpy as np

from lfe.annotate import MISSION_OBJECTIVES, PHASE_NAMES, annotate_scenarios
from lfe.scenario import (
    _FLOAT_SITE,
    _FLOAT_TRACK,
    _FLOAT_WEAPON,
    SITE_COLUMNS,
    TRACK_COLUMNS,
    WEAPON_COLUMNS,
)

__all__ = [
    "RECORDED",
    "annotation_bytes",
    "dataset_digest",
    "machine",
    "scenario_bytes",
    "study_repeat_digest",
]

_VERSION = b"bsi-sklearn-lfe-checksum 1\n"
_TABLES = (("tracks", TRACK_COLUMNS, _FLOAT_TRACK), ("weapons", WEAPON_COLUMNS, _FLOAT_WEAPON),
           ("sites", SITE_COLUMNS, _FLOAT_SITE))


def _text(value):
    data = str(value).encode("utf-8")
    return struct.pack("<Q", len(data)) + data


def _json_default(value):
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"{value!r} of type {type(value).__name__} has no canonical form")


def _column(values, kind):
    if kind == "float":
        return np.ascontiguousarray(values, dtype="<f8").tobytes()
    if kind == "bool":
        return np.ascontiguousarray(values, dtype=bool).astype(np.uint8).tobytes()
    if kind == "int":
        return np.ascontiguousarray(values, dtype="<i8").tobytes()
    return b"".join(_text(v) for v in values)


def scenario_bytes(scenario):
    """The canonical bytes of one scenario: metadata, then its three tables column by column.

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    data : bytes
    """
    parts = [_text("scenario"), _text(scenario.scenario_id),
             _text(json.dumps(scenario.meta, sort_keys=True, separators=(",", ":"),
                              default=_json_default))]
    for name, columns, floats in _TABLES:
        table = getattr(scenario, name)
        parts += [_text(name), struct.pack("<Q", len(table))]
        for col in columns:
            kind = "float" if col in floats else "bool" if col == "alive" else "text"
            parts += [_text(col), _column(table[col].to_numpy(), kind)]
    return b"".join(parts)


def annotation_bytes(labels, phases):
    """The canonical bytes of the commander's verdicts and phase times.

    Parameters
    ----------
    labels : DataFrame
        Index ``scenario_id``, columns :data:`lfe.MISSION_OBJECTIVES` (0/1).
    phases : DataFrame
        Index ``scenario_id``, columns :data:`lfe.PHASE_NAMES` (s).

    Returns
    -------
    data : bytes
    """
    parts = [_text("labels"), _column([str(i) for i in labels.index], "text")]
    parts += [_text(m) + _column(labels[m].to_numpy(), "int") for m in MISSION_OBJECTIVES]
    parts += [_text("phases"), _column([str(i) for i in phases.index], "text")]
    parts += [_text(p) + _column(phases[p].to_numpy(), "float") for p in PHASE_NAMES]
    return b"".join(parts)


def dataset_digest(dataset, *, annotations=()):
    """sha256 of a dataset's missions, verdicts and phase times in their canonical byte form.

    Parameters
    ----------
    dataset : LFEDataset
    annotations : sequence of (labels, phases), default=()
        Further annotations of the same missions (other noise draws) to include, in order.

    Returns
    -------
    digest : str
        64 hexadecimal digits.

    Examples
    --------
    >>> from lfe import make_lfe_dataset
    >>> from lfe.checksum import dataset_digest
    >>> a = make_lfe_dataset(n_scenarios=2, random_state=3)
    >>> dataset_digest(a) == dataset_digest(make_lfe_dataset(n_scenarios=2, random_state=3))
    True
    >>> dataset_digest(a) == dataset_digest(make_lfe_dataset(n_scenarios=2, random_state=4))
    False
    """
    h = hashlib.sha256(_VERSION)
    h.update(struct.pack("<Q", len(dataset.scenarios)))
    for sc in dataset.scenarios:
        h.update(scenario_bytes(sc))
    h.update(annotation_bytes(dataset.labels, dataset.phases))
    for labels, phases in annotations:
        h.update(annotation_bytes(labels, phases))
    return h.hexdigest()


def study_repeat_digest(seed=0, repeat=0):
    """Digest of one repeat of the default ``bsi-lfe study --seed SEED``.

    The repeat's missions (:func:`lfe.study.repeat_dataset`: the default study's
    training pool and test set, 72 + 200 missions), their noise-free verdicts and phase
    times, then their annotations at each of the study's default noise rates with the study's
    time noise and label seed.

    Parameters
    ----------
    seed : int, default=0
        The study's seed.
    repeat : int, default=0

    Returns
    -------
    digest : str
    summary : str
        What was hashed, in words.
    """
    from lfe._settings import STUDY_DEFAULTS as DEFAULTS
    from lfe.study import TIME_NOISE, repeat_dataset, repeat_seeds

    seeds = repeat_seeds(seed, repeat)
    n_pool, test_size = max(DEFAULTS["sizes"]), DEFAULTS["test_size"]
    dataset = repeat_dataset(n_pool, test_size, seeds["dataset_seed"])
    extra = [annotate_scenarios(dataset.scenarios, noise=rate, time_noise=TIME_NOISE,
                                random_state=seeds["label_seed"])
             for rate in DEFAULTS["noise"]]
    rates = ", ".join(f"{r:g}" for r in DEFAULTS["noise"])
    summary = (f"bsi-lfe study --seed {seed}, repeat {repeat}: {n_pool} + {test_size} missions "
               f"(seed {seeds['dataset_seed']}), labels at noise {rates} "
               f"(seed {seeds['label_seed']})")
    return dataset_digest(dataset, annotations=extra), summary


#: The digests of the built-in dataset (``make_lfe_dataset()``) and of repeat 0 of the default
#: study (:func:`study_repeat_digest`), recorded on an Intel Xeon (x86-64, AVX-512); every
#: IEEE-754 machine must print the same (``bsi-lfe simulate --checksum``).
RECORDED = {
    "dataset": "f4ad13bcf1e9b91976a7eb4223ff8948cf581449a11efe003872ffae5df90563",
    "study repeat 0": "0466bd326d3a5d5436370fef872079fbd139898ec3b2cce73239bbdca1658604",
}


def machine():
    """The CPU, platform, Python and numpy versions, in one line (to quote with a digest)."""
    cpu = platform.processor() or ""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            names = [line.split(":", 1)[1].strip() for line in fh if line.startswith("model name")]
        cpu = names[0] if names else cpu
    except OSError:
        pass
    return (f"{cpu or 'unknown CPU'}, {platform.machine()}, {platform.system()}, "
            f"Python {platform.python_version()}, numpy {np.__version__}")
