"""The missions' checksums: recorded digests, what they cover, ``bsi-lfe simulate --checksum``.

The recorded digests are the missions themselves: a change to the simulator, the commander,
the random draws or the deterministic math that changes one bit of one mission fails here
(record the new digests in this file and in ``lfe.checksum.RECORDED``, and say why in
``benchmarks/HISTORY.md``). Every IEEE-754 machine must compute the same digests.
"""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import lfe.checksum
from lfe import LFEDataset, make_lfe_dataset
from lfe.checksum import RECORDED, dataset_digest, study_repeat_digest
from lfe.cli import main

#: ``make_lfe_dataset()`` (24 missions, seed 0, noise 0.04, time noise 10 s).
DATASET = "f4ad13bcf1e9b91976a7eb4223ff8948cf581449a11efe003872ffae5df90563"
#: repeat 0 of the default ``bsi-lfe study --seed 0`` (272 missions, labels at noise 0, 0.04).
STUDY_REPEAT = "0466bd326d3a5d5436370fef872079fbd139898ec3b2cce73239bbdca1658604"
ROOT = Path(__file__).resolve().parents[2]


def test_recorded_digests_are_the_commands():
    assert RECORDED == {"dataset": DATASET, "study repeat 0": STUDY_REPEAT}


def test_default_dataset_digest_is_recorded(default_dataset):
    assert dataset_digest(default_dataset) == DATASET


@pytest.mark.slow  # 272 missions: about 30 s
def test_study_repeat_digest_is_recorded():
    digest, summary = study_repeat_digest(0, 0)
    assert digest == STUDY_REPEAT
    assert "72 + 200 missions" in summary


@pytest.fixture(scope="module")
def small():
    return make_lfe_dataset(n_scenarios=2, random_state=4)


def test_digest_sees_one_bit_of_anything(small):
    base = dataset_digest(small)
    assert base == dataset_digest(make_lfe_dataset(n_scenarios=2, random_state=4))

    def changed(edit):
        ds = LFEDataset([type(sc)(sc.tracks.copy(), sc.weapons.copy(), sc.sites.copy(), sc.meta)
                         for sc in small.scenarios], small.labels.copy(), small.phases.copy())
        edit(ds)
        return dataset_digest(ds)

    def nudge(ds):  # one unit in the last place of one position
        ds.scenarios[1].tracks.loc[5, "x"] = np.nextafter(ds.scenarios[1].tracks.loc[5, "x"],
                                                          np.inf)

    def negative_zero(ds):
        ds.scenarios[0].tracks.loc[0, "time"] = -0.0  # was 0.0

    assert small.scenarios[0].tracks.loc[0, "time"] == 0.0
    edits = [nudge, negative_zero,
             lambda ds: ds.labels.iloc.__setitem__((0, 1), 1 - ds.labels.iloc[0, 1]),
             lambda ds: ds.phases.iloc.__setitem__((1, 2), ds.phases.iloc[1, 2] + 1.0),
             lambda ds: ds.scenarios[0].meta.__setitem__("seed", 1),
             lambda ds: ds.scenarios[1].weapons.loc.__setitem__((0, "outcome"), "x")]
    digests = {changed(edit) for edit in edits}
    assert len(digests) == len(edits) and base not in digests
    labels, phases = small.labels, small.phases
    assert dataset_digest(small, annotations=[(labels, phases)]) != base


def test_digest_survives_save_and_load(small, tmp_path):
    assert dataset_digest(LFEDataset.load(small.save(tmp_path / "ds"))) == dataset_digest(small)


def test_cli_checksum_prints_both_digests(monkeypatch, capsys):
    monkeypatch.setattr(lfe.checksum, "study_repeat_digest",
                        lambda seed, repeat: (STUDY_REPEAT, f"stub {seed} {repeat}"))
    assert main(["simulate", "--checksum"]) == 0
    out = capsys.readouterr().out
    assert f"dataset         {DATASET}  (the recorded value)" in out
    assert f"study repeat 0  {STUDY_REPEAT}  (the recorded value)" in out
    assert "stub 0 0" in out and out.startswith("sha256 of the missions (")


def test_cli_checksum_of_another_dataset_and_out_rules(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(lfe.checksum, "study_repeat_digest",
                        lambda seed, repeat: ("0" * 64, "stub"))
    assert main(["simulate", "--checksum", "--n-scenarios", "2", "--seed", "4",
                 "--out", str(tmp_path / "ds")]) == 0
    out = capsys.readouterr().out
    assert f"dataset         {dataset_digest(make_lfe_dataset(2, random_state=4))}\n" in out
    assert "recorded" not in out  # no recorded value for these arguments
    assert (tmp_path / "ds" / "dataset.json").is_file()
    assert main(["simulate", "--n-scenarios", "1"]) == 2
    assert "--out DIR is required (unless --checksum)" in capsys.readouterr().err


_CHILD = """
import sys
from lfe import make_lfe_dataset
from lfe.checksum import dataset_digest
print(dataset_digest(make_lfe_dataset(3, random_state=0)))
"""


def _dispatched_features():
    """numpy's SIMD targets this CPU runs (the ones NPY_DISABLE_CPU_FEATURES can turn off)."""
    try:
        from numpy._core import _multiarray_umath as umath
    except ImportError:  # pragma: no cover - numpy 1.x
        from numpy.core import _multiarray_umath as umath
    found = getattr(umath, "__cpu_features__", {})
    dispatch = getattr(umath, "__cpu_dispatch__", [])
    return [f for f in dispatch if found.get(f)]


@pytest.mark.slow  # a fresh interpreter: about 5 s
def test_same_missions_without_simd_and_fused_multiply_add():
    # numpy's SIMD kernels off (its baseline only) and glibc's libm without FMA / AVX2:
    # the old simulator gave other missions this way (75 / 58 / 58 % became 79 / 50 / 67 %)
    features = _dispatched_features()
    if not features:
        pytest.skip("this numpy dispatches no SIMD target on this CPU")
    env = dict(os.environ, PYTHONPATH=str(ROOT), NPY_DISABLE_CPU_FEATURES=",".join(features),
               GLIBC_TUNABLES="glibc.cpu.hwcaps=-AVX2,-FMA,-AVX512F,-AVX512DQ")
    child = subprocess.run([sys.executable, "-c", _CHILD], env=env, capture_output=True,
                           text=True, check=True, cwd=ROOT)
    assert child.stdout.strip() == dataset_digest(make_lfe_dataset(3, random_state=0))
