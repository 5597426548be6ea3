"""The work units of ``bsi-lfe study``: simulate one repeat's missions, run one cell on them.

A *repeat* is one independently simulated set of missions: a training pool and a test set of
fresh missions, every draw from the repeat's own seeds. A *cell* is one training size of one
repeat, for one label-noise rate and one proposition set: every classifier of the study is
fitted on the same training missions and scored on the same test missions. Both are plain
functions of picklable arguments, so joblib can run them in worker processes or on a dask
cluster.
"""

from __future__ import annotations

import contextlib
import time
import warnings

import numpy as np
from sklearn.dummy import DummyClassifier
from sklearn.metrics import f1_score, make_scorer
from sklearn.model_selection import GridSearchCV, KFold, StratifiedKFold, train_test_split

from baselines import FAIR_TRAINING, PAPER_BASELINES
from baselines.practitioner import (
    PRACTITIONER_BASELINES,
    make_practitioner_baseline,
)
from bsi_sklearn.classifier import BSIClassifier
from lfe._probability_scores import positive_probabilities, probability_scores
from lfe.annotate import MISSION_OBJECTIVES, annotate_scenarios
from lfe.compare import BSI_ROWS as COMPARE_BSI_ROWS
from lfe.compare import fit_bsi, weighted_f1  # the comparison's scorer and BSI fit, shared
from lfe.dataset import make_lfe_dataset
from lfe.extractor import LFEPropositionExtractor
from lfe.scenario import checked_once

__all__ = [
    "BSI_CV",
    "BSI_ROWS",
    "CEILING",
    "MAJORITY",
    "NETWORKS",
    "PRACTITIONER",
    "ROWS",
    "TIME_NOISE",
    "bsi_settings",
    "derive_seed",
    "draw_training_set",
    "network_settings",
    "repeat_dataset",
    "repeat_seeds",
    "run_cell",
    "search_grid",
    "simulate_repeat",
]

#: The four recurrent baselines, in the paper's order.
NETWORKS = tuple(PAPER_BASELINES)
#: What a practitioner would try first (:mod:`baselines.practitioner`): a logistic regression
#: on plain temporal features of the propositions, and MiniRocket with a ridge classifier.
PRACTITIONER = tuple(PRACTITIONER_BASELINES)
#: BSI rows with fixed hyperparameters: name -> ``BSIClassifier`` parameters (the
#: comparison's: Prior 2 and Prior 3 with the CB likelihood, Prior 2 with the CI likelihood,
#: and every default without the extractor's roles).
BSI_ROWS = dict(COMPARE_BSI_ROWS)
#: BSI whose hyperparameters an inner cross-validation on the training set chooses.
BSI_CV = "BSI (GridSearchCV)"
#: Always predict the training set's most frequent outcome.
MAJORITY = "Majority class"
#: The commander's rule without judgement noise, scored against the (noisy) test labels: the
#: best any classifier of the labels can expect, not a classifier.
CEILING = "Noise-free rule (ceiling)"
#: Every row of the study, in display order.
ROWS = (*NETWORKS, *PRACTITIONER, *BSI_ROWS, BSI_CV, MAJORITY, CEILING)
#: Standard deviation (s) of the error on the marked phase times (``make_lfe_dataset``'s).
TIME_NOISE = 10.0


def derive_seed(*key):
    """A 31-bit seed derived from integers (the study's seed, the repeat, a purpose, ...).

    Parameters
    ----------
    *key : int
        Non-negative integers; different keys give independent seeds
        (:class:`numpy.random.SeedSequence`).

    Returns
    -------
    seed : int
    """
    return int(np.random.SeedSequence([int(k) for k in key]).generate_state(1)[0] & 0x7FFFFFFF)


def repeat_seeds(seed, repeat):
    """The seeds of one repeat of a study: ``{"dataset_seed": ..., "label_seed": ...}``.

    Parameters
    ----------
    seed : int
        The study's seed (``bsi-lfe study --seed``).
    repeat : int
        The repeat, from 0.

    Returns
    -------
    seeds : dict
    """
    return {"dataset_seed": derive_seed(seed, repeat, 0),
            "label_seed": derive_seed(seed, repeat, 1)}


def repeat_dataset(n_pool, test_size, dataset_seed):
    """A repeat's missions: one :func:`lfe.make_lfe_dataset` run, noise-free verdicts.

    Parameters
    ----------
    n_pool, test_size : int
        Missions of the training pool (the first ``n_pool``) and of the test set.
    dataset_seed : int
        Seed of the missions.

    Returns
    -------
    dataset : LFEDataset
    """
    return make_lfe_dataset(n_pool + test_size, random_state=dataset_seed, noise=0.0,
                            time_noise=0.0)


def simulate_repeat(*, n_pool, test_size, noises, propositions, dataset_seed, label_seed):
    """Simulate one repeat: a training pool and a test set, labels at every noise rate.

    The ``n_pool + test_size`` missions come from one :func:`lfe.make_lfe_dataset` run seeded
    with ``dataset_seed`` (:func:`repeat_dataset`; the first ``n_pool`` are the training pool,
    the rest the test set).
    The commander's rule without noise gives the clean verdicts (the ceiling row and the
    stratification of the training sets); :func:`lfe.annotate_scenarios` with ``label_seed``
    gives the verdicts and phase times at each noise rate, so the missions are the same at
    every rate and only the labels differ.

    Parameters
    ----------
    n_pool, test_size : int
        Missions of the training pool and of the test set.
    noises : sequence of float
        Label-noise rates (probability each verdict is flipped).
    propositions : sequence of str
        Proposition sets of :class:`lfe.LFEPropositionExtractor`.
    dataset_seed, label_seed : int
        Seeds of the missions and of the annotation noise.

    Returns
    -------
    data : dict
        ``clean`` (n, 3) noise-free verdicts; ``labels[noise]`` (n, 3); ``phases[noise]``
        per-step phase labels; ``props[propositions]`` proposition traces; ``roles[...]``;
        ``flight`` flight-phase features; ``n_pool``.
    """
    dataset = repeat_dataset(n_pool, test_size, dataset_seed)
    objectives = list(MISSION_OBJECTIVES)
    data = {"n_pool": n_pool, "clean": dataset.labels[objectives].to_numpy(),
            "labels": {}, "phases": {}, "props": {}, "roles": {}}
    extractor = None
    # every step below reads the same unmodified scenarios: validate them once, not nine times
    with checked_once(dataset.scenarios) as scenarios:
        for ps in propositions:
            extractor = LFEPropositionExtractor(propositions=ps).fit(scenarios)
            data["props"][ps] = extractor.transform(scenarios)
            data["roles"][ps] = {"global_candidates": extractor.global_candidates_,
                                 "subtasks": extractor.subtasks_,
                                 "conditions": extractor.conditions_}
        data["flight"] = extractor.flight_phase_features(scenarios)
        for noise in noises:
            labels, phases = annotate_scenarios(scenarios, noise=noise, time_noise=TIME_NOISE,
                                                random_state=label_seed)
            data["labels"][noise] = labels[objectives].to_numpy()
            data["phases"][noise] = extractor.phase_labels(scenarios, phases)
    return data


def draw_training_set(clean, n_pool, n_train, seed):
    """Positions of ``n_train`` pool missions, stratified on the clean outcomes where possible.

    Stratified on the combination of the three noise-free verdicts when every combination
    drawn has two members or more, else on MO1, else drawn at random; the whole pool when
    ``n_train == n_pool``.

    Parameters
    ----------
    clean : ndarray of shape (n_missions, 3)
        Noise-free verdicts; the first ``n_pool`` rows are the pool.
    n_pool : int
        Size of the training pool.
    n_train : int
        Training missions to draw.
    seed : int
        Seed of the draw.

    Returns
    -------
    positions : ndarray of int, sorted
    """
    pool = np.arange(n_pool)
    if n_train >= n_pool:
        return pool
    codes = clean[:n_pool] @ (1 << np.arange(clean.shape[1]))
    for stratify in (codes, clean[:n_pool, 0], None):
        try:
            train, _ = train_test_split(pool, train_size=n_train, random_state=seed,
                                        stratify=stratify)
        except ValueError:
            continue
        return np.sort(train)
    raise AssertionError("an unstratified split cannot fail")  # pragma: no cover


def _fit_bsi_cv(X, y, roles, params, grid, seed):
    """GridSearchCV over ``grid`` on the training set only; ``(classifier, chosen params)``."""
    if not np.any(y == 1):
        return None, {}
    n_min = int(np.bincount(y, minlength=2).min())
    if n_min == 1:
        # One mission of a class: some inner training fold would lack it (an inner fit
        # without an acceptable mission fails), so there is nothing to cross-validate.
        return fit_bsi("BSI (Prior 2)", X, y, roles, params, seed), {}
    n_splits = min(3, len(y))
    cv = (StratifiedKFold(min(n_splits, n_min), shuffle=True, random_state=seed)
          if n_min >= 2 else KFold(n_splits, shuffle=True, random_state=seed))
    # zero_division=0: what "f1_weighted" computes, without warning about a class that a
    # fold's truth or predictions lack
    scorer = make_scorer(f1_score, average="weighted", zero_division=0)
    # the paper's likelihood (CB), whose epsilon the grid searches
    params = {"likelihood": "cb", **params}
    search = GridSearchCV(BSIClassifier(random_state=seed, **roles, **params), grid,
                          scoring=scorer, cv=cv, n_jobs=1, error_score="raise")
    search.fit(X, y)
    chosen = {k: (v if v is None or isinstance(v, str) else float(v))
              for k, v in search.best_params_.items()}
    return search.best_estimator_, chosen


class _WarningLog:
    """Every warning raised while one row of a cell is fitted and scored, counted.

    Nothing is silenced: each warning is recorded (``warnings.catch_warnings(record=True)``
    with the ``"always"`` action, so a repeated warning counts each time) and goes into the
    cell's file, the study's ``study_warnings.csv`` and ``study_runs.csv`` (column
    ``warnings``), and the count is printed at the end of the run.
    """

    def __init__(self):
        self.counts = {}

    @contextlib.contextmanager
    def recording(self, name):
        """Record the warnings of the block under the row ``name``."""
        self.counts.setdefault(name, {})
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                yield
            finally:
                for w in caught:
                    text = str(w.message).strip()
                    key = (w.category.__name__, text.splitlines()[0] if text else "")
                    self.counts[name][key] = self.counts[name].get(key, 0) + 1

    def total(self, name):
        """Warnings recorded under ``name``."""
        return sum(self.counts.get(name, {}).values())

    def records(self):
        """One dict per row, category and message: ``classifier, category, message, count``."""
        return [{"classifier": name, "category": category, "message": message, "count": n}
                for name in ROWS for (category, message), n in
                sorted(self.counts.get(name, {}).items())]


def run_cell(data, *, noise, propositions, n_train, train, model_seed, settings):
    """Fit every row of the study on one training set; score it on the test missions.

    Parameters
    ----------
    data : dict
        One repeat, from :func:`simulate_repeat`.
    noise : float
        Label-noise rate of this cell.
    propositions : str
        Proposition set of this cell.
    n_train : int
        Training size (``len(train)``).
    train : ndarray of int
        Positions of the training missions in the pool.
    model_seed : int
        Seed of every model of the cell (network weights, validation split and batch order,
        MCMC chains, inner cross-validation folds, MiniRocket's kernels).
    settings : dict
        ``networks`` (:class:`baselines.LSTMSequenceClassifier` parameters), ``bsi``
        (:class:`bsi_sklearn.BSIClassifier` parameters) and ``grid`` (the inner search's).

    Returns
    -------
    rows : list of dict
        One per row (:data:`ROWS`) and objective: ``classifier``, ``objective``, ``f1``,
        ``accuracy``, ``warnings`` (how many warnings fitting and scoring that row raised in
        this cell), ``fit_s``, ``detail`` (the chosen hyperparameters, the networks' chosen
        epochs), ``log_loss`` and ``brier`` (of P(label 1) on the test missions, for the rows
        whose model gives probabilities: BSI, the networks, the logistic regression, the
        majority class's base rate; ``None`` for MiniRocket, the noise-free rule and a BSI
        fit that could not run, no training mission being acceptable).
    warnings : list of dict
        ``classifier, category, message, count`` of every warning raised (see
        :class:`_WarningLog`).
    """
    import baselines

    n_pool = data["n_pool"]
    test = np.arange(n_pool, len(data["clean"]))
    y = data["labels"][noise]
    props = data["props"][propositions]
    roles = data["roles"][propositions]
    objectives = list(MISSION_OBJECTIVES)
    # import torch before recording, so that a warning raised on import (once per process) is
    # not counted in whichever cell a worker happens to run first
    make_network = baselines.make_paper_baseline
    log = _WarningLog()

    def sub(seqs, idx):
        return [seqs[i] for i in idx]

    preds, fit_s, detail, probas = {}, {}, {}, {}
    coupled = None  # the coupled networks' inputs, built once for both
    for name in NETWORKS:
        start = time.perf_counter()
        with log.recording(name):
            clf = make_network(name, random_state=model_seed, **settings["networks"])
            if clf.coupled and coupled is None:
                # arrays, not frames: the same float64 values as pd.concat of the propositions
                # and the flight features, without checking 51 column names per mission
                coupled = [np.hstack([p.to_numpy(dtype=float), f.to_numpy(dtype=float)])
                           for p, f in zip(props, data["flight"])]
            X = coupled if clf.coupled else props
            clf.fit(sub(X, train), y[train], phases=sub(data["phases"][noise], train))
            preds[name] = clf.predict(sub(X, test))
            probas[name] = positive_probabilities(clf, sub(X, test))
        fit_s[name] = time.perf_counter() - start
        detail[name] = f"epochs={clf.refit_epochs_ or clf.best_epoch_}"
    X_train, X_test = sub(props, train), sub(props, test)
    for name in PRACTITIONER:
        start = time.perf_counter()
        with log.recording(name):
            clf = make_practitioner_baseline(name, random_state=model_seed).fit(X_train,
                                                                                y[train])
            preds[name] = clf.predict(X_test)
            probas[name] = positive_probabilities(clf, X_test)
        fit_s[name] = time.perf_counter() - start
        detail[name] = (" | ".join(f"C={c:.3g}" if c is not None else "constant"
                                   for c in clf.chosen_C_) if hasattr(clf, "chosen_C_")
                        else "")
    for name in (*BSI_ROWS, BSI_CV):
        start = time.perf_counter()
        columns, chosen, proba = [], [], []
        with log.recording(name):
            for k in range(len(objectives)):
                if name == BSI_CV:
                    clf, params = _fit_bsi_cv(X_train, y[train, k], roles, settings["bsi"],
                                              settings["grid"], model_seed)
                    chosen.append(";".join(f"{p}={v}" for p, v in sorted(params.items())))
                else:
                    clf = fit_bsi(name, X_train, y[train, k], roles, settings["bsi"],
                                   model_seed)
                columns.append(np.zeros(len(test), dtype=y.dtype) if clf is None
                               else clf.predict(X_test))
                proba.append(np.full(len(test), np.nan) if clf is None
                             else clf.predict_proba(X_test)[:, 1])
        preds[name] = np.column_stack(columns)
        probas[name] = np.column_stack(proba)
        fit_s[name] = time.perf_counter() - start
        detail[name] = " | ".join(chosen)
    # "prior" predicts the most frequent outcome, as "most_frequent" does, and gives the
    # training set's base rate as its probability (not a one-hot certainty)
    majority = [DummyClassifier(strategy="prior").fit(np.zeros((len(train), 1)), y[train, k])
                for k in range(len(objectives))]
    blank = np.zeros((len(test), 1))
    preds[MAJORITY] = np.column_stack([clf.predict(blank) for clf in majority])
    probas[MAJORITY] = np.column_stack([positive_probabilities(clf, blank)[:, 0]
                                        for clf in majority])
    preds[CEILING] = data["clean"][test]
    rows = []
    for name in ROWS:
        for k, mo in enumerate(objectives):
            truth, pred = y[test, k], np.asarray(preds[name])[:, k]
            p1 = None if probas.get(name) is None else probas[name][:, k]
            scores = probability_scores(truth, p1)
            rows.append({"classifier": name, "objective": mo,
                         "f1": weighted_f1(truth, pred),
                         "accuracy": float(np.mean(truth == pred)),
                         "warnings": log.total(name),
                         "fit_s": fit_s.get(name, 0.0), "detail": detail.get(name, ""),
                         # None, not NaN: the cell files stay standard JSON
                         **{metric: None if np.isnan(value) else value
                            for metric, value in scores.items()}})
    return rows, log.records()


def bsi_settings(quick):
    """BSI parameters of the study: ``inference="auto"``.

    Exact within its work budget; MCMC with the classifier's defaults (shorter with ``quick``)
    only where exact cannot go.
    """
    return dict(inference="auto", n_samples=300) if quick else dict(inference="auto")


def network_settings(quick):
    """Network parameters of the study: :data:`baselines.FAIR_TRAINING`, smaller with quick."""
    small = dict(hidden_size=16, max_epochs=15, patience=5) if quick else {}
    return {**FAIR_TRAINING, **small}


def search_grid(quick):
    """Hyperparameter grid of the inner search (the prior, and the likelihood's epsilon)."""
    if quick:
        return {"prior": ["sets_of_chains", "forest"]}
    return {"prior": ["sets_of_chains", "forest"], "epsilon": [None, 0.1]}
