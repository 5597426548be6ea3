"""The rows of ``bench_event_logs.py``: one fit on one generated event log, and its scores.

:func:`run_row` takes a JSON-able spec (the log's parameters, the method) and returns a dict;
it regenerates the log from its seed (:func:`bsi_sklearn.datasets.make_process_log` is
deterministic), so a child process needs nothing but the spec. ``_event_log_child.py`` runs it
in a fresh interpreter under the parent's limits.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from bsi_sklearn.datasets import make_process_log

__all__ = ["METHODS", "LABELS", "split_log",
           "normalised_clauses", "rule_recovered", "rule_disagreement", "run_row",
           "SCARLET_DIR_ENV", "FRESH_CASES"]

#: Row keys, in display order, and their names in the tables.
METHODS = ("bsi", "logreg", "tree", "minirocket", "scarlet")
LABELS = {"bsi": "BSI (defaults)", "logreg": "Logistic regression (activity counts)",
          "tree": "Decision tree, depth 4 (occurrence)",
          "minirocket": "MiniRocket (encoded traces)", "scarlet": "Scarlet (encoded traces)"}
#: Environment variable naming Scarlet's private install directory (set by the parent).
SCARLET_DIR_ENV = "BSI_EVENT_LOG_SCARLET_DIR"
MINIROCKET_MIN_STEPS = 9
#: Fresh cases of the same process on which the MAP is compared with the hidden rule.
FRESH_CASES = 5000


def split_log(log, spec):
    """Training and test case ids: stratified on the observed labels, seed 0.

    ``n_train`` in the spec fixes the training size (the recovery rows: 200); otherwise 70 %
    of the cases train. Without two cases of each label the split is not stratified.
    """
    from sklearn.model_selection import train_test_split

    y = log.labels.to_numpy()
    strat = y if np.bincount(y, minlength=2).min() >= 2 else None
    size = spec.get("n_train") or 1 - float(spec.get("test_size", 0.3))
    train, test = train_test_split(log.labels.index.to_numpy(), train_size=size,
                                   stratify=strat, random_state=0)
    return list(train), list(test)


def _encoded(train_cases, test_cases, activities, min_steps=1, **encoder):
    """Encoded training and test traces (``EventLogEncoder``'s DataFrames), and its name.

    ``encoder`` are ``EventLogEncoder``'s parameters: BSI takes its defaults (the activities
    and their negations); MiniRocket and Scarlet ``negations=False``, the activities alone
    (a negated column adds nothing a kernel or an operator ``!`` cannot read from the
    activity's). Traces shorter than ``min_steps`` repeat their last state (the finite-trace
    reading), for MiniRocket's kernels of length 9.
    """
    from bsi_sklearn.io import EventLogEncoder

    enc = EventLogEncoder(**encoder).fit(train_cases)
    tr, te = enc.transform(train_cases), enc.transform(test_cases)
    if min_steps > 1:
        tr, te = ([_pad(x, min_steps) for x in xs] for xs in (tr, te))
    name = "EventLogEncoder(" + ", ".join(f"{k}={v!r}" for k, v in encoder.items()) + ")"
    return tr, te, name


def _pad(frame, min_steps):
    if len(frame) >= min_steps:
        return frame
    return frame.iloc[np.minimum(np.arange(min_steps), len(frame) - 1)].reset_index(drop=True)


def _counts(cases, activities):
    index = {a: j for j, a in enumerate(activities)}
    out = np.zeros((len(cases), len(activities)))
    for i, case in enumerate(cases):
        for a in case:
            out[i, index[a]] += 1
    return out


def normalised_clauses(spec):
    """A specification's clause keys, closed under what every trace implies.

    Its ``G``, ``F`` and ``U`` keys (orders transitively closed, as
    :class:`~bsi_sklearn.Specification` stores them), an ``F`` or ``U`` key of a subtask with
    a condition written ``("F|c", w)`` / ``("U|c", a, b)``, and for every unconditional order
    ``(a, b)`` the key ``("F", a)`` it implies (BSI's until is strong: ``(!b U a)`` needs an
    ``a``). Two specifications with the same normalised keys hold on the same traces.
    """
    conds = spec.conditions
    keys = {("G", p) for p in spec.globals}
    for w in spec.eventuals:
        keys.add(("F|" + str(conds[w]), w) if w in conds else ("F", w))
    for a, b in spec.orders:
        if a in conds:
            keys.add(("U|" + str(conds[a]), a, b))
        else:
            keys |= {("U", a, b), ("F", a)}
    return frozenset(keys)


def rule_recovered(map_spec, log):
    """Whether the MAP specification is the hidden rule (:func:`normalised_clauses` equal)."""
    return normalised_clauses(map_spec) == normalised_clauses(log.specification())


def rule_disagreement(map_spec, log, spec, train_cases, n_fresh=FRESH_CASES):
    """The fraction of fresh cases of the log's process on which the MAP and the rule differ.

    A clause that every case of the process satisfies cannot be told from its absence by any
    log, so a MAP with more clauses than the rule (:func:`rule_recovered` false) may still
    accept exactly the cases the rule accepts. The fresh cases are the ``n_fresh`` that
    :func:`~bsi_sklearn.datasets.make_process_log` draws after the log's own (same seed, same
    process and rule: neither depends on ``n_cases``), judged by their clean labels; encoded
    by the encoder fitted on ``train_cases`` (activities it never saw are left out).
    """
    big = make_process_log(spec["n_activities"], spec["n_cases"] + n_fresh, rule=spec["rule"],
                           noise=spec["noise"], random_state=spec["seed"])
    fresh = big.cases()[spec["n_cases"]:]
    truth = big.clean_labels.to_numpy()[spec["n_cases"]:].astype(bool)
    _, encoded, _ = _encoded(train_cases, fresh, log.activities, handle_unknown="ignore",
                             **spec.get("encoder", {}))
    verdict = np.array([map_spec.satisfied_by(x) for x in encoded], dtype=bool)
    return float(np.mean(verdict != truth))


def _scores(pred, truth):
    from sklearn.metrics import accuracy_score, f1_score

    pred = np.asarray(pred).astype(int)
    return {"accuracy": float(accuracy_score(truth, pred)),
            "f1_weighted": float(f1_score(truth, pred, average="weighted", zero_division=0))}


def _fit_logreg(Xtr, ytr):
    from sklearn.linear_model import LogisticRegression
    from sklearn.model_selection import GridSearchCV, StratifiedKFold
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import StandardScaler

    from baselines.practitioner import LOGISTIC_CS

    pipe = make_pipeline(StandardScaler(), LogisticRegression(max_iter=10_000))
    folds = int(min(3, np.bincount(ytr, minlength=2).min()))
    if folds < 2:
        return pipe.fit(Xtr, ytr), 1.0
    search = GridSearchCV(pipe, {"logisticregression__C": list(LOGISTIC_CS)},
                          scoring="neg_log_loss", n_jobs=1, error_score="raise",
                          cv=StratifiedKFold(folds, shuffle=True, random_state=0))
    search.fit(Xtr, ytr)
    return search.best_estimator_, float(search.best_params_["logisticregression__C"])


def _row_practitioner(method, log, train, test, ytr, row):
    cases = dict(zip(log.labels.index, log.cases()))
    tr, te = [cases[c] for c in train], [cases[c] for c in test]
    acts = log.activities
    if method in ("logreg", "tree"):
        t0 = time.perf_counter()
        Ftr = _counts(tr, acts)
        if method == "logreg":
            model, c = _fit_logreg(Ftr, ytr)
            row["hyper"] = f"C={c:g} (3-fold CV, log-loss)"
        else:
            from sklearn.tree import DecisionTreeClassifier

            Ftr = Ftr > 0
            model = DecisionTreeClassifier(max_depth=4, random_state=0).fit(Ftr, ytr)
            row["hyper"] = "max_depth=4"
        row["fit_s"] = time.perf_counter() - t0
        Fte = _counts(te, acts)
        return model.predict(Fte if method == "logreg" else Fte > 0)
    t0 = time.perf_counter()
    Xtr, Xte, row["encoding"] = _encoded(tr, te, acts, MINIROCKET_MIN_STEPS, negations=False)
    row["encode_s"] = time.perf_counter() - t0
    from baselines.practitioner import MiniRocketClassifier

    t0 = time.perf_counter()
    model = MiniRocketClassifier(random_state=0).fit(Xtr, ytr)
    row["fit_s"] = time.perf_counter() - t0
    row["hyper"] = "10,000 kernels, RidgeClassifierCV (LOO)"
    return model.predict(Xte)


def _row_bsi(log, train, test, ytr, row):
    from bsi_sklearn import BSIClassifier

    cases = dict(zip(log.labels.index, log.cases()))
    t0 = time.perf_counter()
    Xtr, Xte, row["encoding"] = _encoded([cases[c] for c in train], [cases[c] for c in test],
                                         log.activities, **row.get("encoder", {}))
    row["encode_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    params = dict(row.get("bsi") or {})  # BSIClassifier's parameters beside the defaults
    clf = BSIClassifier(random_state=0, **params).fit(Xtr, ytr)
    row["fit_s"] = time.perf_counter() - t0
    row["hyper"] = ", ".join([f"{k}={v!r}" for k, v in params.items()]
                             or ["defaults"]) + ", random_state=0"
    row["inference"] = str(getattr(clf, "inference_", ""))
    row["map"] = clf.map_specification_.to_ltl()
    if not ({p for p, _ in log.rule_clauses} - {"existence", "precedence", "absence"}):
        row["rule_recovered"] = bool(rule_recovered(clf.map_specification_, log))
        if not row.get("positive_only"):  # a positive-only log's cases are drawn otherwise
            row["rule_disagreement"] = rule_disagreement(
                clf.map_specification_, log, row, [cases[c] for c in train])
    return clf.predict(Xte)


def _row_scarlet(log, train, test, ytr, row, timeout):
    scarlet_dir = Path(os.environ.get(SCARLET_DIR_ENV, ""))
    if not (scarlet_dir / "Scarlet" / "inferLTL.py").is_file():
        row["status"] = (f"not installed (pip install --target {scarlet_dir} scarlet-ltl==0.0.4,"
                         " or --install-scarlet)")
        return None
    from external_scarlet import ScarletWorker, evaluate_scarlet_formula, parse_scarlet_formula

    cases = dict(zip(log.labels.index, log.cases()))
    Xtr, Xte, row["encoding"] = _encoded([cases[c] for c in train], [cases[c] for c in test],
                                         log.activities, negations=False)
    names = list(Xtr[0].columns)
    worker = ScarletWorker(scarlet_dir, timeout=timeout)
    thres = 0.0 if float(log.labels.ne(log.clean_labels).sum()) == 0 else 0.05
    t0 = time.perf_counter()
    try:
        out = worker.learn([x.to_numpy() for x, y in zip(Xtr, ytr) if y == 1],
                           [x.to_numpy() for x, y in zip(Xtr, ytr) if y == 0], len(names),
                           thres=thres)
    finally:
        worker.close()
    row["fit_s"] = time.perf_counter() - t0
    row["hyper"] = f"thres={thres}"
    if out["formula"] is None:
        row["status"] = f"scarlet: {out['status']}"
        return None
    formula = parse_scarlet_formula(out["formula"], {f"v{i}": n for i, n in enumerate(names)})
    row["map"] = str(formula)
    if out["status"] == "timeout":
        row["status"] = "timeout (best formula so far)"
    return evaluate_scarlet_formula(formula, Xte)


def run_row(spec):
    """One row: generate the log, split it, fit ``spec["method"]``, score on the test cases.

    Scores are against the test cases' clean labels (the rule's truth); training uses the
    observed (noisy) labels. ``positive_only`` in the spec: every case of the log is labelled
    acceptable (BSI then learns from positives only; the clean labels say which are not).
    Returns the spec's fields plus ``status`` (``ok`` or why not), ``accuracy``,
    ``f1_weighted``, ``fit_s``, ``n_train``, ``n_test``, and per method ``hyper``,
    ``encoding``, ``encode_s``, ``map``, ``rule_recovered``, ``rule_disagreement``. ``bsi`` in
    the spec: ``BSIClassifier`` parameters other than the defaults (for example
    ``{"likelihood": "ci"}``).
    """
    row = dict(spec, method_label=LABELS[spec["method"]], status="ok")
    log = make_process_log(spec["n_activities"], spec["n_cases"], rule=spec["rule"],
                           noise=spec["noise"], random_state=spec["seed"],
                           positive_only=bool(spec.get("positive_only", False)))
    train, test = split_log(log, spec)
    ytr = log.labels.loc[train].to_numpy()
    truth = log.clean_labels.loc[test].to_numpy()
    row.update(n_train=len(train), n_test=len(test), rule_text=log.rule,
               train_positive=float(ytr.mean()), test_positive=float(truth.mean()))
    method = spec["method"]
    if method == "minirocket" and len(train) > spec.get("minirocket_max_train", np.inf):
        row["status"] = f"skipped (over {spec['minirocket_max_train']} training cases)"
        return row
    if method == "bsi":
        pred = _row_bsi(log, train, test, ytr, row)
    elif method == "scarlet":
        pred = _row_scarlet(log, train, test, ytr, row, spec.get("timeout", 300))
    else:
        pred = _row_practitioner(method, log, train, test, ytr, row)
    if pred is not None:
        row.update(_scores(pred, truth))
    return row
