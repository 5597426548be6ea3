"""The protocol of ``bsi-lfe compare`` (:mod:`lfe.compare`): the folds, the tasks, :func:`compare`.

The same folds for every row (shuffled, stratified on the three outcomes where possible); one
task per row and fold (a network, a practitioner's row, a BSI classifier per objective or the
majority class, fitted on the fold's training scenarios and predicting its test ones) and one
per BSI row fitted on every scenario (its MAP specification scored); the tasks run through
joblib, and their predictions make the tables of a :class:`~lfe.compare.ComparisonResult`.
"""

from __future__ import annotations

import time
from numbers import Integral

import numpy as np
import pandas as pd
from sklearn.dummy import DummyClassifier
from sklearn.model_selection import KFold
from sklearn.utils.parallel import Parallel, delayed

import baselines
from baselines import FAIR_TRAINING, PAPER_BASELINES
from baselines.practitioner import (
    PRACTITIONER_BASELINES,
    make_practitioner_baseline,
)
from bsi_sklearn.classifier import BSIClassifier
from bsi_sklearn.param_validation import (
    NONZERO_INTEGER,
    Interval,
    validate_params,
)
from lfe._probability_scores import positive_probabilities, probability_scores
from lfe._settings import COMPARE_QUICK
from lfe._workers import load_libraries
from lfe.annotate import MISSION_OBJECTIVES
from lfe.compare._result import ComparisonResult
from lfe.compare._rows import BSI_ROWS, MAJORITY, PAPER_MAP_F1, ROWS, WITHOUT_ROLES
from lfe.dataset import LFEDataset, load_lfe_dataset, make_lfe_dataset
from lfe.extractor import LFEPropositionExtractor
from lfe.scenario import checked_once

__all__ = ["compare", "fit_bsi", "weighted_f1"]

# The paper's proposition set: 8.3 million hypotheses under Prior 2 and 34.4 million under
# Prior 3, each enumerated exactly in a few seconds.
_QUICK_BASELINE = dict(hidden_size=16, max_epochs=15, patience=5)
# inference stays "auto" (exact within its work budget); shorter chains only if it samples
_QUICK_BSI = dict(inference="auto", n_samples=300, n_chains=2, burn_in=50)


def _folds(labels, n_splits, seed):
    """Shuffled folds stratified on the combination of the three outcomes, when possible."""
    codes = labels.to_numpy() @ (1 << np.arange(labels.shape[1]))
    positions = np.arange(len(labels))
    counts = np.bincount(codes)
    counts = counts[counts > 0]
    if (counts < n_splits).all():  # no combination fills every fold: plain shuffled folds
        folds = list(KFold(n_splits, shuffle=True, random_state=seed).split(positions))
        return [(np.sort(tr), np.sort(te)) for tr, te in folds], "KFold, shuffled"
    test_fold = _stratified_test_folds(codes, n_splits, seed)
    split = "StratifiedKFold on the MO1-MO3 outcome combination, shuffled"
    rare = int(np.sum(counts < n_splits))
    if rare:
        split += (f" ({rare} combination{'s' if rare > 1 else ''} with fewer missions than "
                  "folds, spread as evenly as possible)")
    return [(positions[test_fold != f], positions[test_fold == f])
            for f in range(n_splits)], split


def _stratified_test_folds(codes, n_splits, seed):
    """Each mission's test fold, by the rule of ``StratifiedKFold(shuffle=True)``.

    The rule is written here rather than called because the LFE outcome combinations are
    always rarer than the folds somewhere (the built-in 24 missions have four combinations
    of 2 for 4 folds), and scikit-learn warns on every such split although its allocation is
    the one this protocol wants: a combination of ``c < n_splits`` missions goes to ``c``
    different folds. The folds are the ones scikit-learn 1.9 draws, so the recorded tables
    stay reproducible (``tests/lfe/test_compare.py`` compares the two).
    """
    # combinations numbered by first appearance, as StratifiedKFold numbers its classes
    _, first, inverse = np.unique(codes, return_index=True, return_inverse=True)
    _, rank = np.unique(first, return_inverse=True)
    encoded = rank[inverse]
    n_classes = len(first)
    # round robin over the sorted combinations: how many of each go to each test fold
    ordered = np.sort(encoded)
    allocation = np.array([np.bincount(ordered[f::n_splits], minlength=n_classes)
                           for f in range(n_splits)])
    rng = np.random.RandomState(seed)
    test_fold = np.empty(len(codes), dtype=int)
    for k in range(n_classes):
        folds_k = np.repeat(np.arange(n_splits), allocation[:, k])
        rng.shuffle(folds_k)
        test_fold[encoded == k] = folds_k
    return test_fold


def weighted_f1(y_true, y_pred):
    """``f1_score(average="weighted", zero_division=0)`` of 0/1 labels, without its overhead.

    The comparison scores a few hundred label pairs; scikit-learn's validation would dominate
    the quick runs. Labels present in ``y_true`` are weighted by their support.
    """
    y_true, y_pred = np.asarray(y_true), np.asarray(y_pred)
    total = 0.0
    for label in np.unique(y_true):
        tp = np.sum((y_true == label) & (y_pred == label))
        denom = np.sum(y_true == label) + np.sum(y_pred == label)
        total += np.sum(y_true == label) * (2.0 * tp / denom if denom else 0.0)
    return float(total / len(y_true)) if len(y_true) else 0.0


def fit_bsi(name, X, y, roles, params, seed):
    """One BSI classifier fitted on one objective; ``None`` without an acceptable scenario."""
    if not np.any(y == 1):
        return None  # BSI needs an acceptable demonstration; predict "failed" throughout
    roles = {} if name in WITHOUT_ROLES else roles
    clf = BSIClassifier(random_state=seed, **roles, **params, **BSI_ROWS[name])
    return clf.fit(X, y)  # a ConvergenceWarning, if MCMC ran and did not converge, is shown


def _run_task(kind, name, fold, data, train, test, params, seed):
    """Fit one classifier on ``train`` and predict ``test``; return predictions and times.

    ``kind`` is ``"baseline"`` (a network), ``"practitioner"``, ``"bsi"``, ``"majority"`` or
    ``"map"`` (a BSI fit on every scenario, scored with its MAP specification). ``"proba"``
    is P(label 1) per test scenario and objective (:func:`positive_probabilities`; read after
    the timed prediction, so the times are the predictions' alone), ``None`` for a model
    without probabilities, ``nan`` in the column of an objective BSI could not fit.
    """
    load_libraries()
    y = data["labels"]

    def sub(seqs, idx):
        return [seqs[i] for i in idx]

    if kind == "baseline":
        clf = baselines.make_paper_baseline(name, random_state=seed, **params)
        X = data["coupled"] if clf.coupled else data["props"]
        start = time.perf_counter()
        clf.fit(sub(X, train), y[train], phases=sub(data["phases"], train))
        fit_s = time.perf_counter() - start
        start = time.perf_counter()
        pred = clf.predict(sub(X, test))
        predict_s = time.perf_counter() - start
        return {"pred": pred, "fit_s": fit_s, "predict_s": predict_s,
                "proba": positive_probabilities(clf, sub(X, test))}
    if kind == "practitioner":
        clf = make_practitioner_baseline(name, random_state=seed)
        start = time.perf_counter()
        clf.fit(sub(data["props"], train), y[train])
        fit_s = time.perf_counter() - start
        start = time.perf_counter()
        pred = clf.predict(sub(data["props"], test))
        predict_s = time.perf_counter() - start
        return {"pred": pred, "fit_s": fit_s, "predict_s": predict_s,
                "proba": positive_probabilities(clf, sub(data["props"], test))}
    if kind == "majority":
        start = time.perf_counter()
        # "prior" predicts the most frequent outcome, as "most_frequent" does, and gives the
        # training folds' base rate as its probability (not a one-hot certainty)
        clf = DummyClassifier(strategy="prior").fit(np.zeros((len(train), 1)), y[train])
        fit_s = time.perf_counter() - start
        start = time.perf_counter()
        pred = clf.predict(np.zeros((len(test), 1)))
        predict_s = time.perf_counter() - start
        return {"pred": pred, "fit_s": fit_s, "predict_s": predict_s,
                "proba": positive_probabilities(clf, np.zeros((len(test), 1)))}
    X_train, X_test = sub(data["props"], train), sub(data["props"], test)
    preds, fit_s, predict_s, extra, proba = [], 0.0, 0.0, [], []
    for k in range(y.shape[1]):
        start = time.perf_counter()
        clf = fit_bsi(name, X_train, y[train, k], data["roles"], params, seed)
        fit_s += time.perf_counter() - start
        start = time.perf_counter()
        if clf is None:
            pred = np.zeros(len(test), dtype=y.dtype)
        elif kind == "map":
            spec = clf.map_specification_
            pred = np.array([int(spec.satisfied_by(t)) for t in X_test], dtype=y.dtype)
        else:
            pred = clf.predict(X_test)
        predict_s += time.perf_counter() - start
        preds.append(pred)
        # the MAP specification's verdicts and a fit that could not run have no probability
        proba.append(np.full(len(test), np.nan) if clf is None or kind == "map"
                     else clf.predict_proba(X_test)[:, 1])
        extra.append({
            "map_specification": "" if clf is None else clf.map_specification_.to_ltl(),
            "inference": "none" if clf is None else clf.inference_,
        })
    return {"pred": np.column_stack(preds), "fit_s": fit_s, "predict_s": predict_s,
            "extra": extra, "proba": None if kind == "map" else np.column_stack(proba)}


_COMPARE_CONSTRAINTS = {
    "dataset": [None, LFEDataset],
    "n_splits": [Interval(Integral, 2, None, closed="left"), None],
    "seed": [Interval(Integral, 0, None, closed="left")],
    "n_jobs": [None, NONZERO_INTEGER],
    "quick": "no_validation",  # read as a truth value
    "verbose": [Interval(Integral, 0, None, closed="left")],
}


def compare(dataset=None, *, n_splits=None, seed=0, n_jobs=None, quick=False, verbose=1):
    """Cross-validate BSI and the paper's four recurrent baselines on LFE missions.

    Every classifier sees the same folds. The baselines (:func:`baselines.make_paper_baseline`,
    hidden size 32, Adam at 1e-2, mini-batches of 4, at most 200 epochs) are trained with the
    protocol :data:`baselines.FAIR_TRAINING`: early stopping (patience 20) chooses the number
    of epochs on a 20 % validation split of the training scenarios, then a fresh network with
    the same initial weights is refitted on every training scenario for that many epochs, so
    the networks learn from as many scenarios as BSI. They predict the three objectives at
    once; the standalone ones read the propositions, the coupled ones also the aircraft
    flight-phase fractions (:meth:`LFEPropositionExtractor.flight_phase_features`) and learn
    the commander's phase labels (:meth:`LFEPropositionExtractor.phase_labels`) as a second
    task. BSI fits one :class:`~bsi_sklearn.BSIClassifier` per objective (CB likelihood, the
    paper's proposition roles, the exact posterior) and predicts with its ``predict``. A
    majority-class reference row is added (its probability: the training folds' base rate).
    Beside the F1, every row whose model gives probabilities (BSI's ``predict_proba``, the
    networks', the logistic regression's, the majority class's) is scored by the log loss and
    the Brier score of its pooled out-of-fold P(label 1); the others (MiniRocket's ridge
    classifier; BSI on a fold without an acceptable scenario) get ``nan``, "n/a" in the tables.
    The MAP-formula F1 comes from BSI fitted on every scenario, its MAP specification's
    verdicts scored against the labels. On the same folds: BSI with Prior 2 and the CI
    likelihood, and the practitioner's rows (:mod:`baselines.practitioner`): a logistic
    regression on five temporal features per proposition, its regularisation chosen by an inner
    cross-validation on the training folds only, and MiniRocket with a ridge classifier.

    Parameters
    ----------
    dataset : LFEDataset, default=None
        The missions; the built-in dataset (:func:`lfe.load_lfe_dataset`, 24 scenarios) when
        omitted, or with ``quick=True`` a simulated one of 8 scenarios (seed 0).
    n_splits : int, default=None
        Number of folds: 4 (the paper's), or 2 with ``quick=True``. The folds are shuffled
        with ``seed`` and stratified on the combination of the three outcomes (each
        combination spread over the folds as evenly as its count allows; plain shuffled
        :class:`~sklearn.model_selection.KFold` when no combination has ``n_splits``
        members), so every training fold sees both outcomes of each objective where possible.
    seed : int, default=0
        Seeds the folds, the baselines' weights, validation splits and batch order, and the
        MCMC chains (quick mode). Each fold's models get their own seed drawn from it.
    n_jobs : int, default=None
        Fits run in parallel processes (joblib; ``None`` or 1: sequentially, -1: every
        core). Each fit is deterministic and single-threaded (the baselines use one torch
        thread), so the results do not depend on ``n_jobs``.
    quick : bool, default=False
        A smoke test in seconds: 8 scenarios (unless ``dataset``), 2 folds, small baselines
        (hidden size 16, at most 15 epochs) and short MCMC runs instead of the exact
        posterior. Not the paper's result.
    verbose : int, default=1
        ``0`` silent; ``1`` a progress bar over the fits.

    Returns
    -------
    result : ComparisonResult
        The tables (``f1``, ``log_loss``, ``brier``, ``table``, ``map_f1``, ``times``,
        ``f1_folds``), the out-of-fold predictions and probabilities and the folds;
        ``save(out)`` writes the files.

    Raises
    ------
    ModuleNotFoundError
        When torch (the ``bsi-sklearn[baselines]`` extra) is not installed, before any fit.

    Examples
    --------
    >>> from lfe import make_lfe_dataset
    >>> from lfe.compare import compare
    >>> ds = make_lfe_dataset(n_scenarios=4, random_state=0)
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     res = compare(ds, quick=True, verbose=0)
    >>> # the quick runs' short chains: posteriors too flat to list, reported by their samples
    >>> sorted({w.category.__name__ for w in caught})
    []
    >>> list(res.f1.columns), list(res.f1.index[:7])
    (['MO1', 'MO2', 'MO3'], ['LSTM', 'Bi-LSTM', 'LSTM Coupled', 'Bi-LSTM Coupled', \
'BSI (Prior 2)', 'BSI (Prior 3)', 'BSI (Prior 2, CI)'])
    >>> "Logistic regression" in res.f1.index
    True
    >>> sorted(set(res.map_f1["classifier"]))
    ['BSI (Prior 2)', 'BSI (Prior 2, CI)', 'BSI (Prior 3)', 'BSI (no roles)']
    >>> full = compare()   # the paper's setting: 1.5 to 4 minutes on 2 cores  # doctest: +SKIP
    """
    start_run = time.perf_counter()
    validate_params({"dataset": dataset, "n_splits": n_splits, "seed": seed, "n_jobs": n_jobs,
                     "quick": quick, "verbose": verbose}, _COMPARE_CONSTRAINTS, "compare")
    if n_splits is None:
        n_splits = COMPARE_QUICK["n_splits"] if quick else 4
    if dataset is None:
        dataset = (make_lfe_dataset(COMPARE_QUICK["n_scenarios"], random_state=0) if quick
                   else load_lfe_dataset())
    if n_splits > len(dataset):
        raise ValueError(
            f"n_splits={n_splits} is more than the {len(dataset)} scenarios of the dataset"
        )

    baselines.require_torch()  # the networks need torch: say so before the BSI fits, not after
    objectives = list(MISSION_OBJECTIVES)
    labels = dataset.labels[objectives]
    with checked_once(dataset.scenarios) as scenarios:  # validated once, not four times
        extractor = LFEPropositionExtractor().fit(scenarios)
        props = extractor.transform(scenarios)
        flight = extractor.flight_phase_features(scenarios)
        phases = extractor.phase_labels(scenarios, dataset.phases)
    data = {
        "props": props,
        "coupled": [pd.concat([p.astype(float), f], axis=1) for p, f in zip(props, flight)],
        "phases": phases,
        "labels": labels.to_numpy(),
        "roles": {"global_candidates": extractor.global_candidates_,
                  "subtasks": extractor.subtasks_, "conditions": extractor.conditions_},
    }
    folds, split = _folds(labels, n_splits, seed)
    fold_seeds = np.random.RandomState(seed).randint(np.iinfo(np.int32).max, size=n_splits)
    baseline_params = {**FAIR_TRAINING, **(_QUICK_BASELINE if quick else {})}
    bsi_params = dict(_QUICK_BSI) if quick else {}
    everything = np.arange(len(dataset))

    # Longest fits first, so parallel workers finish together.
    tasks = [("map", name, -1, everything, everything, bsi_params, seed) for name in BSI_ROWS]
    tasks += [("bsi", name, f, tr, te, bsi_params, int(fold_seeds[f]))
              for name in BSI_ROWS for f, (tr, te) in enumerate(folds)]
    tasks += [("baseline", name, f, tr, te, baseline_params, int(fold_seeds[f]))
              for name in PAPER_BASELINES for f, (tr, te) in enumerate(folds)]
    tasks += [("practitioner", name, f, tr, te, {}, int(fold_seeds[f]))
              for name in PRACTITIONER_BASELINES for f, (tr, te) in enumerate(folds)]
    tasks += [("majority", MAJORITY, f, tr, te, {}, 0) for f, (tr, te) in enumerate(folds)]

    jobs = (delayed(_run_task)(kind, name, f, data, tr, te, params, s)
            for kind, name, f, tr, te, params, s in tasks)
    outputs = Parallel(n_jobs=n_jobs, return_as="generator")(jobs)
    if verbose:
        from tqdm.auto import tqdm

        outputs = tqdm(outputs, total=len(tasks), desc="bsi-lfe compare", unit="fit")
    outputs = list(outputs)

    names = list(ROWS)
    pred = {name: np.full(labels.shape, -1, dtype=np.int64) for name in names}
    proba = {name: np.full(labels.shape, np.nan) for name in names}  # nan: none given
    time_rows, fold_rows, map_rows = [], [], []
    for (kind, name, f, _, test, _, _), out in zip(tasks, outputs):
        if kind == "map":
            for k, mo in enumerate(objectives):
                map_rows.append({
                    "classifier": name, "objective": mo,
                    "f1": weighted_f1(labels[mo].to_numpy(), out["pred"][:, k]),
                    "paper": PAPER_MAP_F1.get(name, {}).get(mo, np.nan),
                    "inference": out["extra"][k]["inference"],
                    "map_specification": out["extra"][k]["map_specification"],
                })
            continue
        pred[name][test] = out["pred"]
        if out["proba"] is not None:
            proba[name][test] = out["proba"]
        time_rows.append({"classifier": name, "fold": f, "fit_s": out["fit_s"],
                          "predict_s": out["predict_s"]})
        for k, mo in enumerate(objectives):
            fold_rows.append({"classifier": name, "objective": mo, "fold": f,
                              "f1": weighted_f1(labels[mo].to_numpy()[test],
                                                 out["pred"][:, k])})

    f1 = pd.DataFrame(
        [[weighted_f1(labels[mo].to_numpy(), pred[name][:, k])
          for k, mo in enumerate(objectives)] for name in names],
        index=pd.Index(names, name="classifier"), columns=objectives,
    )
    # pooled out-of-fold probabilities, as the F1; nan (n/a) unless every fold gave them
    scores = {name: [probability_scores(labels[mo].to_numpy(), proba[name][:, k])
                     for k, mo in enumerate(objectives)] for name in names}
    log_loss, brier = (
        pd.DataFrame([[s[metric] for s in scores[name]] for name in names],
                     index=pd.Index(names, name="classifier"), columns=objectives)
        for metric in ("log_loss", "brier"))
    times = (pd.DataFrame(time_rows).groupby("classifier", sort=False)
             .agg(fit_s_mean=("fit_s", "mean"), fit_s_std=("fit_s", lambda s: s.std(ddof=0)),
                  predict_s_mean=("predict_s", "mean"), fit_predict_s_total=("fit_s", "sum")))
    times["fit_predict_s_total"] += pd.DataFrame(time_rows).groupby(
        "classifier", sort=False)["predict_s"].sum()
    times = times.loc[names]
    fold_of = np.empty(len(dataset), dtype=np.int64)
    for f, (_, te) in enumerate(folds):
        fold_of[te] = f
    predictions = pd.DataFrame(
        np.column_stack([pred[name] for name in names]),
        index=pd.Index(dataset.scenario_ids, name="scenario_id"),
        columns=pd.MultiIndex.from_product([names, objectives],
                                           names=["classifier", "objective"]),
    )
    predictions[("fold", "")] = fold_of
    probabilities = pd.DataFrame(
        np.column_stack([proba[name] for name in names]), index=predictions.index,
        columns=predictions.columns[:-1])
    probabilities[("fold", "")] = fold_of
    config = {
        "n_scenarios": len(dataset), "n_splits": n_splits, "seed": seed, "n_jobs": n_jobs,
        "quick": bool(quick), "split": split,
        "fold_sizes": [(len(tr), len(te)) for tr, te in folds],
        "baseline_params": baseline_params, "bsi_params": bsi_params,
        "dataset": dict(dataset.info),
    }
    return ComparisonResult(f1, pd.DataFrame(fold_rows), pd.DataFrame(map_rows), times,
                            predictions, folds, config, time.perf_counter() - start_run,
                            log_loss=log_loss, brier=brier, probabilities=probabilities)
