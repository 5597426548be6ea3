"""The posterior file: the JSON form of a posterior, written compactly and checked on read.

The format is specified by the JSON Schema ``docs/posterior-schema.json`` (described in
``docs/posterior-file.md``); :func:`parse_posterior` checks every rule of it, and the rules a
schema cannot say (probabilities that sum to one, names that exist, orders that form a forest),
raising a ``ValueError`` that names the field (``probabilities[3]``,
``specifications[2].orders[0]``). :class:`~bsi_sklearn.Posterior` builds itself from the
result; this module knows the file, not the model.
"""

from __future__ import annotations

import json
import math
import numbers
import os
from pathlib import Path
from typing import NamedTuple

import numpy as np

from bsi_sklearn.data.roles import Roles
from bsi_sklearn.io._atomic import write_atomic
from bsi_sklearn.specification import Specification
from bsi_sklearn.specification.templates import get_template

__all__ = [
    "SCHEMA",
    "SCHEMA_VERSION",
    "MAX_LISTED",
    "PosteriorDocument",
    "dump_posterior",
    "parse_posterior",
    "read_posterior",
    "write_posterior",
]

#: Name and version of the format (the ``schema`` and ``version`` fields). Version 2 adds
#: the pattern clauses (DESIGN §12); version 3 adds ``map_index``, the position of the most
#: probable specification where it is not listed first (a posterior reported by its
#: samples). A posterior that needs neither is still written as version 1, byte for byte as
#: before, and every version is read.
SCHEMA = "bsi-sklearn/posterior"
SCHEMA_VERSION = 3
_VERSIONS = (1, 2, 3)

#: Default most specifications a file lists; the rest is written as ``dropped_mass``.
MAX_LISTED = 10_000

#: How far the listed probabilities may sum from 1 (rounding of a long sum).
SUM_TOLERANCE = 1e-6

_TOP_KEYS = ("schema", "version", "names", "roles", "specifications", "probabilities",
             "clause_marginals", "dropped_mass")
_TOP_KEYS_3 = _TOP_KEYS + ("map_index",)
_ROLE_KEYS = ("global_candidates", "subtasks", "conditions")
_SPEC_KEYS = ("globals", "eventuals", "orders", "ltl")
# Version 2: the roles list the pattern candidates, each specification its pattern clauses.
_ROLE_KEYS_2 = _ROLE_KEYS + ("patterns",)
_SPEC_KEYS_2 = ("globals", "eventuals", "orders", "patterns", "ltl")


class PosteriorDocument(NamedTuple):
    """A checked posterior file, as arrays (see ``Posterior`` for their meaning).

    Attributes
    ----------
    roles : Roles
    structures : ndarray of shape (n_specs, n_subtasks), int64
    tau_masks : ndarray of shape (n_specs, n_globals + n_patterns), bool
        The ``G`` candidates, then the pattern candidates (``roles.patterns``).
    w1_masks : ndarray of shape (n_specs, n_subtasks), bool
    probabilities : ndarray of shape (n_specs,)
    marginal_keys : list of tuple
        Clause keys, in the file's order.
    marginals : ndarray
        Inclusion probability of every clause of ``marginal_keys``.
    dropped_mass : float
    map_index : int
        Position of the most probable specification (0 before version 3).
    """

    roles: Roles
    structures: np.ndarray
    tau_masks: np.ndarray
    w1_masks: np.ndarray
    probabilities: np.ndarray
    marginal_keys: list
    marginals: np.ndarray
    dropped_mass: float
    map_index: int = 0


# ---------------------------------------------------------------------------------- writing
def _plain(ident):
    """A proposition identifier as a JSON value (NumPy scalars to Python)."""
    return ident.item() if isinstance(ident, np.generic) else ident


def _json_key(x):
    return (type(x).__name__, x)


def _spec_entry(spec, version):
    entry = {
        "globals": sorted((_plain(p) for p in spec.globals), key=_json_key),
        "eventuals": sorted((_plain(w) for w in spec.eventuals), key=_json_key),
        "orders": sorted(([_plain(a), _plain(b)] for a, b in spec.orders),
                         key=lambda o: (_json_key(o[0]), _json_key(o[1]))),
    }
    if version >= 2:
        entry["patterns"] = sorted(([name, [_plain(p) for p in props]]
                                    for name, props in spec.patterns),
                                   key=lambda k: (k[0], [_json_key(p) for p in k[1]]))
    elif spec.patterns:
        raise ValueError("a specification has pattern clauses but the roles list no pattern "
                         f"candidate: {spec.to_ltl()!r}")
    entry["ltl"] = spec.to_ltl()
    return entry


def _key_entry(key):
    # A pattern clause's key ("P", template, propositions) nests its propositions.
    return [_plain(x) if not isinstance(x, tuple) else [_plain(p) for p in x] for x in key]


def dump_posterior(roles, specifications, probabilities, marginal_keys, marginals,
                   dropped_mass, map_index=0):
    """The text of a posterior file.

    Parameters
    ----------
    roles : Roles
    specifications : list of Specification
        The listed specifications, most probable first.
    probabilities : ndarray
        Their probabilities (summing to one).
    marginal_keys : list of tuple
        Clause keys, in the order of the roles.
    marginals : ndarray
        The clause inclusion probabilities over the whole posterior.
    dropped_mass : float
        Posterior mass not listed.
    map_index : int, default=0
        Position of the most probable specification among those listed.

    Returns
    -------
    text : str
        One field a line, one specification or probability a line; floats exactly. Version 2
        when the roles have pattern candidates (``roles.patterns``, listed by template name
        or user LTLf text and their propositions), version 3 (with ``map_index``) when the
        most probable specification is not listed first, else version 1, as before them.
    """
    version = 3 if map_index else 2 if getattr(roles, "patterns", ()) else 1
    role_entry = {
        "global_candidates": [_plain(n) for n in roles.global_names()],
        "subtasks": [_plain(n) for n in roles.subtask_names()],
        "conditions": [[_plain(w), _plain(c)] for w, c in roles.condition_names().items()],
    }
    if version >= 2:
        role_entry["patterns"] = [[name, [_plain(p) for p in props]]
                                  for name, props in roles.pattern_keys()]
    doc = {
        "schema": SCHEMA,
        "version": version,
        "names": [_plain(n) for n in roles.names],
        "roles": role_entry,
        "specifications": [_spec_entry(s, version) for s in specifications],
        "probabilities": [float(p) for p in probabilities],
        "clause_marginals": [[_key_entry(key), float(v)]
                             for key, v in zip(marginal_keys, marginals)],
        "dropped_mass": float(dropped_mass),
    }
    if version >= 3:
        doc["map_index"] = int(map_index)
    lines = []
    for key, value in doc.items():
        if isinstance(value, list) and value and key != "names":
            inner = ",\n".join("  " + _compact(v) for v in value)
            lines.append(f" {json.dumps(key)}: [\n{inner}\n ]")
        else:
            lines.append(f" {json.dumps(key)}: {_compact(value)}")
    return "{\n" + ",\n".join(lines) + "\n}\n"


def _compact(value):
    return json.dumps(value, separators=(", ", ": "), allow_nan=False)


def write_posterior(path, text):
    """Write a posterior file in one step (a temporary file renamed over ``path``).

    Parameters
    ----------
    path : str or path-like
        The destination; its folder must exist.
    text : str
        From :func:`dump_posterior`.

    Returns
    -------
    path : pathlib.Path

    Raises
    ------
    ValueError
        When ``path`` is empty or an existing folder, or its folder is missing or a file.
    """
    path = _as_path(path, "Posterior.to_json")
    if path.is_dir():
        raise ValueError(f"Posterior.to_json: {str(path)!r} is a folder; give a file name")
    parent = path.parent
    if not parent.is_dir():
        what = "is not a folder" if parent.exists() else "does not exist"
        raise ValueError(f"Posterior.to_json: cannot write {str(path)!r}: "
                         f"{str(parent)!r} {what}")
    return write_atomic(path, text)


# ---------------------------------------------------------------------------------- reading
def _as_path(path, who):
    if not isinstance(path, (str, os.PathLike)):
        raise ValueError(f"{who}: a path must be a str or path-like, got "
                         f"{type(path).__name__}")
    if str(path) == "" or os.fspath(path) == "":
        raise ValueError(f"{who}: the path is empty")
    return Path(path)


def read_posterior(path):
    """Read and check the posterior file at ``path``.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    document : PosteriorDocument

    Raises
    ------
    FileNotFoundError
        When there is no file at ``path``.
    ValueError
        Naming the file and the field, for a folder, a file that is not UTF-8 JSON text, or
        any rule of the format broken.
    """
    path = _as_path(path, "Posterior.read_json")
    if path.is_dir():
        raise ValueError(f"Posterior.read_json: {str(path)!r} is a folder, not a posterior "
                         "file")
    return parse_posterior(path.read_bytes(), who=f"Posterior.read_json: {str(path)!r}")


def parse_posterior(text, who="Posterior.from_json"):
    """Check the text of a posterior file and return its content as arrays.

    Parameters
    ----------
    text : str or bytes
        The JSON text.
    who : str, default="Posterior.from_json"
        What the messages start with.

    Returns
    -------
    document : PosteriorDocument

    Raises
    ------
    ValueError
        ``"<who>: <field>: <what is wrong>"`` for text that is not JSON, not of this schema or
        version, or breaks a rule of the format.

    Examples
    --------
    >>> parse_posterior('{"schema": "bsi-sklearn/posterior", "version": 1}')
    Traceback (most recent call last):
    ...
    ValueError: Posterior.from_json: (document): missing field 'names'
    """
    if isinstance(text, (bytes, bytearray)):
        try:
            text = bytes(text).decode("utf-8")
        except UnicodeDecodeError as exc:
            raise ValueError(f"{who}: not UTF-8 text ({exc.reason} at byte {exc.start})") \
                from None
    try:
        doc = json.loads(text, parse_constant=_no_constant)
    except json.JSONDecodeError as exc:
        raise ValueError(f"{who}: not JSON ({exc})") from None
    except _BadConstant as exc:
        raise ValueError(f"{who}: {exc} is not a JSON number (JSON has no NaN or Infinity; "
                         "every probability is a finite number)") from None
    return _Reader(who).document(doc)


def _canonical(key):
    """A pattern key as :attr:`Specification.patterns` holds it."""
    (key,) = Specification(patterns=[key]).patterns
    return key


class _BadConstant(Exception):
    pass


def _no_constant(name):
    raise _BadConstant(name)


def _kind(value):
    return {dict: "an object", list: "a list", str: "a string", bool: "a boolean",
            type(None): "null"}.get(type(value), "a number")


class _Reader:
    """The checks of one document, each failure a ValueError naming the field."""

    def __init__(self, who):
        self.who = who

    def fail(self, field, what):
        raise ValueError(f"{self.who}: {field}: {what}")

    def object(self, value, field, keys):
        if not isinstance(value, dict):
            self.fail(field, f"expected an object, got {_kind(value)}")
        for k in keys:
            if k not in value:
                self.fail(field, f"missing field {k!r}")
        extra = [k for k in value if k not in keys]
        if extra:
            self.fail(field, f"unknown field {extra[0]!r} (the fields are {list(keys)})")
        return value

    def list(self, value, field):
        if not isinstance(value, list):
            self.fail(field, f"expected a list, got {_kind(value)}")
        return value

    def number(self, value, field, low=0.0, high=1.0):
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            self.fail(field, f"expected a number, got {_kind(value)} {value!r}")
        try:
            value = float(value)
        except OverflowError:
            value = math.inf
        if not math.isfinite(value):
            self.fail(field, f"{value!r} is not a finite number")
        if value < low:
            self.fail(field, f"{value!r} is negative" if low == 0 else f"{value!r} < {low}")
        if value > high:
            self.fail(field, f"{value!r} is above {high}")
        return value

    def document(self, doc):
        """Check ``doc`` (parsed JSON) and return a :class:`PosteriorDocument`."""
        if not isinstance(doc, dict):
            self.fail("(document)", f"expected an object, got {_kind(doc)}")
        if doc.get("schema") != SCHEMA:
            self.fail("schema", f"expected {SCHEMA!r}, got {doc.get('schema')!r}")
        version = doc.get("version")
        if isinstance(version, bool) or version not in _VERSIONS:
            self.fail("version", f"schema version {version!r} is not supported; this "
                      f"bsi-sklearn reads versions {', '.join(map(str, _VERSIONS))}")
        self.version = version
        self.object(doc, "(document)", _TOP_KEYS_3 if self.version >= 3 else _TOP_KEYS)
        names = self.names(doc["names"])
        roles = self.roles(doc["roles"], names)
        structures, tau, w1 = self.specifications(doc["specifications"], roles)
        probs = self.probabilities(doc["probabilities"], len(structures))
        keys, marginals = self.marginals(doc["clause_marginals"], names)
        dropped = self.number(doc["dropped_mass"], "dropped_mass")
        map_index = self.map_index(doc["map_index"], len(structures)) if self.version >= 3 \
            else 0
        return PosteriorDocument(roles, structures, tau, w1, probs, keys, marginals, dropped,
                                 map_index)

    def map_index(self, value, n_specs):
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < n_specs:
            self.fail("map_index", f"expected the position of a listed specification (an "
                      f"integer from 0 to {n_specs - 1}), got {_kind(value)} {value!r}")
        return value

    def names(self, value):
        names = self.list(value, "names")
        if not names:
            self.fail("names", "the list is empty")
        for k, n in enumerate(names):
            if isinstance(n, bool) or not isinstance(n, (str, int)):
                self.fail(f"names[{k}]", f"a proposition name is a string or an integer, "
                          f"got {_kind(n)} {n!r}")
        if any(isinstance(n, int) for n in names) and names != list(range(len(names))):
            self.fail("names", "integer names are column indices and must be 0, 1, ..., "
                      f"{len(names) - 1} in order (got {names[:8]})")
        seen = set()
        for k, n in enumerate(names):
            if n in seen:
                self.fail(f"names[{k}]", f"{n!r} is listed twice")
            seen.add(n)
        return names

    def members(self, value, field, allowed, what):
        """Positions in ``allowed`` of the names listed in ``value`` (each once)."""
        out = []
        for k, ident in enumerate(self.list(value, field)):
            position = self.position(ident, f"{field}[{k}]", allowed, what)
            if position in out:
                self.fail(f"{field}[{k}]", f"{ident!r} is listed twice")
            out.append(position)
        return out

    def position(self, ident, field, allowed, what):
        """Position of the name ``ident`` in ``allowed`` (no float for an integer name)."""
        if isinstance(ident, bool) or not isinstance(ident, (str, int)) or \
                ident not in allowed:
            self.fail(field, f"{ident!r} is not {what}")
        return allowed.index(ident)

    def roles(self, value, names):
        roles = self.object(value, "roles", _ROLE_KEYS_2 if self.version >= 2 else _ROLE_KEYS)
        g = self.members(roles["global_candidates"], "roles.global_candidates", names,
                         "one of the names")
        s = self.members(roles["subtasks"], "roles.subtasks", names, "one of the names")
        cond = np.full(len(s), -1, dtype=np.int64)
        for k, pair in enumerate(self.list(roles["conditions"], "roles.conditions")):
            field = f"roles.conditions[{k}]"
            if not isinstance(pair, list) or len(pair) != 2:
                self.fail(field, f"expected a pair [subtask, condition], got {pair!r}")
            w, c = (self.position(x, f"{field}[{k}]", names, "one of the names")
                    for k, x in enumerate(pair))
            if w not in s:
                self.fail(field, f"{names[w]!r} is not one of the subtasks")
            if w == c:
                self.fail(field, f"subtask {names[w]!r} is its own condition")
            if cond[s.index(w)] >= 0:
                self.fail(field, f"subtask {names[w]!r} has a second condition")
            cond[s.index(w)] = c
        patterns = self.pattern_list(roles.get("patterns", []), "roles.patterns", names)
        if len(set(patterns)) < len(patterns):
            k = next(k for k, p in enumerate(patterns) if p in patterns[:k])
            self.fail(f"roles.patterns[{k}]", "listed twice")
        return Roles(np.asarray(g, dtype=np.int64), np.asarray(s, dtype=np.int64), cond,
                     list(names),
                     tuple((t, tuple(names.index(p) for p in props)) for t, props in patterns))

    def pattern_list(self, value, field, allowed):
        """``[(template name, propositions), ...]``, each checked, the propositions as given."""
        out = []
        for k, item in enumerate(self.list(value, field)):
            where = f"{field}[{k}]"
            if not isinstance(item, list) or len(item) != 2 or not isinstance(item[0], str):
                self.fail(where, f"expected a pair [template, [propositions]], got {item!r}")
            props = self.list(item[1], f"{where}[1]")
            for j, ident in enumerate(props):
                self.position(ident, f"{where}[1][{j}]", allowed, "one of the names")
            try:
                Specification(patterns=[(item[0], props)])  # the template and its slots
            except ValueError as exc:
                self.fail(where, str(exc))
            out.append((get_template(item[0]).name, tuple(props)))
        return out

    def specifications(self, value, roles):
        specs = self.list(value, "specifications")
        if not specs:
            self.fail("specifications", "the list is empty (a posterior lists at least one)")
        g_names, s_names = roles.global_names(), roles.subtask_names()
        n_g, n = len(g_names), len(s_names)
        # As a Specification stores them (a symmetric template's propositions sorted).
        p_keys = [_canonical(key) for key in roles.pattern_keys()]
        structures = np.full((len(specs), n), -1, dtype=np.int64)
        tau = np.zeros((len(specs), n_g), dtype=bool)
        chosen = np.zeros((len(specs), len(p_keys)), dtype=bool)  # the patterns, after tau
        w1 = np.zeros((len(specs), n), dtype=bool)
        conditions = roles.condition_names()
        for h, entry in enumerate(specs):
            field = f"specifications[{h}]"
            entry = self.object(entry, field,
                                _SPEC_KEYS_2 if self.version >= 2 else _SPEC_KEYS)
            tau[h, self.members(entry["globals"], f"{field}.globals", g_names,
                                "a global candidate")] = True
            w1[h, self.members(entry["eventuals"], f"{field}.eventuals", s_names,
                               "a subtask")] = True
            pairs = []
            for k, pair in enumerate(self.list(entry["orders"], f"{field}.orders")):
                where = f"{field}.orders[{k}]"
                if not isinstance(pair, list) or len(pair) != 2:
                    self.fail(where, f"expected a pair [a, b] (a precedes b), got {pair!r}")
                a, b = self.members(pair, where, s_names, "a subtask")
                pairs.append((a, b))
            structures[h] = self.forest(pairs, n, f"{field}.orders")
            where = f"{field}.patterns"
            for k, key in enumerate(self.pattern_list(entry.get("patterns", []), where,
                                                      roles.names)):
                key = _canonical(key)
                if key not in p_keys:
                    self.fail(f"{where}[{k}]", f"{key[0]}{list(key[1])} is not one of the "
                              "pattern candidates (roles.patterns)")
                if chosen[h, p_keys.index(key)]:
                    self.fail(f"{where}[{k}]", "listed twice")
                chosen[h, p_keys.index(key)] = True
            ltl = entry["ltl"]
            spec = Specification(
                [g_names[j] for j in np.flatnonzero(tau[h])],
                [s_names[w] for w in np.flatnonzero(w1[h])],
                [(s_names[a], s_names[b]) for a, b in pairs], conditions,
                patterns=[p_keys[k] for k in np.flatnonzero(chosen[h])])
            if ltl != spec.to_ltl():
                what = "clauses" if self.version >= 2 else "globals, eventuals and orders"
                self.fail(f"{field}.ltl", f"{ltl!r} is not the formula of the entry's "
                          f"{what} ({spec.to_ltl()!r})")
        tau = np.concatenate([tau, chosen], axis=1)  # pattern k is global slot n_globals + k
        rows = np.concatenate([tau, w1, structures], axis=1)
        _, first, counts = np.unique(rows, axis=0, return_index=True, return_counts=True)
        if (counts > 1).any():
            h = int(first[np.argmax(counts > 1)])
            self.fail(f"specifications[{h}]", "listed more than once (a posterior lists "
                      "unique specifications)")
        return structures, tau, w1

    def forest(self, pairs, n, field):
        """Parent array of the forest whose ancestor -> descendant pairs are ``pairs``."""
        ancestors = [set() for _ in range(n)]
        for a, b in pairs:
            ancestors[b].add(a)
        parent = np.full(n, -1, dtype=np.int64)
        for v in range(n):
            # In a forest the ancestors of v form a chain: its parent has one ancestor fewer.
            closest = [a for a in ancestors[v] if len(ancestors[a]) == len(ancestors[v]) - 1]
            if ancestors[v] and (len(closest) != 1 or ancestors[closest[0]] | {closest[0]}
                                 != ancestors[v]):
                self.fail(field, "not a forest given as every ancestor -> descendant pair")
            if closest:
                parent[v] = closest[0]
        return parent

    def probabilities(self, value, n_specs):
        probs = self.list(value, "probabilities")
        if len(probs) != n_specs:
            self.fail("probabilities", f"{len(probs)} probabilities for {n_specs} "
                      "specifications")
        out = np.array([self.number(p, f"probabilities[{k}]") for k, p in enumerate(probs)])
        total = float(out.sum())
        if abs(total - 1.0) > SUM_TOLERANCE:
            self.fail("probabilities", f"sum to {total!r}, not 1 (a distribution over the "
                      "listed specifications; the mass left out is dropped_mass)")
        rising = np.flatnonzero(np.diff(out) > 0)
        if len(rising):
            k = int(rising[0]) + 1
            self.fail(f"probabilities[{k}]", f"{float(out[k])!r} is larger than the one "
                      f"before ({float(out[k - 1])!r}); specifications are listed most "
                      "probable first")
        return out

    def marginals(self, value, names):
        keys, values = [], []
        for k, item in enumerate(self.list(value, "clause_marginals")):
            field = f"clause_marginals[{k}]"
            if not isinstance(item, list) or len(item) != 2 or not isinstance(item[0], list):
                self.fail(field, f"expected a pair [clause key, probability], got {item!r}")
            key = item[0]
            if key and key[0] == "P" and self.version >= 2 and len(key) == 3:
                (pattern,) = self.pattern_list([key[1:]], field, names)
                keys.append(("P", *_canonical(pattern)))
                values.append(self.number(item[1], field, high=1.0 + 1e-9))
                continue
            if not key or key[0] not in ("G", "F", "U") or len(key) != (3 if key[0] == "U"
                                                                          else 2):
                self.fail(field, f"{key!r} is not a clause key ['G', p], ['F', w] or "
                          "['U', a, b]" + (", ['P', template, [propositions]]"
                                           if self.version >= 2 else ""))
            for ident in key[1:]:
                self.position(ident, field, names, "one of the names")
            keys.append(tuple(key))
            values.append(self.number(item[1], field, high=1.0 + 1e-9))
        return keys, np.asarray(values, dtype=float)
