"""`Posterior`: a categorical distribution over unique canonical specifications."""

import json
import numbers
from pathlib import Path

import numpy as np
import pandas as pd
from numba import njit

from bsi_sklearn.clauses import (
    clause_index_eventual,
    clause_index_order,
    clause_truth,
    n_clauses,
    pack_rows,
)
from bsi_sklearn.param_validation import Interval, validate_params
from bsi_sklearn.roles import Roles
from bsi_sklearn.specification import Specification
from bsi_sklearn.traces import Traces, check_traces

__all__ = ["Posterior", "SCHEMA", "SCHEMA_VERSION"]

#: Name and version of the JSON form of a posterior (:meth:`Posterior.to_json`).
SCHEMA = "bsi-sklearn/posterior"
SCHEMA_VERSION = 1


@njit(cache=True, nogil=True)
def _clause_masks(structures, tau_masks, w1_masks, n_g, n):
    n_h = structures.shape[0]
    n_cl = n_clauses(n_g, n)
    n_words = (n_cl + 63) // 64
    out = np.zeros((n_h, n_words), dtype=np.uint64)
    one = np.uint64(1)
    for h in range(n_h):
        for j in range(n_g):
            if tau_masks[h, j]:
                out[h, j >> 6] |= one << np.uint64(j & 63)
        for w in range(n):
            if w1_masks[h, w]:
                c = clause_index_eventual(w, n_g)
                out[h, c >> 6] |= one << np.uint64(c & 63)
        for v in range(n):
            a = structures[h, v]
            while a >= 0:
                c = clause_index_order(a, v, n_g, n)
                out[h, c >> 6] |= one << np.uint64(c & 63)
                a = structures[h, a]
    return out


@njit(cache=True, nogil=True)
def _vote(masks, probs, truth_words):
    # P(acceptable) of every demonstration: mass of specifications whose clauses all hold.
    n_d = truth_words.shape[0]
    out = np.zeros(n_d)
    for i in range(n_d):
        acc = 0.0
        for h in range(masks.shape[0]):
            ok = True
            for w in range(masks.shape[1]):
                if masks[h, w] & ~truth_words[i, w]:
                    ok = False
                    break
            if ok:
                acc += probs[h]
        out[i] = acc
    return out


class Posterior:
    """Posterior over specifications, sorted by decreasing probability.

    Built by :class:`~bsi_sklearn.BSIClassifier`; not usually constructed by hand.

    Parameters
    ----------
    structures : ndarray of shape (n_specs, n_subtasks)
        Parent array of every specification's order forest (-1 for roots).
    tau_masks : ndarray of shape (n_specs, n_globals), bool
        Which global candidates every specification includes.
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

    Attributes
    ----------
    specifications : list of Specification
    probabilities : ndarray
    dropped_mass : float

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

    def __init__(self, structures, tau_masks, w1_masks, probabilities, roles,
                 clause_marginals=None, dropped_mass=0.0):
        self._structures = np.ascontiguousarray(structures, dtype=np.int64)
        self._tau = np.ascontiguousarray(tau_masks, dtype=bool)
        self._w1 = np.ascontiguousarray(w1_masks, dtype=bool)
        self.probabilities = np.asarray(probabilities, dtype=float)
        self.roles = roles
        self.dropped_mass = float(dropped_mass)
        self._masks = _clause_masks(
            self._structures, self._tau, self._w1, roles.n_globals, roles.n_subtasks
        )
        if clause_marginals is None:
            clause_marginals = self._marginals_from_specs()
        self._marginals = np.asarray(clause_marginals, dtype=float)
        self._specs = None

    # ------------------------------------------------------------------ containers
    def __len__(self):
        return len(self.probabilities)

    def __repr__(self):
        return (
            f"Posterior(n_specifications={len(self)}, map={self.specification(0)}, "
            f"p_map={self.probabilities[0]:.4g})"
        )

    def specification(self, i):
        """The ``i``-th most probable specification."""
        return self._build_spec(i)

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

    def to_frame(self, k=None):
        """The posterior as a DataFrame: rank, LTL formula, probability, conjunct counts.

        Parameters
        ----------
        k : int, default=None
            Keep only the ``k`` most probable specifications.
        """
        n = len(self) if k is None else min(int(k), len(self))
        specs = [self._build_spec(i) for i in range(n)]
        return pd.DataFrame(
            {
                "specification": specs,
                "ltl": [s.to_ltl() for s in specs],
                "probability": self.probabilities[:n],
                "n_globals": [len(s.globals) for s in specs],
                "n_eventuals": [len(s.eventuals) for s in specs],
                "n_orders": [len(s.orders) for s in specs],
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
        keys = [("G", p) for p in g] + [("F", w) for w in s]
        keys += [("U", a, b) for a in s for b in s if a != b]
        return keys

    def _clause_slots(self):
        n_g, n = self.roles.n_globals, self.roles.n_subtasks
        return list(range(n_g + n)) + [
            clause_index_order(a, b, n_g, n) for a in range(n) for b in range(n) if a != b
        ]

    def clause_matrix(self):
        """Boolean matrix ``(n_specs, n_clauses)``: which candidate clauses each specification has.

        Columns follow :meth:`clause_keys`; no Specification objects are built, so this is the
        fast path for metrics over large posteriors.
        """
        n_cl = self.roles.n_globals + self.roles.n_subtasks + self.roles.n_subtasks ** 2
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
        n_cl = self.roles.n_globals + self.roles.n_subtasks + self.roles.n_subtasks ** 2
        bits = np.unpackbits(
            self._masks.view(np.uint8), axis=1, bitorder="little"
        )[:, :n_cl].astype(float)
        return self.probabilities @ bits

    # ------------------------------------------------------------------ prediction
    def satisfaction(self, X):
        """Boolean matrix ``(n_specs, n_demos)``: which specification each demonstration meets.

        Costs ``n_specs * n_demos``; meant for inspection of small posteriors.
        """
        words = self._truth_words(X)
        m = self._masks
        return ~((m[:, None, :] & ~words[None, :, :]) != 0).any(axis=2)

    def predict_proba(self, X):
        """Posterior voting: column 1 is the mass of specifications each trace satisfies.

        Parameters
        ----------
        X : demonstrations (any format ``BSIClassifier.fit`` accepts), or ``Traces``.

        Returns
        -------
        ndarray of shape (n_demos, 2)
        """
        p1 = np.clip(_vote(self._masks, self.probabilities, self._truth_words(X)), 0.0, 1.0)
        return np.column_stack([1.0 - p1, p1])

    def _truth_words(self, X):
        traces = X if isinstance(X, Traces) else check_traces(X, estimator_name="Posterior")
        n_props = len(self.roles.names)
        if traces.n_props != n_props:
            raise ValueError(
                f"X has {traces.n_props} propositions, but the posterior was inferred over "
                f"{n_props}"
            )
        return pack_rows(clause_truth(traces, self.roles))

    # ------------------------------------------------------------------ JSON
    def to_json(self, path=None):
        """The posterior as JSON: names, roles, specifications, probabilities, marginals.

        Parameters
        ----------
        path : str or path-like, default=None
            File to write; the text is returned either way.

        Returns
        -------
        text : str
            An object with ``schema`` (``"bsi-sklearn/posterior"``), ``version``, ``names``
            (the proposition identifiers), ``roles`` (global candidates, subtasks,
            ``[subtask, condition]`` pairs), ``specifications`` (``globals``, ``eventuals``,
            ``orders`` as ``[a, b]`` pairs, and the ``ltl`` text), ``probabilities``,
            ``clause_marginals`` (``[clause key, probability]``) and ``dropped_mass``.
            Floats are written exactly, so :meth:`from_json` gives identical predictions.

        Examples
        --------
        >>> import numpy as np
        >>> from bsi_sklearn import BSIClassifier, Posterior
        >>> X = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]])]
        >>> post = BSIClassifier(subtasks=[1, 2], random_state=0).fit(X).posterior_
        >>> again = Posterior.from_json(post.to_json())
        >>> bool((again.predict_proba(X) == post.predict_proba(X)).all())
        True
        """
        r = self.roles
        plain = _plain
        doc = {
            "schema": SCHEMA,
            "version": SCHEMA_VERSION,
            "names": [plain(n) for n in r.names],
            "roles": {
                "global_candidates": [plain(n) for n in r.global_names()],
                "subtasks": [plain(n) for n in r.subtask_names()],
                "conditions": [[plain(w), plain(c)] for w, c in r.condition_names().items()],
            },
            "specifications": [
                {"globals": sorted((plain(p) for p in s.globals), key=_json_key),
                 "eventuals": sorted((plain(w) for w in s.eventuals), key=_json_key),
                 "orders": sorted(([plain(a), plain(b)] for a, b in s.orders),
                                  key=lambda o: (_json_key(o[0]), _json_key(o[1]))),
                 "ltl": s.to_ltl()}
                for s in self.specifications
            ],
            "probabilities": self.probabilities.tolist(),
            "clause_marginals": [[[plain(x) for x in key], float(v)]
                                 for key, v in zip(self.clause_keys(),
                                                   self._marginals[self._clause_slots()])],
            "dropped_mass": self.dropped_mass,
        }
        text = json.dumps(doc, indent=1)
        if path is not None:
            Path(path).write_text(text + "\n", encoding="utf-8")
        return text

    @classmethod
    def from_json(cls, source):
        """Read a posterior written by :meth:`to_json`.

        Parameters
        ----------
        source : str or path-like
            The JSON text, or the path of a file holding it.

        Returns
        -------
        posterior : Posterior

        Raises
        ------
        ValueError
            When the text is not a posterior of this schema and version, or is inconsistent
            (an unknown proposition, orders that are not a forest, probabilities that do not
            match the specifications).
        """
        if isinstance(source, Path) or (isinstance(source, str)
                                        and not source.lstrip().startswith("{")):
            source = Path(source).read_text(encoding="utf-8")
        try:
            doc = json.loads(source)
        except json.JSONDecodeError as exc:
            raise ValueError(f"Posterior.from_json: not JSON ({exc})") from None
        if not isinstance(doc, dict) or doc.get("schema") != SCHEMA:
            got = doc.get("schema") if isinstance(doc, dict) else type(doc).__name__
            raise ValueError(f"Posterior.from_json: expected schema {SCHEMA!r}, got {got!r}")
        if doc.get("version") != SCHEMA_VERSION:
            raise ValueError(
                f"Posterior.from_json: schema version {doc.get('version')!r} is not supported; "
                f"this bsi-sklearn reads version {SCHEMA_VERSION}"
            )
        names = list(doc["names"])
        roles_doc = doc["roles"]

        def index(ident, where):
            if ident not in names:
                raise ValueError(f"Posterior.from_json: {where} names unknown proposition "
                                 f"{ident!r}")
            return names.index(ident)

        g = [index(p, "roles.global_candidates") for p in roles_doc["global_candidates"]]
        s = [index(w, "roles.subtasks") for w in roles_doc["subtasks"]]
        cond = np.full(len(s), -1, dtype=np.int64)
        for w, c in roles_doc["conditions"]:
            cond[s.index(index(w, "roles.conditions"))] = index(c, "roles.conditions")
        roles = Roles(np.asarray(g, dtype=np.int64), np.asarray(s, dtype=np.int64), cond, names)
        specs = doc["specifications"]
        probs = np.asarray(doc["probabilities"], dtype=float)
        if len(probs) != len(specs) or len(specs) == 0:
            raise ValueError(f"Posterior.from_json: {len(specs)} specifications but "
                             f"{len(probs)} probabilities")
        g_names, s_names = roles.global_names(), roles.subtask_names()
        structures = np.full((len(specs), len(s)), -1, dtype=np.int64)
        tau = np.zeros((len(specs), len(g)), dtype=bool)
        w1 = np.zeros((len(specs), len(s)), dtype=bool)
        for h, spec in enumerate(specs):
            where = f"specification {h}"
            for p in spec["globals"]:
                tau[h, _position(g_names, p, where)] = True
            for w in spec["eventuals"]:
                w1[h, _position(s_names, w, where)] = True
            structures[h] = _forest([(_position(s_names, a, where), _position(s_names, b, where))
                                     for a, b in spec["orders"]], len(s), where)
        keys = [tuple(k) for k, _ in doc["clause_marginals"]]
        post = cls(structures, tau, w1, probs, roles, dropped_mass=doc["dropped_mass"])
        if keys != post.clause_keys():
            raise ValueError("Posterior.from_json: clause_marginals do not follow the roles")
        post._marginals[post._clause_slots()] = [v for _, v in doc["clause_marginals"]]
        return post

    # ------------------------------------------------------------------ internals
    def _build_spec(self, i):
        if self._specs is not None:
            return self._specs[i]
        r = self.roles
        g, s = r.global_names(), r.subtask_names()
        parent = self._structures[i]
        orders = []
        for v in range(len(parent)):
            a = parent[v]
            while a >= 0:
                orders.append((s[a], s[v]))
                a = parent[a]
        return Specification(
            globals=[g[j] for j in np.flatnonzero(self._tau[i])],
            eventuals=[s[w] for w in np.flatnonzero(self._w1[i])],
            orders=orders,
            conditions=r.condition_names(),
        )


def _plain(ident):
    """A proposition identifier as a JSON value (numpy scalars to Python)."""
    return ident.item() if isinstance(ident, np.generic) else ident


def _json_key(x):
    return (type(x).__name__, x)


def _position(names, ident, where):
    if ident not in names:
        raise ValueError(f"Posterior.from_json: {where} names {ident!r}, which is not a "
                         "candidate of its clause kind")
    return names.index(ident)


def _forest(pairs, n, where):
    """Parent array of the forest whose ancestor->descendant pairs are ``pairs``."""
    ancestors = [set() for _ in range(n)]
    for a, b in pairs:
        ancestors[b].add(a)
    parent = np.full(n, -1, dtype=np.int64)
    for v in range(n):
        # In a forest the ancestors of v form a chain: its parent has one ancestor fewer.
        closest = [a for a in ancestors[v] if len(ancestors[a]) == len(ancestors[v]) - 1]
        if ancestors[v] and (len(closest) != 1 or ancestors[closest[0]] | {closest[0]}
                             != ancestors[v]):
            raise ValueError(f"Posterior.from_json: the orders of {where} are not a forest "
                             "(every ancestor -> descendant pair)")
        if closest:
            parent[v] = closest[0]
    return parent
