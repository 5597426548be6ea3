"""`Posterior`: a categorical distribution over unique canonical specifications."""

import numbers
import os

import numpy as np
import pandas as pd

from bsi_sklearn.data.traces import Traces, check_consistent_traces, check_traces
from bsi_sklearn.io.posterior_file import (
    MAX_LISTED,
    SCHEMA,
    SCHEMA_VERSION,
    dump_posterior,
    parse_posterior,
    read_posterior,
    write_posterior,
)
from bsi_sklearn.model.clauses import (
    clause_index_eventual,
    clause_index_order,
    clause_masks,
    clause_sums,
    clause_truth,
    n_clauses,
    pack_rows,
)
from bsi_sklearn.param_validation import Interval, validate_params
from bsi_sklearn.satisfaction import vote
from bsi_sklearn.specification import Specification

__all__ = ["Posterior", "SCHEMA", "SCHEMA_VERSION"]


class Posterior:
    """Posterior over specifications, sorted by decreasing probability.

    Built by :class:`~bsi_sklearn.BSIClassifier`; not usually constructed by hand.

    Parameters
    ----------
    structures : ndarray of shape (n_specs, n_subtasks)
        Parent array of every specification's order forest (-1 for roots).
    tau_masks : ndarray of shape (n_specs, n_globals + n_patterns), bool
        Which global candidates, then which pattern clauses (``roles.patterns``), every
        specification includes.
    w1_masks : ndarray of shape (n_specs, n_subtasks), bool
        Which eventual clauses every specification includes.
    probabilities : ndarray of shape (n_specs,)
        Normalised probabilities, in decreasing order.
    roles : Roles
        Proposition roles the hypotheses refer to.
    clause_marginals : ndarray of shape (n_clauses,), default=None
        Inclusion probability of every candidate clause slot; computed from the specifications
        when omitted (exact inference passes marginals over the full support).
    dropped_mass : float, default=0.0
        Posterior mass left out of ``specifications`` (exact inference with ``tol``).
    map_index : int, default=0
        Position of the most probable specification. Not 0 only for a posterior reported by
        its samples (too diffuse to list, ``mcmc_diagnostics_["sampled"]``): there the
        probabilities are sample frequencies, and the most probable specification found may
        have been sampled less often than others, or never (probability 0).

    Attributes
    ----------
    specifications : list of Specification
    probabilities : ndarray
    dropped_mass : float
    map_index : int
    map_specification : Specification
        The most probable specification, ``specification(map_index)``.
    vacuous_clauses : frozenset of clause keys
        Candidate clauses no training demonstration violates, set apart by :meth:`to_frame`
        (:meth:`mark_vacuous`, called by ``BSIClassifier.fit``; empty for a file's posterior).

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn import BSIClassifier
    >>> X = [np.array([[1, 1, 0], [1, 0, 1]]), np.array([[1, 1, 0], [1, 1, 1]])]
    >>> clf = BSIClassifier(prior="sets_of_chains", random_state=0).fit(X)
    >>> post = clf.posterior_
    >>> post.top(1)[0][0] == clf.map_specification_
    True
    >>> float(post.probabilities.sum())
    1.0
    """

    vacuous_clauses = frozenset()
    map_index = 0  # a posterior pickled before the MAP's position was recorded listed it first

    def __init__(self, structures, tau_masks, w1_masks, probabilities, roles,
                 clause_marginals=None, dropped_mass=0.0, map_index=0):
        self._structures = np.ascontiguousarray(structures, dtype=np.int64)
        self._tau = np.ascontiguousarray(tau_masks, dtype=bool)
        self._w1 = np.ascontiguousarray(w1_masks, dtype=bool)
        self.probabilities = np.asarray(probabilities, dtype=float)
        self.roles = roles
        self.dropped_mass = float(dropped_mass)
        if not 0 <= int(map_index) < len(self.probabilities):
            raise ValueError(f"Posterior: map_index={map_index!r} is not the position of one "
                             f"of the {len(self.probabilities)} specifications")
        self.map_index = int(map_index)
        self._masks = clause_masks(
            self._structures, self._tau, self._w1, roles.n_global_slots, roles.n_subtasks
        )
        if clause_marginals is None:
            clause_marginals = self._marginals_from_specs()
        self._marginals = np.asarray(clause_marginals, dtype=float)
        self._specs = None

    @classmethod
    def from_result(cls, result, roles):
        """The posterior of an inference result (:func:`bsi_sklearn.inference.policy.infer`).

        Parameters
        ----------
        result : bsi_sklearn.inference.policy.InferenceResult
        roles : Roles
            The roles the clause truth was computed with.

        Returns
        -------
        Posterior
        """
        return cls(result.structures, result.tau_masks, result.w1_masks, result.probabilities,
                   roles, clause_marginals=result.clause_marginals,
                   dropped_mass=result.dropped_mass, map_index=result.map_index)

    # ------------------------------------------------------------------ containers
    def __len__(self):
        return len(self.probabilities)

    def __repr__(self):
        return (
            f"Posterior(n_specifications={len(self)}, map={self.map_specification}, "
            f"p_map={self.probabilities[self.map_index]:.4g})"
        )

    def specification(self, i):
        """The ``i``-th listed specification (by decreasing probability)."""
        return self._build_spec(i)

    @property
    def map_specification(self):
        """The most probable specification (:attr:`map_index`)."""
        return self._build_spec(self.map_index)

    @property
    def specifications(self):
        """All specifications, most probable first (built on first access)."""
        if self._specs is None:
            self._specs = [self._build_spec(i) for i in range(len(self))]
        return self._specs

    def top(self, k=5):
        """The ``k`` most probable specifications as ``(Specification, probability)`` pairs."""
        validate_params({"k": k}, {"k": [Interval(numbers.Integral, 1, None, closed="left")]},
                        "Posterior.top")
        return [(self._build_spec(i), float(self.probabilities[i]))
                for i in range(min(k, len(self)))]

    def to_frame(self, k=None, *, negations=None):
        """The posterior as a DataFrame: rank, LTL formula, probability, conjunct counts.

        Columns: ``specification``, ``ltl`` (the full formula), ``readable`` (orders as chains,
        :attr:`vacuous_clauses` set apart, negations without ``!!``:
        :meth:`Specification.readable`), ``probability``, ``n_globals``, ``n_eventuals``,
        ``n_orders``.

        Parameters
        ----------
        k : int, default=None
            Keep only the ``k`` most probable specifications.
        negations : None, False or mapping, default=None
            Which propositions negate others, for ``readable``
            (:meth:`Specification.readable`; by default ``"!p"`` negates ``p``).
        """
        n = len(self) if k is None else min(int(k), len(self))
        specs = [self._build_spec(i) for i in range(n)]
        return pd.DataFrame(
            {
                "specification": specs,
                "ltl": [s.to_ltl() for s in specs],
                "readable": [s.readable(self.vacuous_clauses, negations=negations)
                             for s in specs],
                "probability": self.probabilities[:n],
                "n_globals": [len(s.globals) for s in specs],
                "n_eventuals": [len(s.eventuals) for s in specs],
                "n_orders": [len(s.orders) for s in specs],
                **({"n_patterns": [len(s.patterns) for s in specs]}
                   if self.roles.patterns else {}),
            },
            index=pd.RangeIndex(n, name="rank"),
        )

    # ------------------------------------------------------------------ summaries
    def entropy(self):
        """Shannon entropy (nats) of the distribution over unique specifications."""
        p = self.probabilities[self.probabilities > 0]
        return float(-(p * np.log(p)).sum())

    def clause_keys(self):
        """Key of every candidate clause, in the order of :meth:`clause_marginals`."""
        g, s = self.roles.global_names(), self.roles.subtask_names()
        keys = [("G", p) for p in g] + [("P", *key) for key in self.roles.pattern_keys()]
        keys += [("F", w) for w in s]
        keys += [("U", a, b) for a in s for b in s if a != b]
        return keys

    def _clause_slots(self):
        n_g, n = self.roles.n_global_slots, self.roles.n_subtasks
        return list(range(n_g)) + [clause_index_eventual(w, n_g) for w in range(n)] + [
            clause_index_order(a, b, n_g, n) for a in range(n) for b in range(n) if a != b
        ]

    def clause_matrix(self):
        """Boolean matrix ``(n_specs, n_clauses)``: which candidate clauses each specification has.

        Columns follow :meth:`clause_keys`; no Specification objects are built, so this is the
        fast path for metrics over large posteriors.
        """
        n_cl = n_clauses(self.roles.n_global_slots, self.roles.n_subtasks)
        bits = np.unpackbits(self._masks.view(np.uint8), axis=1, bitorder="little")[:, :n_cl]
        return bits[:, self._clause_slots()].astype(bool)

    def clause_marginals(self):
        """Posterior inclusion probability of every candidate clause.

        Returns
        -------
        pandas.Series
            Indexed by clause keys ``("G", p)``, ``("F", w)``, ``("U", a, b)``.

        Notes
        -----
        An order key reads in the order of events, not of the formula: ``("U", a, b)`` means
        *a precedes b*, the clause ``(!b U a)`` (b does not happen before a does), so the
        subtasks appear in the key in the reverse of their order in the formula's text. The
        same keys are used by :meth:`Specification.clauses` and the reports.

        Examples
        --------
        >>> import numpy as np
        >>> from bsi_sklearn import BSIClassifier
        >>> X = [np.array([[0, 0], [1, 0], [1, 1]])]
        >>> clf = BSIClassifier(global_candidates=[], subtasks=[0, 1], random_state=0).fit(X)
        >>> marginals = clf.posterior_.clause_marginals()
        >>> key = ("U", 0, 1)  # 0 precedes 1: the clause (!1 U 0)
        >>> bool(marginals[key] > marginals[("U", 1, 0)])
        True
        >>> [c for c in clf.map_specification_.clause_strings() if "U" in c]
        ['(!1 U 0)']
        """
        return pd.Series(
            self._marginals[self._clause_slots()],
            index=pd.Index(self.clause_keys(), tupleize_cols=False, name="clause"),
            name="inclusion_probability",
        )

    def _marginals_from_specs(self):
        # Summed over the packed masks: unpacked to floats they would take 8 bytes a clause
        # slot and specification (3 GB for 40,000 sampled specifications of 100 subtasks).
        n_cl = n_clauses(self.roles.n_global_slots, self.roles.n_subtasks)
        weights = np.ascontiguousarray(self.probabilities, dtype=float)[None, :]
        return clause_sums(self._masks, weights)[0, :n_cl]

    def mark_vacuous(self, X, y=None, *, truth=None):
        """Set :attr:`vacuous_clauses` to the candidate clauses every demonstration satisfies.

        ``X``: demonstrations (as ``BSIClassifier.fit`` takes them) or ``Traces``; ``y``: their
        0/1 labels; ``truth``: their clause truth (:func:`~bsi_sklearn.model.clauses.clause_truth`)
        where the caller has computed it (``fit`` has), else it is computed from ``X``.
        Clauses no demonstration violates, acceptable or not, are untested; with no
        unacceptable demonstration none is marked (positives alone separate nothing).
        """
        truth = self._truth(X) if truth is None else truth
        if y is not None and (np.shape(y) != (len(truth),) or not np.isin(y, (0, 1)).all()):
            raise ValueError(f"mark_vacuous: y must be one 0/1 label per demonstration "
                             f"({len(truth)}), got {y!r}")
        marked = truth.all(axis=0)[self._clause_slots()] & (y is None or not np.all(y))
        self.vacuous_clauses = frozenset(k for k, v in zip(self.clause_keys(), marked) if v)
        return self.vacuous_clauses

    # ------------------------------------------------------------------ prediction
    def satisfaction(self, X):
        """Boolean matrix ``(n_specs, n_demos)``: which specification each demonstration meets.

        Costs ``n_specs * n_demos``; meant for inspection of small posteriors.
        """
        words = self._truth_words(X)
        m = self._masks
        return ~((m[:, None, :] & ~words[None, :, :]) != 0).any(axis=2)

    def predict_proba(self, X):
        """The paper's vote, no label noise: column 1 is the posterior mass satisfied.

        Parameters
        ----------
        X : demonstrations (any format ``BSIClassifier.fit`` accepts), or ``Traces``.

        Returns
        -------
        ndarray of shape (n_demos, 2)
        """
        p1 = np.clip(vote(self._masks, self.probabilities, self._truth_words(X)), 0.0, 1.0)
        return np.column_stack([1.0 - p1, p1])

    @property
    def feature_names_in_(self):
        """The propositions' names when they are strings (the columns of the fitted frames).

        ``None`` when the propositions are column indices. Demonstrations given as
        DataFrames must have exactly these columns, in this order, as for a fitted
        :class:`~bsi_sklearn.BSIClassifier`.
        """
        names = self.roles.names
        if all(isinstance(n, str) for n in names):
            return np.asarray(names, dtype=object)
        return None

    def _truth_words(self, X):
        return pack_rows(self._truth(X))

    def _truth(self, X):
        if isinstance(X, Traces):  # already checked by the caller (the classifier)
            traces = X
            if traces.n_props != len(self.roles.names):
                raise ValueError(
                    f"X has {traces.n_props} propositions, but the posterior was inferred "
                    f"over {len(self.roles.names)}"
                )
        else:
            traces = check_traces(X, estimator_name="Posterior")
            check_consistent_traces(traces, len(self.roles.names), self.feature_names_in_,
                                    "Posterior")
        return clause_truth(traces, self.roles)

    # ------------------------------------------------------------------ JSON
    def to_json(self, path=None, *, max_specifications=MAX_LISTED):
        """The posterior as JSON text (the format of ``docs/posterior-schema.json``).

        Parameters
        ----------
        path : str or path-like, default=None
            File to write, in one step (a temporary file renamed over it, so a failed write
            leaves the previous file intact); the text is returned either way.
        max_specifications : int or None, default=10_000
            Most specifications listed: the most probable ones (and the MAP,
            :attr:`map_index`, whatever its rank), their probabilities renormalised, and
            the mass of the others added to ``dropped_mass`` (as exact inference does with
            ``tol``). ``None`` lists them all. The file grows by about 150 bytes a listed
            specification.

        Returns
        -------
        text : str
            An object with ``schema`` (``"bsi-sklearn/posterior"``), ``version``, ``names``
            (the proposition identifiers), ``roles`` (global candidates, subtasks,
            ``[subtask, condition]`` pairs), ``specifications`` (``globals``, ``eventuals``,
            ``orders`` as ``[a, b]`` pairs, and the ``ltl`` text), ``probabilities``,
            ``clause_marginals`` (``[clause key, probability]``, over the whole posterior)
            and ``dropped_mass``. Floats are written exactly, so when every specification is
            listed :meth:`from_json` gives identical predictions; otherwise they differ by at
            most the mass left out.

        Raises
        ------
        ValueError
            When ``path`` is a folder, or its folder is missing or is a file.

        Examples
        --------
        >>> import numpy as np
        >>> from bsi_sklearn import BSIClassifier, Posterior
        >>> X = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]])]
        >>> post = BSIClassifier(subtasks=[1, 2], random_state=0).fit(X).posterior_
        >>> again = Posterior.from_json(post.to_json())
        >>> bool((again.predict_proba(X) == post.predict_proba(X)).all())
        True
        >>> short = Posterior.from_json(post.to_json(max_specifications=1))
        >>> len(short), bool(short.dropped_mass > 0)
        (1, True)
        """
        validate_params(
            {"max_specifications": max_specifications},
            {"max_specifications": [Interval(numbers.Integral, 1, None, closed="left"), None]},
            "Posterior.to_json")
        k = len(self) if max_specifications is None else min(len(self), max_specifications)
        # The most probable first, and the MAP whatever its rank (then last: listed later, it
        # is no more probable than the others kept).
        rows = np.arange(k) if self.map_index < k else np.r_[np.arange(k - 1), self.map_index]
        probs, dropped = self.probabilities[rows], self.dropped_mass
        if k < len(self):
            kept = float(probs.sum())
            # One listed specification carries all the listed mass (the MAP may have none).
            probs = probs / kept if k > 1 else np.ones(1)
            dropped = 1.0 - (1.0 - dropped) * kept
        text = dump_posterior(self.roles, [self._build_spec(i) for i in rows], probs,
                              self.clause_keys(), self._marginals[self._clause_slots()],
                              dropped, map_index=int(np.flatnonzero(rows == self.map_index)[0]))
        if path is not None:
            write_posterior(path, text)
        return text.rstrip("\n")

    @classmethod
    def from_json(cls, text):
        """Read a posterior from the JSON text written by :meth:`to_json`.

        Parameters
        ----------
        text : str, bytes or path-like
            The JSON text. A ``str`` is always text, never a file name; a
            :class:`pathlib.Path` (any ``os.PathLike``) is read as a file, as
            :meth:`read_json` does.

        Returns
        -------
        posterior : Posterior

        Raises
        ------
        ValueError
            Naming the field, when the text is not JSON or breaks a rule of the format
            (``docs/posterior-schema.json``): another schema or version, a missing or unknown
            field, an unknown proposition, orders that are not a forest, probabilities that
            are not a distribution (negative, not numbers, not summing to 1, not in
            decreasing order), a specification listed twice.

        Examples
        --------
        >>> Posterior.from_json("posterior.json")
        Traceback (most recent call last):
        ...
        ValueError: Posterior.from_json: not JSON (Expecting value: line 1 column 1 (char 0)); \
a str is the JSON text: to read a file, pass a pathlib.Path or call Posterior.read_json(path)
        """
        if isinstance(text, os.PathLike):
            return cls.read_json(text)
        if not isinstance(text, (str, bytes, bytearray)):
            raise ValueError("Posterior.from_json: expected the JSON text as str or bytes (or "
                             f"a pathlib.Path), got {type(text).__name__}")
        try:
            doc = parse_posterior(text)
        except ValueError as exc:
            if not str(exc).startswith("Posterior.from_json: not JSON"):
                raise
            raise ValueError(f"{exc}; a str is the JSON text: to read a file, pass a "
                             "pathlib.Path or call Posterior.read_json(path)") from None
        return cls._from_document(doc, "Posterior.from_json")

    @classmethod
    def read_json(cls, path):
        """Read a posterior from a file written by :meth:`to_json`.

        Parameters
        ----------
        path : str or path-like

        Returns
        -------
        posterior : Posterior

        Raises
        ------
        FileNotFoundError
            When there is no such file.
        ValueError
            Naming the file and the field: a folder, a file that is not UTF-8 JSON, or one
            that breaks a rule of the format (see :meth:`from_json`).
        """
        return cls._from_document(read_posterior(path), f"Posterior.read_json: {str(path)!r}")

    @classmethod
    def _from_document(cls, doc, who):
        post = cls(doc.structures, doc.tau_masks, doc.w1_masks, doc.probabilities, doc.roles,
                   dropped_mass=doc.dropped_mass, map_index=doc.map_index)
        expected, keys = post.clause_keys(), doc.marginal_keys
        if len(keys) != len(expected):
            raise ValueError(f"{who}: clause_marginals: {len(keys)} entries for the "
                             f"{len(expected)} candidate clauses of the roles")
        for k, (key, want) in enumerate(zip(keys, expected)):
            if key != want:
                raise ValueError(f"{who}: clause_marginals[{k}]: the key {list(key)!r} should "
                                 f"be {list(want)!r} (the candidate clauses of the roles: G, "
                                 "then F, then U)")
        post._marginals[post._clause_slots()] = doc.marginals
        return post

    # ------------------------------------------------------------------ internals
    def _build_spec(self, i):
        if self._specs is not None:
            return self._specs[i]
        r = self.roles
        g, s = r.global_names(), r.subtask_names()
        n_gp, pats = len(g), r.pattern_keys()
        parent = self._structures[i]
        orders = []
        for v in range(len(parent)):
            a = parent[v]
            while a >= 0:
                orders.append((s[a], s[v]))
                a = parent[a]
        tau = np.flatnonzero(self._tau[i])
        return Specification(
            globals=[g[j] for j in tau if j < n_gp],
            eventuals=[s[w] for w in np.flatnonzero(self._w1[i])],
            orders=orders,
            conditions=r.condition_names(),
            patterns=[pats[j - n_gp] for j in tau if j >= n_gp],
        )


