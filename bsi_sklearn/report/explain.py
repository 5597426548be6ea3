"""`explain`: build the `SpecificationReport` of a fitted classifier."""

from __future__ import annotations

import numbers

import numpy as np
import pandas as pd
from sklearn.metrics import confusion_matrix, f1_score
from sklearn.utils.validation import check_is_fitted

from bsi_sklearn.data.traces import check_consistent_traces, check_traces
from bsi_sklearn.param_validation import Interval, validate_params
from bsi_sklearn.report.specification_report import SpecificationReport
from bsi_sklearn.report.wording import (
    _KINDS,
    _check_descriptions,
    _clause_condition,
    _difference,
    _sort_key,
    clause_sentence,
    clause_specification,
    ordered_clauses,
)

__all__ = ["explain"]


_CONSTRAINTS = {"top_k": [Interval(numbers.Integral, 1, None, closed="left")],
                "title": [str, None]}

def explain(classifier, X=None, y=None, descriptions=None, top_k=5, *, title=None,
            demo_names=None, negations=None):
    """Explain a fitted classifier: its MAP specification, posterior and verdicts.

    Parameters
    ----------
    classifier : BSIClassifier
        A fitted classifier.
    X : demonstrations, default=None
        Any format accepted by ``classifier.predict``. Adds the clause-by-demonstration
        satisfaction heatmap and, for every demonstration the classifier predicts
        unacceptable, the MAP clauses it violates.
    y : array-like of shape (n_demos,), default=None
        Labels of ``X`` (values of ``classifier.classes_``). Adds the MAP specification's
        confusion matrix and F1.
    descriptions : dict, default=None
        Proposition -> short phrase in the present tense (``{"omega_3": "POI 3 is
        visited"}``), used in the sentences (see :func:`clause_sentence`) and the figures.
        Propositions without a description read ``"<name> holds"``.
    top_k : int, default=5
        Number of most probable specifications listed.
    title : str, default=None
        Report title; ``"BSI specification report"`` when omitted.
    demo_names : sequence of str, default=None
        A name per demonstration of ``X``; their indices when omitted.
    negations : None, False or mapping, default=None
        Which propositions negate others in the readable formulas and the sentences
        (:meth:`Specification.readable`): by default ``"!q"`` negates ``q``; a mapping
        ``{negated: proposition}`` (``NegationAugmenter.negations_``,
        ``EventLogEncoder.negations_``) names exactly those; ``False`` none.

    Returns
    -------
    SpecificationReport

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn import BSIClassifier
    >>> X = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]]),
    ...      np.array([[1, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1]]),
    ...      np.array([[1, 0, 0], [1, 0, 1], [1, 1, 1]])]
    >>> clf = BSIClassifier(global_candidates=[0], subtasks=[1, 2]).fit(X, [1, 1, 0])
    >>> report = explain(clf, X, [1, 1, 0],
    ...                  descriptions={0: "the robot is safe", 1: "the part is picked",
    ...                                2: "the part is placed"})
    >>> print(report.ltl)
    G(0) & F(1) & F(2) & (!2 U 1)
    >>> for sentence in report.sentences:
    ...     print(sentence)
    Always, the robot is safe.
    Eventually, the part is picked.
    Eventually, the part is placed.
    The part is picked before the part is placed.
    >>> report.violations
    {'2': [('U', 1, 2)]}
    >>> report.f1_weighted
    1.0
    """
    check_is_fitted(classifier, ["posterior_", "map_specification_"])
    posterior = classifier.posterior_
    roles = posterior.roles
    names = list(roles.names)
    descriptions = _check_descriptions(descriptions, names)
    validate_params({"top_k": top_k, "title": title}, _CONSTRAINTS, "explain")
    if title is None:
        title = "BSI specification report"
    if y is not None and X is None:
        raise ValueError("y was given without X: labels need their demonstrations")

    spec = classifier.map_specification_
    conds = spec.conditions
    keys = ordered_clauses(spec)
    # untested clauses (issue 20); a classifier pickled before they were recorded has none
    vacuous = getattr(classifier, "vacuous_clauses_", frozenset())
    implied = {("U", a, b) for a, b in spec.implied_orders()}
    marginals = posterior.clause_marginals()
    marginal = dict(zip(marginals.index, marginals.to_numpy()))
    clauses = pd.DataFrame(
        {
            "kind": [_KINDS[k[0]] for k in keys],
            "ltl": [clause_specification(k, conds).to_ltl() for k in keys],
            "latex": [clause_specification(k, conds).to_ltl(latex=True) for k in keys],
            "readable": [clause_specification(k, conds).readable(negations=negations)
                         for k in keys],
            "sentence": [clause_sentence(k, conds, descriptions, negations=negations)
                         for k in keys],
            "inclusion_probability": [float(marginal.get(k, np.nan)) for k in keys],
            "implied": [k in implied for k in keys],
            "vacuous": [k in vacuous for k in keys],
        },
        index=pd.Index(keys, tupleize_cols=False, name="clause", dtype=object),
    )
    frame = posterior.to_frame(k=top_k)
    top = pd.DataFrame(
        {"probability": frame["probability"].to_numpy(), "ltl": frame["ltl"].to_numpy(),
         "readable": [s.readable(vacuous, negations=negations)
                      for s in frame["specification"]],
         "n_clauses": (frame["n_globals"] + frame["n_eventuals"] + frame["n_orders"]
                       + frame.get("n_patterns", 0)).to_numpy(),
         "difference": [_difference(s, spec, negations) for s in frame["specification"]]},
        index=pd.RangeIndex(1, len(frame) + 1, name="rank"),
    )
    diagnostics = getattr(classifier, "mcmc_diagnostics_", None)
    inference = {
        "method": getattr(classifier, "inference_", "unknown"),
        "prior": classifier.prior,
        "likelihood": classifier.likelihood,
        "dropped_mass": float(posterior.dropped_mass),
        "rhat": None if not diagnostics else float(diagnostics["rhat"]),
        "max_missed_mass": (None if not diagnostics or "max_missed_mass" not in diagnostics
                            or diagnostics.get("sampled")
                            else float(diagnostics["max_missed_mass"])),
        # A posterior too diffuse to list is reported by its samples: the chains agree when
        # each clause's inclusion does (the missed mass weighs states exactly, and says
        # nothing there).
        "inclusion_rhat": (float(diagnostics["inclusion_rhat"])
                           if diagnostics and diagnostics.get("sampled") else None),
    }
    fields = dict(
        title=title, specification=spec, ltl=spec.to_ltl(), ltl_latex=spec.to_ltl(latex=True),
        readable=spec.readable(vacuous, negations=negations), negations=negations,
        vacuous_clauses=frozenset(vacuous),
        clauses=clauses, descriptions=descriptions, top=top,
        map_probability=float(posterior.probabilities[posterior.map_index]),
        entropy=posterior.entropy(),
        n_unique_specifications=len(posterior), clause_marginals=marginals,
        order_edges=sorted(spec.orders - spec.implied_orders(),
                           key=lambda o: (_sort_key(o[0]), _sort_key(o[1]))),
        inference=inference,
        roles_table=_roles_table(roles),
        demo_names=None, clause_states=None, map_satisfied=None, proba=None, proba_name=None,
        predicted_acceptable=None, violations=None, labels=None, confusion_matrix=None,
        f1=None, f1_weighted=None, vote_f1_weighted=None,
    )
    if X is not None:
        fields.update(_demonstration_fields(classifier, X, y, keys, conds, demo_names))
    return SpecificationReport(**fields)


def _roles_table(roles):
    glob = set(roles.global_names())
    subs = set(roles.subtask_names())
    cond_of = {}
    for w, c in roles.condition_names().items():
        cond_of.setdefault(c, []).append(w)
    rows = []
    for name in roles.names:
        parts = []
        if name in glob:
            parts.append("global candidate")
        if name in subs:
            parts.append("subtask")
        if name in cond_of:
            parts.append("condition of " + ", ".join(str(w) for w in cond_of[name]))
        rows.append((name, "; ".join(parts) or "unused"))
    return rows


def _demonstration_fields(classifier, X, y, keys, conds, demo_names):
    traces = check_traces(X, binarize=classifier.binarize, estimator_name="explain")
    check_consistent_traces(traces, classifier.n_features_in_,
                            getattr(classifier, "feature_names_in_", None), "explain")
    n = traces.n_demos
    if demo_names is None:
        demo_names = [str(i) for i in range(n)]
    else:
        demo_names = [str(d) for d in demo_names]
        if len(demo_names) != n:
            raise ValueError(f"demo_names has {len(demo_names)} entries for {n} demonstrations")
        if len(set(demo_names)) != n:
            raise ValueError("demo_names must be unique")
    names = list(classifier.posterior_.roles.names)
    col = {p: i for i, p in enumerate(names)}
    single = [clause_specification(k, conds) for k in keys]
    states = np.zeros((len(keys), n), dtype=int)
    for i in range(n):
        trace = traces.trace(i)
        for r, (k, s) in enumerate(zip(keys, single)):
            if not s.satisfied_by(trace, names):
                states[r, i] = 0
            else:
                c = _clause_condition(k, conds)
                states[r, i] = 2 if c is not None and not trace[0, col[c]] else 1
    map_satisfied = (states > 0).all(axis=0)
    # The classifier's own verdicts: its decision rule lives in BSIClassifier.predict only.
    proba = classifier.predict_proba(X)[:, 1]
    predicted_acceptable = np.asarray(classifier.predict(X) == classifier.classes_[1])
    violations = {demo_names[i]: [k for r, k in enumerate(keys) if states[r, i] == 0]
                  for i in range(n) if not predicted_acceptable[i]}
    fields = dict(
        demo_names=demo_names,
        clause_states=pd.DataFrame(states, index=pd.Index(keys, tupleize_cols=False,
                                                          name="clause", dtype=object),
                                   columns=pd.Index(demo_names, name="demonstration")),
        map_satisfied=map_satisfied, proba=proba, predicted_acceptable=predicted_acceptable,
        proba_name=("posterior mass satisfied" if getattr(classifier, "vote", None) ==
                    "satisfaction" else "P(acceptable)"),
        violations=violations,
    )
    if y is not None:
        labels = _check_y(y, n, classifier.classes_)
        cm = confusion_matrix(labels, map_satisfied, labels=[True, False])
        fields.update(
            labels=labels,
            confusion_matrix=pd.DataFrame(
                cm, index=pd.Index(["acceptable", "unacceptable"], name="label"),
                columns=pd.Index(["acceptable", "unacceptable"], name="MAP specification")),
            f1=float(f1_score(labels, map_satisfied, pos_label=True, zero_division=0.0)),
            f1_weighted=float(f1_score(labels, map_satisfied, average="weighted",
                                       labels=[True, False], zero_division=0.0)),
            vote_f1_weighted=float(f1_score(labels, predicted_acceptable, average="weighted",
                                            labels=[True, False], zero_division=0.0)),
        )
    return fields


def _check_y(y, n, classes):
    arr = np.asarray(y)
    if arr.ndim != 1 or len(arr) != n:
        raise ValueError(f"y must be 1-D with one label per demonstration ({n}), got shape "
                         f"{arr.shape}")
    known = np.asarray(classes).tolist()
    for i, v in enumerate(arr.tolist()):
        if not any(v == c for c in known):
            raise ValueError(f"y[{i}] = {v!r} is not one of the classifier's classes {known}")
    return np.array([v == classes[1] for v in arr], dtype=bool)
