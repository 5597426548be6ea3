"""Metrics comparing inferred specifications (or posteriors) with a ground truth."""

from __future__ import annotations

from collections.abc import Mapping
from numbers import Integral
from typing import NamedTuple

import numpy as np

from bsi_sklearn.param_validation import Interval, validate_params
from bsi_sklearn.specification import Specification

__all__ = [
    "OrderClassification",
    "OrderCounts",
    "jaccard_similarity",
    "expected_similarity",
    "best_similarity",
    "classify_orders",
    "expected_order_counts",
    "similarity_summary",
]


class OrderClassification(NamedTuple):
    """The orders of an inferred specification, split against a ground truth.

    Attributes
    ----------
    correct : frozenset of (a, b)
        Orders that the ground truth also contains.
    incorrect : frozenset of (a, b)
        Orders ``(a, b)`` whose reverse ``(b, a)`` is a ground-truth order.
    extra : frozenset of (a, b)
        Every other order: it over-constrains the task without inducing wrong behaviour.
    """

    correct: frozenset
    incorrect: frozenset
    extra: frozenset

    @property
    def counts(self):
        """The three set sizes as an :class:`OrderCounts`."""
        return OrderCounts(len(self.correct), len(self.incorrect), len(self.extra))


class OrderCounts(NamedTuple):
    """Numbers (or posterior expectations) of correct, incorrect and extra orders."""

    correct: float
    incorrect: float
    extra: float


_SPEC = [Specification]
_TOP_K = [Interval(Integral, 1, None, closed="left")]


def _check_spec(spec, name, caller):
    validate_params({name: spec}, {name: _SPEC}, caller)
    return spec


def jaccard_similarity(spec, truth):
    """Jaccard index between the clause sets of two specifications (paper eq. 13).

    ``L = |C(spec) & C(truth)| / |C(spec) | C(truth)|`` where ``C`` is
    :meth:`Specification.clauses` (globals, eventuals, the transitively closed orders and
    the pattern clauses, ``("P", template, propositions)``).
    Two empty specifications are identical: their similarity is 1.

    Parameters
    ----------
    spec : Specification
        The candidate (inferred) specification.
    truth : Specification
        The ground-truth specification.

    Returns
    -------
    similarity : float
        In ``[0, 1]``; 1 exactly when both specifications have the same clauses.

    See Also
    --------
    expected_similarity : the same index averaged over a posterior.

    Examples
    --------
    >>> from bsi_sklearn.specification import Specification
    >>> truth = Specification(globals=["t"], eventuals=["a", "b"], orders=[("a", "b")])
    >>> spec = Specification(globals=["t"], eventuals=["a"])
    >>> jaccard_similarity(spec, truth)
    0.5
    """
    a = _check_spec(spec, "spec", "jaccard_similarity").clauses()
    b = _check_spec(truth, "truth", "jaccard_similarity").clauses()
    union = len(a | b)
    if union == 0:
        return 1.0
    return len(a & b) / union


def _as_distribution(posterior):
    """Return ``(specifications, probabilities)`` sorted by descending probability.

    Accepts an object with ``specifications`` and ``probabilities`` attributes (a
    ``Posterior``), a mapping ``Specification -> probability`` or a sequence of
    ``(Specification, probability)`` pairs. Probabilities are normalised to sum to 1.
    """
    if hasattr(posterior, "specifications") and hasattr(posterior, "probabilities"):
        specs = list(posterior.specifications)
        probs = posterior.probabilities
    elif isinstance(posterior, Specification):
        specs, probs = [posterior], [1.0]
    else:
        if isinstance(posterior, Mapping):
            pairs = list(posterior.items())
        else:
            try:
                pairs = list(posterior)
            except TypeError:
                raise ValueError(
                    "posterior must be a Posterior, a mapping Specification -> probability or "
                    f"a sequence of (Specification, probability) pairs, got "
                    f"{type(posterior).__name__}"
                ) from None
        specs, probs = [], []
        for i, pair in enumerate(pairs):
            try:
                s, p = pair
            except (TypeError, ValueError):
                raise ValueError(
                    f"posterior entry {i} is not a (Specification, probability) pair"
                ) from None
            specs.append(s)
            probs.append(p)
    probs = _check_probabilities(probs, len(specs))
    for i, s in enumerate(specs):
        if not isinstance(s, Specification):
            raise ValueError(
                f"posterior entry {i} is not a Specification (got {type(s).__name__})"
            )
    total = probs.sum()
    order = np.argsort(-probs, kind="stable")
    return [specs[i] for i in order], probs[order] / total


class _Profile(NamedTuple):
    """Per-specification counts against the truth, most probable first."""

    probs: np.ndarray
    inter: np.ndarray  # clauses shared with the truth
    size: np.ndarray  # clauses of the specification
    correct: np.ndarray
    incorrect: np.ndarray
    extra: np.ndarray
    truth_size: int

    @property
    def similarity(self):
        union = self.size + self.truth_size - self.inter
        return np.where(union > 0, self.inter / np.maximum(union, 1), 1.0)


def _profile(posterior, truth, caller):
    """Count, for every specification of ``posterior``, what it shares with ``truth``.

    Uses ``posterior.clause_matrix()`` (boolean ``(n_specs, n_keys)``, columns in the order
    of ``posterior.clause_keys()``) when the posterior offers both: no ``Specification``
    needs to be built, which matters for posteriors of 10^5 specifications.
    """
    _check_spec(truth, "truth", caller)
    true_clauses = truth.clauses()
    matrix = getattr(posterior, "clause_matrix", None)
    keys = getattr(posterior, "clause_keys", None)
    if callable(matrix) and callable(keys) and hasattr(posterior, "probabilities"):
        keys = list(keys())
        M = np.asarray(matrix(), dtype=bool)
        probs = _check_probabilities(posterior.probabilities, M.shape[0])
        if M.ndim != 2 or M.shape[1] != len(keys):
            raise ValueError(
                f"posterior.clause_matrix() has shape {M.shape} for {len(keys)} clause keys"
            )
        in_truth = np.array([k in true_clauses for k in keys], dtype=bool)
        is_order = np.array([k[0] == "U" for k in keys], dtype=bool)
        reverses = np.array(
            [k[0] == "U" and ("U", k[2], k[1]) in true_clauses for k in keys], dtype=bool
        )
        Mi = M.astype(np.int64)
        inter = Mi @ in_truth
        correct = Mi @ (in_truth & is_order)
        incorrect = Mi @ reverses
        extra = Mi @ is_order - correct - incorrect
        size = Mi.sum(axis=1)
        order = np.argsort(-probs, kind="stable")
        return _Profile(probs[order] / probs.sum(), inter[order], size[order], correct[order],
                        incorrect[order], extra[order], len(true_clauses))
    specs, probs = _as_distribution(posterior)
    counts = np.empty((len(specs), 5), dtype=np.int64)
    for i, spec in enumerate(specs):
        shared_orders = spec.orders & truth.orders
        reversed_orders = sum((b, a) in truth.orders for a, b in spec.orders)
        counts[i] = (
            len(spec.globals & truth.globals) + len(spec.eventuals & truth.eventuals)
            + len(shared_orders),
            spec.n_conjuncts,
            len(shared_orders),
            reversed_orders,
            len(spec.orders) - len(shared_orders) - reversed_orders,
        )
    return _Profile(probs, *counts.T, len(true_clauses))


def _check_probabilities(probs, n):
    try:
        probs = np.asarray(probs, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError("posterior probabilities must be numbers") from None
    if probs.ndim != 1 or len(probs) != n:
        raise ValueError(
            f"posterior has {n} specifications but probabilities of shape {probs.shape}"
        )
    if n == 0:
        raise ValueError("posterior is empty: it holds no specification")
    if not np.all(np.isfinite(probs)) or np.any(probs < 0):
        raise ValueError("posterior probabilities must be finite and non-negative")
    if probs.sum() <= 0:
        raise ValueError("posterior probabilities sum to zero")
    return probs


def expected_similarity(posterior, truth):
    """Posterior expectation of the Jaccard similarity to the ground truth.

    ``E[L] = sum_phi P(phi | D) L(phi)``, the paper's measure of how far the inferred
    distribution lies from the ground truth.

    Parameters
    ----------
    posterior : Posterior, mapping or sequence of (Specification, float)
        Anything with ``specifications`` and ``probabilities`` attributes, a mapping
        ``Specification -> probability``, or ``(Specification, probability)`` pairs.
        Probabilities are normalised to sum to 1.
    truth : Specification
        The ground-truth specification.

    Returns
    -------
    similarity : float

    Examples
    --------
    >>> from bsi_sklearn.specification import Specification
    >>> truth = Specification(eventuals=["a", "b"])
    >>> posterior = [(truth, 0.75), (Specification(eventuals=["a"]), 0.25)]
    >>> expected_similarity(posterior, truth)
    0.875
    """
    prof = _profile(posterior, truth, "expected_similarity")
    return float(np.dot(prof.probs, prof.similarity))


def best_similarity(posterior, truth, k=5):
    """Highest Jaccard similarity among the ``k`` most probable specifications.

    Parameters
    ----------
    posterior : Posterior, mapping or sequence of (Specification, float)
        See :func:`expected_similarity`.
    truth : Specification
        The ground-truth specification.
    k : int, default=5
        How many of the most probable specifications to consider (the paper uses 5); ties
        in probability keep the posterior's own order.

    Returns
    -------
    similarity : float
        1.0 exactly when the ground truth is among the top ``k``.

    Examples
    --------
    >>> from bsi_sklearn.specification import Specification
    >>> truth = Specification(eventuals=["a", "b"])
    >>> posterior = [(Specification(eventuals=["a"]), 0.6), (truth, 0.4)]
    >>> best_similarity(posterior, truth, k=1), best_similarity(posterior, truth, k=2)
    (0.5, 1.0)
    """
    k = _check_k(k, "best_similarity")
    prof = _profile(posterior, truth, "best_similarity")
    return float(prof.similarity[:k].max())


def _check_k(k, caller):
    validate_params({"k": k}, {"k": _TOP_K}, caller)
    return int(k)


def similarity_summary(posterior, truth, k=5):
    """All the paper's ground-truth measures of a posterior, in one pass.

    Parameters
    ----------
    posterior : Posterior, mapping or sequence of (Specification, float)
        See :func:`expected_similarity`.
    truth : Specification
        The ground-truth specification.
    k : int, default=5
        Size of the top list for ``best_similarity`` and ``truth_in_top_k``.

    Returns
    -------
    summary : dict
        ``expected_similarity``, ``best_similarity`` (top ``k``), ``map_similarity``,
        ``map_is_truth``, ``truth_in_top_k``, ``truth_rank`` (1 for the MAP; None when the
        truth has no mass), ``truth_probability``, ``n_specifications`` and the expected
        numbers of ``correct_orders``, ``incorrect_orders`` and ``extra_orders``.

    Examples
    --------
    >>> from bsi_sklearn.specification import Specification
    >>> truth = Specification(eventuals=["a", "b"], orders=[("a", "b")])
    >>> posterior = [(Specification(eventuals=["a", "b"]), 0.6), (truth, 0.4)]
    >>> summary = similarity_summary(posterior, truth)
    >>> summary["truth_rank"], summary["map_similarity"], summary["correct_orders"]
    (2, 0.6666666666666666, 0.4)
    """
    k = _check_k(k, "similarity_summary")
    prof = _profile(posterior, truth, "similarity_summary")
    sim = prof.similarity
    exact = np.flatnonzero((prof.inter == prof.truth_size) & (prof.size == prof.truth_size))
    rank = int(exact[0]) + 1 if len(exact) else None
    return {
        "expected_similarity": float(np.dot(prof.probs, sim)),
        "best_similarity": float(sim[:k].max()),
        "map_similarity": float(sim[0]),
        "map_is_truth": rank == 1,
        "truth_in_top_k": rank is not None and rank <= k,
        "truth_rank": rank,
        "truth_probability": float(prof.probs[exact[0]]) if len(exact) else 0.0,
        "n_specifications": int(len(prof.probs)),
        "correct_orders": float(np.dot(prof.probs, prof.correct)),
        "incorrect_orders": float(np.dot(prof.probs, prof.incorrect)),
        "extra_orders": float(np.dot(prof.probs, prof.extra)),
    }


def classify_orders(spec, truth):
    """Split the orders of ``spec`` into correct, incorrect and extra ones.

    An inferred order ``(a, b)`` (*a precedes b*) is *correct* if the ground truth contains
    it, *incorrect* if the ground truth contains its reverse ``(b, a)``, and *extra*
    otherwise. Both sets of orders are transitively closed, as :class:`Specification`
    stores them.

    Parameters
    ----------
    spec : Specification
        The inferred specification.
    truth : Specification
        The ground-truth specification.

    Returns
    -------
    classification : OrderClassification
        Named tuple of frozensets ``(correct, incorrect, extra)``; ``.counts`` gives their
        sizes.

    Examples
    --------
    >>> from bsi_sklearn.specification import Specification
    >>> truth = Specification(orders=[("a", "b"), ("b", "c")])
    >>> spec = Specification(orders=[("a", "b"), ("c", "a"), ("d", "a")])
    >>> result = classify_orders(spec, truth)
    >>> sorted(result.correct), sorted(result.incorrect), sorted(result.extra)
    ([('a', 'b')], [('c', 'a'), ('c', 'b')], [('d', 'a'), ('d', 'b')])
    >>> result.counts
    OrderCounts(correct=1, incorrect=2, extra=2)
    """
    inferred = _check_spec(spec, "spec", "classify_orders").orders
    true = _check_spec(truth, "truth", "classify_orders").orders
    correct = inferred & true
    incorrect = frozenset(p for p in inferred if (p[1], p[0]) in true)
    extra = inferred - correct - incorrect
    return OrderClassification(frozenset(correct), incorrect, frozenset(extra))


def expected_order_counts(posterior, truth):
    """Posterior expectation of the numbers of correct, incorrect and extra orders.

    Parameters
    ----------
    posterior : Posterior, mapping or sequence of (Specification, float)
        See :func:`expected_similarity`.
    truth : Specification
        The ground-truth specification.

    Returns
    -------
    counts : OrderCounts
        Named tuple of floats ``(correct, incorrect, extra)``.

    Examples
    --------
    >>> from bsi_sklearn.specification import Specification
    >>> truth = Specification(orders=[("a", "b")])
    >>> posterior = [(truth, 0.5), (Specification(orders=[("b", "a")]), 0.5)]
    >>> expected_order_counts(posterior, truth)
    OrderCounts(correct=0.5, incorrect=0.5, extra=0.0)
    """
    prof = _profile(posterior, truth, "expected_order_counts")
    return OrderCounts(
        float(np.dot(prof.probs, prof.correct)),
        float(np.dot(prof.probs, prof.incorrect)),
        float(np.dot(prof.probs, prof.extra)),
    )
