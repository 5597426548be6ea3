"""Default dataset, save / load round trip, `bsi-lfe simulate`."""

import json
import re

import numpy as np
import pandas as pd
import pytest
from lfe_build import aircraft, scenario

from lfe import (
    MISSION_OBJECTIVES,
    PHASE_NAMES,
    LFEDataset,
    annotate_scenarios,
    load_lfe_dataset,
    make_lfe_dataset,
)
from lfe.cli import main
from lfe.scenario import normalise_table


def _assert_same(a, b):
    assert a.scenario_ids == b.scenario_ids
    for sa, sb in zip(a.scenarios, b.scenarios):
        for table in ("tracks", "weapons", "sites"):
            pd.testing.assert_frame_equal(getattr(sa, table), getattr(sb, table),
                                          check_exact=True)
        assert sa.meta == sb.meta
        assert sa == sb
    pd.testing.assert_frame_equal(a.labels, b.labels, check_exact=True)
    pd.testing.assert_frame_equal(a.phases, b.phases, check_exact=True)
    assert a.info == b.info


def test_default_dataset_has_both_outcomes_for_each_objective(default_dataset):
    ds = default_dataset
    assert len(ds) == 24
    assert ds.scenario_ids == [f"lfe-{k:03d}" for k in range(24)]
    assert list(ds.labels.columns) == list(MISSION_OBJECTIVES)
    assert list(ds.phases.columns) == list(PHASE_NAMES)
    for mo in MISSION_OBJECTIVES:
        assert set(ds.labels[mo]) == {0, 1}, mo
    assert (np.diff(ds.phases.to_numpy(), axis=1) >= 0).all()
    assert repr(ds).startswith("LFEDataset(24 scenarios; achieved: MO1")


def test_load_returns_an_independent_copy(default_dataset):
    copy = load_lfe_dataset()
    assert copy is not default_dataset
    copy.labels.iloc[0, 0] = 1 - copy.labels.iloc[0, 0]
    copy.scenarios[0].tracks.loc[0, "x"] = -999.0
    fresh = load_lfe_dataset()
    assert fresh.labels.iloc[0, 0] == default_dataset.labels.iloc[0, 0]
    assert fresh.scenarios[0].tracks.loc[0, "x"] != -999.0


def test_save_load_round_trip_is_lossless(default_dataset, tmp_path):
    ds = LFEDataset(default_dataset.scenarios[:5], default_dataset.labels.iloc[:5],
                    default_dataset.phases.iloc[:5], info=default_dataset.info)
    path = ds.save(tmp_path / "ds")
    assert sorted(p.name for p in path.iterdir()) == [
        "dataset.json", "labels.csv", "meta.json", "phases.csv", "sites.csv", "tracks.csv",
        "weapons.csv"]
    _assert_same(ds, LFEDataset.load(path))
    _assert_same(ds, load_lfe_dataset(path))


def test_round_trip_keeps_awkward_ids_and_empty_tables(tmp_path):
    """Ids that look like numbers or missing values stay text; no weapons stays no weapons."""
    fleet = {"007": aircraft("friendly", "striker"), "NA": aircraft("hostile", "fighter"),
             "1e3": aircraft("friendly", "escort")}
    shot = ("1", 5.0, "007", "NA", "aam", 7.123456789012345, "miss")
    raw = [scenario(fleet, 30.0, [shot], scenario_id="0001", seed=np.int64(4)),
           scenario(fleet, 30.0, [], scenario_id="nan")]
    scs = []
    for sc in raw:  # the simulator's dtypes
        tables = [normalise_table(getattr(sc, t), t) for t in ("tracks", "weapons", "sites")]
        scs.append(type(sc)(*tables, sc.meta))
    labels, phases = annotate_scenarios(scs)
    ds = LFEDataset(scs, labels, phases)
    back = LFEDataset.load(ds.save(tmp_path / "odd"))
    assert back.scenario_ids == ["0001", "nan"]
    assert back.scenarios[0].meta["seed"] == 4
    assert back.scenarios[1].weapons.empty
    _assert_same(ds, back)


def test_make_lfe_dataset_is_reproducible():
    a = make_lfe_dataset(2, random_state=5)
    b = make_lfe_dataset(2, random_state=5)
    c = make_lfe_dataset(2, random_state=6)
    _assert_same(a, b)
    assert a.scenarios[0] != c.scenarios[0]
    assert a.info["random_state"] == 5 and a.info["n_scenarios"] == 2


@pytest.mark.parametrize("n", [0, -1, 2.0, True])
def test_make_lfe_dataset_bad_size(n):
    with pytest.raises(ValueError, match="n_scenarios must be an integer >= 1"):
        make_lfe_dataset(n)


def test_dataset_constructor_checks(default_dataset):
    ds = default_dataset
    scs = ds.scenarios[:2]
    labels, phases = ds.labels.iloc[:2], ds.phases.iloc[:2]
    with pytest.raises(ValueError, match="labels is missing column 'MO2'"):
        LFEDataset(scs, labels.drop(columns="MO2"), phases)
    with pytest.raises(ValueError, match="phases must be indexed by the scenario ids"):
        LFEDataset(scs, labels, phases.iloc[::-1])
    with pytest.raises(ValueError, match="labels must be a DataFrame"):
        LFEDataset(scs, labels.to_numpy(), phases)
    with pytest.raises(ValueError, match="scenario ids must be unique"):
        LFEDataset([scs[0], scs[0]], labels, phases)


def test_load_rejects_other_directories(tmp_path):
    with pytest.raises(FileNotFoundError, match="no dataset.json"):
        LFEDataset.load(tmp_path)
    (tmp_path / "dataset.json").write_text(json.dumps({"format": "other"}))
    with pytest.raises(ValueError, match="not an LFE dataset"):
        LFEDataset.load(tmp_path)


def test_cli_simulate_writes_a_dataset_that_loads(tmp_path, capsys):
    out = tmp_path / "sim"
    status = main(["simulate", "--n-scenarios", "3", "--seed", "2", "--noise", "0",
                   "--time-noise", "0", "--out", str(out)])
    assert status == 0
    printed = capsys.readouterr().out
    assert "LFEDataset(3 scenarios" in printed and str(out) in printed
    ds = load_lfe_dataset(out)
    _assert_same(ds, make_lfe_dataset(3, random_state=2, noise=0.0, time_noise=0.0))


@pytest.mark.parametrize("args, match", [
    (["--n-scenarios", "0"], "--n-scenarios must be an integer >= 1, got 0"),
    (["--noise", "2"], "--noise must be a number in"),
    (["--time-noise", "-1"], "--time-noise must be a finite number >= 0"),
    (["--seed", "-1"], "--seed must be"),
])
def test_cli_simulate_bad_arguments(tmp_path, capsys, args, match):
    status = main(["simulate", *args, "--out", str(tmp_path / "x")])
    assert status == 2
    assert re.search(match, capsys.readouterr().err)
    assert not (tmp_path / "x").exists()


def test_cli_simulate_refuses_a_file_as_output(tmp_path, capsys):
    target = tmp_path / "file.txt"
    target.write_text("keep me")
    assert main(["simulate", "--n-scenarios", "1", "--out", str(target)]) == 2
    assert "is a file" in capsys.readouterr().err
    assert target.read_text() == "keep me"


def test_round_trip_of_frames_built_by_hand(default_dataset, tmp_path):
    """Labels and phases indexed by the ids without an index name still load."""
    scs = default_dataset.scenarios[:2]
    ids = [sc.scenario_id for sc in scs]
    labels = pd.DataFrame({"MO1": [1, 0], "MO2": [0, 1], "MO3": [1, 1]}, index=ids)
    phases = pd.DataFrame([[0.0, 10.0, 20.0, 30.0], [1.0, 2.0, 3.0, 4.0]], index=ids,
                          columns=list(PHASE_NAMES))
    back = LFEDataset.load(LFEDataset(scs, labels, phases).save(tmp_path / "byhand"))
    pd.testing.assert_frame_equal(back.labels, labels, check_names=False)
    pd.testing.assert_frame_equal(back.phases, phases, check_names=False)
