"""The LFE dataset: simulated scenarios with the commander's annotations, and its disk format."""

from __future__ import annotations

import copy
import functools
import json
import numbers
from pathlib import Path

import numpy as np
import pandas as pd
from sklearn.utils import check_random_state

from bsi_sklearn.param_validation import Interval, validate_params
from lfe.annotate import (
    _ANNOTATE_CONSTRAINTS,
    MISSION_OBJECTIVES,
    PHASE_NAMES,
    annotate_scenarios,
)
from lfe.draws import uniform
from lfe.scenario import (
    _FLOAT_SITE,
    _FLOAT_TRACK,
    _FLOAT_WEAPON,
    SITE_COLUMNS,
    TRACK_COLUMNS,
    WEAPON_COLUMNS,
    Scenario,
    check_scenarios,
    checked_once,
    normalise_table,
)
from lfe.simulator import ScenarioConfig, simulate_scenario

__all__ = ["LFEDataset", "make_lfe_dataset", "load_lfe_dataset", "random_scenario_config"]

_FORMAT = "bsi-sklearn-lfe"
_FORMAT_VERSION = 1
_COLUMNS = {"tracks": TRACK_COLUMNS, "weapons": WEAPON_COLUMNS, "sites": SITE_COLUMNS}
# pandas 3.1 parses floats exactly by default (and deprecates the option); pandas 2 and 3.0
# need it (3.0.6 reads 9.355507060774123 back as 9.355507060774125).
_EXACT_FLOATS = ({} if tuple(int(v) for v in pd.__version__.split(".")[:2]) >= (3, 1)
                 else {"float_precision": "round_trip"})
_NUMERIC = {"tracks": _FLOAT_TRACK, "weapons": _FLOAT_WEAPON, "sites": _FLOAT_SITE}


def _json_default(value):
    # numpy scalars pass validation (numbers.Real) but json cannot write them
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"meta value {value!r} of type {type(value).__name__} cannot be saved")


def random_scenario_config(random_state=None):
    """Draw the configuration of one scenario of the default dataset.

    The paper's package is fixed (8 escorts, 8 SEAD, 2 strikers); the threat and the
    execution vary: 4 to 12 hostile fighters, 0 to 5 SAM sites, weapon loads and
    probabilities of kill, the TOT window (opening 1300-1700 s, 240-360 s long), the escorts'
    push time and the strikers' push error (-300 to +300 s around the plan), and the losses
    that make hostile fighters withdraw.

    Parameters
    ----------
    random_state : int, RandomState instance or None, default=None
        Source of the draws.

    Returns
    -------
    config : ScenarioConfig

    Examples
    --------
    >>> from lfe.dataset import random_scenario_config
    >>> c = random_scenario_config(0)
    >>> 4 <= c.n_hostile <= 12 and 0 <= c.n_sams <= 5 and c.n_friendly == 18
    True
    """
    rng = check_random_state(random_state)
    return ScenarioConfig(
        n_hostile=int(rng.randint(4, 13)),
        n_sams=int(rng.randint(0, 6)),
        escort_push_time=float(10 * rng.randint(12, 31)),
        striker_push_offset=float(10 * rng.randint(-30, 31)),
        tot_start=float(10 * rng.randint(130, 171)),
        tot_window=float(rng.choice([240.0, 300.0, 360.0])),
        escort_missiles=int(rng.randint(3, 7)),
        hostile_missiles=int(rng.randint(2, 5)),
        sead_harms=int(rng.randint(1, 4)),
        sam_missiles=int(rng.randint(4, 11)),
        pk_escort=round(float(uniform(rng, 0.4, 0.7)), 3),
        pk_hostile=round(float(uniform(rng, 0.35, 0.6)), 3),
        pk_harm=round(float(uniform(rng, 0.4, 0.7)), 3),
        pk_sam=round(float(uniform(rng, 0.2, 0.45)), 3),
        pk_bomb=round(float(uniform(rng, 0.15, 0.45)), 3),
        hostile_withdraw_fraction=round(float(uniform(rng, 0.4, 0.8)), 3),
        hostile_alert_fraction=round(float(uniform(rng, 0.0, 0.5)), 3),
    )


class LFEDataset:
    """Simulated large-force exercises with the mission commander's annotations.

    Parameters
    ----------
    scenarios : list of Scenario
        The raw scenarios.
    labels : DataFrame
        Index ``scenario_id``, columns ``MO1``, ``MO2``, ``MO3`` (1 achieved, 0 failed).
    phases : DataFrame
        Index ``scenario_id``, columns ``escort_push``, ``strikers_push``, ``tot``, ``egress``:
        the commander's phase transition times (s).
    info : dict, default=None
        How the dataset was made (generator, arguments), stored with it.

    Attributes
    ----------
    scenario_ids : list of str
        Identifiers, in order.

    Examples
    --------
    >>> from lfe import make_lfe_dataset
    >>> ds = make_lfe_dataset(n_scenarios=3, random_state=0)
    >>> len(ds), list(ds.labels.columns)
    (3, ['MO1', 'MO2', 'MO3'])
    >>> ds.labels.index.tolist() == ds.scenario_ids
    True
    """

    def __init__(self, scenarios, labels, phases, info=None):
        scenarios = check_scenarios(scenarios)
        ids = [sc.scenario_id for sc in scenarios]
        if len(set(ids)) != len(ids):
            raise ValueError("scenario ids must be unique")
        for name, frame, cols in (("labels", labels, MISSION_OBJECTIVES),
                                  ("phases", phases, PHASE_NAMES)):
            if not isinstance(frame, pd.DataFrame):
                raise ValueError(f"{name} must be a DataFrame, got {type(frame).__name__}")
            missing = [c for c in cols if c not in frame.columns]
            if missing:
                raise ValueError(f"{name} is missing column {missing[0]!r}")
            if [str(i) for i in frame.index] != ids:
                raise ValueError(f"{name} must be indexed by the scenario ids, in order")
        self.scenarios = scenarios
        self.labels = labels
        self.phases = phases
        self.info = dict(info or {})

    @property
    def scenario_ids(self):
        """Scenario identifiers, in order."""
        return [sc.scenario_id for sc in self.scenarios]

    def __len__(self):
        return len(self.scenarios)

    def __repr__(self):
        rates = ", ".join(f"{m} {self.labels[m].mean():.0%}" for m in MISSION_OBJECTIVES)
        return f"LFEDataset({len(self)} scenarios; achieved: {rates})"

    def save(self, path):
        """Write the dataset to a directory (CSV and JSON, lossless).

        Files: ``tracks.csv``, ``weapons.csv``, ``sites.csv`` (every scenario, with a
        ``scenario_id`` column), ``meta.json`` (one object per scenario, in order),
        ``labels.csv``, ``phases.csv`` and ``dataset.json`` (format and ``info``). The files
        are written all or none: when one cannot be written (a read-only folder, a full disk),
        the directory keeps its previous files and no temporary file.

        Parameters
        ----------
        path : str or Path
            Directory, created if needed.

        Returns
        -------
        path : Path

        Raises
        ------
        OSError
            Naming the file that could not be written.
        """
        from bsi_sklearn.io import write_files_atomic

        path = Path(path)
        path.mkdir(parents=True, exist_ok=True)
        files = {}
        for table in ("tracks", "weapons", "sites"):
            frames = []
            for sc in self.scenarios:
                frame = getattr(sc, table).loc[:, list(_COLUMNS[table])]
                frames.append(frame.assign(scenario_id=sc.scenario_id))
            data = pd.concat(frames, ignore_index=True)
            data = data[["scenario_id", *_COLUMNS[table]]]
            files[path / f"{table}.csv"] = data.to_csv(index=False)
        files[path / "meta.json"] = json.dumps([sc.meta for sc in self.scenarios], indent=1,
                                               default=_json_default)
        # the index is written as scenario_id whatever its name, as load reads it
        files[path / "labels.csv"] = self.labels.to_csv(index_label="scenario_id")
        files[path / "phases.csv"] = self.phases.to_csv(index_label="scenario_id")
        files[path / "dataset.json"] = json.dumps(
            {"format": _FORMAT, "version": _FORMAT_VERSION, "n_scenarios": len(self),
             "info": self.info}, indent=1)
        # all or nothing: a failed write (read-only folder, full disk) leaves the previous
        # dataset whole, with no temporary file
        write_files_atomic(files)
        return path

    @classmethod
    def load(cls, path):
        """Read a dataset written by :meth:`save`.

        Parameters
        ----------
        path : str or Path
            The directory.

        Returns
        -------
        dataset : LFEDataset
        """
        path = Path(path)
        header_file = path / "dataset.json"
        if not header_file.is_file():
            raise FileNotFoundError(f"{path} is not an LFE dataset directory (no dataset.json)")
        with open(header_file, encoding="utf-8") as fh:
            header = json.load(fh)
        if header.get("format") != _FORMAT:
            raise ValueError(
                f"{header_file}: not an LFE dataset (format {header.get('format')!r})"
            )
        with open(path / "meta.json", encoding="utf-8") as fh:
            metas = json.load(fh)
        tables = {}
        for table in ("tracks", "weapons", "sites"):
            # Text columns stay text: ids such as "007", "1e3" or "NA" must not become numbers
            # or missing values (the numeric columns are finite by validation).
            text = {c: str for c in ("scenario_id", *_COLUMNS[table])
                    if c not in _NUMERIC[table] and c != "alive"}
            data = pd.read_csv(path / f"{table}.csv", dtype=text, keep_default_na=False,
                               **_EXACT_FLOATS)
            tables[table] = dict(iter(data.groupby("scenario_id", sort=False)))
        scenarios = []
        for meta in metas:
            sid = str(meta["scenario_id"])
            parts = {}
            for table in ("tracks", "weapons", "sites"):
                frame = tables[table].get(sid)
                if frame is None:
                    frame = pd.DataFrame(columns=["scenario_id", *_COLUMNS[table]])
                frame = frame.drop(columns="scenario_id").reset_index(drop=True)
                parts[table] = normalise_table(frame, table)
            scenarios.append(Scenario(parts["tracks"], parts["weapons"], parts["sites"], meta))
        labels = pd.read_csv(path / "labels.csv", index_col="scenario_id",
                             dtype={"scenario_id": str}, keep_default_na=False)
        labels = labels[list(MISSION_OBJECTIVES)].astype(np.int64)
        phases = pd.read_csv(path / "phases.csv", index_col="scenario_id",
                             dtype={"scenario_id": str}, keep_default_na=False,
                             na_values={p: ["", "NaN", "nan"] for p in PHASE_NAMES},
                             **_EXACT_FLOATS)
        phases = phases[list(PHASE_NAMES)].astype(float)
        return cls(scenarios, labels, phases, info=header.get("info"))


_MAKE_CONSTRAINTS = {
    "n_scenarios": [Interval(numbers.Integral, 1, None, closed="left")],
    "random_state": ["random_state"],
    "noise": _ANNOTATE_CONSTRAINTS["noise"],
    "time_noise": _ANNOTATE_CONSTRAINTS["time_noise"],
}


def make_lfe_dataset(n_scenarios=24, random_state=0, *, noise=0.04, time_noise=10.0):
    """Simulate and annotate a dataset of offensive-counter-air large-force exercises.

    Each scenario's configuration comes from :func:`random_scenario_config` and its run from
    :func:`lfe.simulate_scenario`; the commander's verdicts and phase times come from
    :func:`lfe.annotate_scenarios` on the raw tables. Every draw comes from ``random_state``.

    Parameters
    ----------
    n_scenarios : int, default=24
        Number of scenarios (the paper has 24).
    random_state : int, RandomState instance or None, default=0
        Seed of the whole dataset.
    noise : float, default=0.04
        Probability that the commander's verdict on each objective is flipped (judgement
        noise, drawn independently per scenario and objective by
        :func:`lfe.annotate_scenarios`). The default dataset is therefore *noisy*: on the
        built-in 24 scenarios the noise-free rule itself scores weighted F1 MO1 1.000, MO2
        0.958, MO3 0.874 against the stored labels, a ceiling no classifier of these labels
        can be expected to beat. ``noise=0`` gives the rule's verdicts exactly. The noise
        is drawn after the simulation, so datasets that differ only in ``noise`` hold the
        same missions.
    time_noise : float, default=10.0
        Standard deviation (s) of the error on the marked phase transition times.

    Returns
    -------
    dataset : LFEDataset
        Scenario ids ``"lfe-000"``, ``"lfe-001"``, ...

    Examples
    --------
    >>> from lfe import make_lfe_dataset
    >>> ds = make_lfe_dataset(n_scenarios=2, random_state=1)
    >>> ds.scenario_ids
    ['lfe-000', 'lfe-001']
    >>> ds.phases.shape
    (2, 4)
    """
    validate_params({"n_scenarios": n_scenarios, "random_state": random_state, "noise": noise,
                     "time_noise": time_noise}, _MAKE_CONSTRAINTS, "make_lfe_dataset")
    rng = check_random_state(random_state)
    width = max(3, len(str(n_scenarios - 1)))
    scenarios = []
    for k in range(int(n_scenarios)):
        config = random_scenario_config(rng)
        seed = int(rng.randint(0, 2**31 - 1))
        scenarios.append(simulate_scenario(config, seed, scenario_id=f"lfe-{k:0{width}d}"))
    info = {"generator": "lfe.make_lfe_dataset", "n_scenarios": int(n_scenarios),
            "random_state": random_state if isinstance(random_state, numbers.Integral)
            else None, "noise": noise, "time_noise": time_noise}
    with checked_once(scenarios) as scenarios:  # annotation and the dataset check them once
        labels, phases = annotate_scenarios(scenarios, noise=noise, time_noise=time_noise,
                                            random_state=rng)
        return LFEDataset(scenarios, labels, phases, info=info)


@functools.lru_cache(maxsize=1)
def _default_dataset():
    return make_lfe_dataset()


def load_lfe_dataset(path=None):
    """The built-in LFE dataset (24 scenarios, seed 0), or a dataset saved on disk.

    Parameters
    ----------
    path : str or Path, default=None
        A directory written by :meth:`LFEDataset.save` (or ``bsi-lfe simulate``). ``None``
        gives the built-in default, ``make_lfe_dataset(24, random_state=0)``, simulated on
        first use (a few seconds) and cached for the process; each call returns a copy.

    Returns
    -------
    dataset : LFEDataset
        ``.scenarios`` (list of Scenario), ``.labels`` (DataFrame MO1, MO2, MO3 as 0/1),
        ``.phases`` (transition times per scenario).

    Examples
    --------
    >>> from lfe import load_lfe_dataset
    >>> ds = load_lfe_dataset()  # doctest: +SKIP
    >>> len(ds), ds.labels.shape  # doctest: +SKIP
    (24, (24, 3))
    """
    if path is not None:
        return LFEDataset.load(path)
    return copy.deepcopy(_default_dataset())
