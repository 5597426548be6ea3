"""BSI against Scarlet on the published samples2LTL / Scarlet ``.trace`` benchmarks.

    python benchmarks/external.py                     # every file; Scarlet on a subset
    python benchmarks/external.py --quick             # two files a folder, short timeouts
    python benchmarks/external.py --no-scarlet        # BSI only
    python benchmarks/external.py --data DIR --out benchmarks/RESULTS_external.md --n-jobs 1

For every ``.trace`` file under ``--data`` (default ``../shared/benchmarks-data`` beside the
repository): a deterministic stratified split (70 % train / 30 % test, seeded by the file's
relative path), then

* **BSI**: :class:`~bsi_sklearn.preprocessing.NegationAugmenter` adds ``!p`` for every
  proposition (so ``G(!p)`` is reachable), candidate clauses are screened on the training
  positives (see :func:`select_roles`), and :class:`~bsi_sklearn.BSIClassifier` is fitted on the
  training positives and negatives: exact enumeration when the support is at most
  ``--max-exact`` hypotheses, MCMC otherwise. Reported: test accuracy (posterior vote), the MAP
  specification, its test accuracy, fit time, and when the target lies in the BSI template
  whether the MAP specification contains the target's clauses (recovery).
* **Scarlet** (Raha et al., TACAS 2022; PyPI ``scarlet-ltl``, MIT) learns from the same training
  split in a worker process (per-file timeout); its formula is parsed
  (:func:`parse_scarlet_formula`) and evaluated on the test split with
  :mod:`bsi_sklearn.ltl` under Scarlet's own finite-trace semantics (strong next).

Writes a per-file CSV and a Markdown report (``benchmarks/RESULTS_external.md``).
Scarlet is installed on demand into a private directory (``--scarlet-dir``) rather than the
project's environment: its dependency ``lark`` 1.x would overwrite the ``lark`` module of
``lark-parser`` 0.12 that ``flloat`` (a test dependency of this project) needs.
"""

from __future__ import annotations

import argparse
import json
import os
import select
import shlex
import subprocess
import sys
import tempfile
import time
import warnings
import zlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))

from _common import machine_info, md_table  # noqa: E402

from bsi_sklearn import BSIClassifier  # noqa: E402
from bsi_sklearn.io import read_trace_file  # noqa: E402
from bsi_sklearn.ltl import And, Atom, Next, Not, parse_ltl  # noqa: E402
from bsi_sklearn.preprocessing import NegationAugmenter  # noqa: E402

__all__ = [
    "Config",
    "DEFAULT_DATA",
    "find_trace_files",
    "family_of",
    "split_indices",
    "select_roles",
    "fit_bsi",
    "parse_scarlet_formula",
    "scarlet_semantics",
    "evaluate_scarlet_formula",
    "ScarletWorker",
    "ensure_scarlet",
    "evaluate_file",
    "scarlet_columns",
    "run_evaluation",
    "summarize",
    "write_report",
    "main",
]

DEFAULT_DATA = HERE.parent / ".." / "shared" / "benchmarks-data"
SCARLET_VERSION = "0.0.4"
DEFAULT_SCARLET_DIR = Path.home() / ".cache" / "bsi-sklearn" / f"scarlet-ltl-{SCARLET_VERSION}"
LAST = "__last__"  # proposition true at the last step: Scarlet's strong next needs it
NEG = "!"  # NegationAugmenter's prefix, the one Formula.to_specification reads


@dataclass
class Config:
    """Settings of one evaluation run (every field is a command-line option)."""

    test_size: float = 0.3
    seed: int = 0
    prior: str = "sets_of_chains"
    likelihood: str = "cb"
    min_support: float = 0.9
    max_globals: int = 6
    max_subtasks: int = 6
    max_exact: int = 1_000_000
    n_samples: int = 2_000
    n_chains: int = 2
    scarlet: bool = True
    scarlet_timeout: float = 20.0
    scarlet_every: int = 6
    scarlet_thres: float = 0.0
    scarlet_noisy_thres: float = 0.05
    scarlet_dir: str = str(DEFAULT_SCARLET_DIR)
    quick: bool = False
    n_jobs: int = 1
    verbose: int = 1


# -- files and splits ---------------------------------------------------------------------


def find_trace_files(data_dir):
    """Every ``.trace`` file under ``data_dir``, sorted; ``ValueError`` when there is none."""
    data_dir = Path(data_dir)
    if not data_dir.is_dir():
        raise ValueError(
            f"benchmark data directory {str(data_dir)!r} does not exist; pass --data DIR (the "
            "folder holding samples2LTL/ and scarlet/, normally ../shared/benchmarks-data)"
        )
    files = sorted(data_dir.rglob("*.trace"))
    if not files:
        raise ValueError(f"no .trace files under {str(data_dir)!r}")
    return files


def family_of(path, data_dir):
    """Benchmark family of a file: its source and folder, e.g. ``samples2LTL/perfect/absence``.

    >>> family_of(Path("d/samples2LTL/traces/finite/perfect_class/abscence/0.trace"), "d")
    'samples2LTL/perfect_class/abscence'
    >>> family_of(Path("d/scarlet/All_benchmarks/RQ2-benchmarks/Varying_form/TracesFiles/"
    ...                "f-01.trace"), "d")
    'scarlet/Varying_form'
    """
    parts = Path(path).resolve().relative_to(Path(data_dir).resolve()).parts[:-1]
    drop = {"traces", "finite", "All_benchmarks", "RQ2-benchmarks", "TracesFiles"}
    return "/".join(p for p in parts if p not in drop)


def split_indices(y, test_size=0.3, seed=0):
    """Deterministic stratified split: ``round(test_size * n_c)`` traces of each class to test.

    A class with fewer than two traces stays wholly in training (a learner cannot be scored
    on a class it never saw, and with one trace there is nothing to split); at least one trace
    of each class stays in training.

    Returns ``(train_idx, test_idx)``, sorted arrays of indices into ``y``.

    >>> tr, te = split_indices(np.array([1] * 10 + [0] * 4), 0.3, seed=0)
    >>> len(tr), len(te), int(np.sum(np.array([1] * 10 + [0] * 4)[te]))
    (10, 4, 3)
    >>> split_indices(np.array([1, 0, 0, 0]), 0.3, seed=0)[1].tolist()
    [3]
    """
    y = np.asarray(y)
    rng = np.random.default_rng(seed)
    train, test = [], []
    for c in np.unique(y):
        idx = rng.permutation(np.flatnonzero(y == c))
        n_test = 0 if len(idx) < 2 else min(int(round(test_size * len(idx))), len(idx) - 1)
        test.extend(idx[:n_test])
        train.extend(idx[n_test:])
    return np.sort(np.asarray(train, dtype=int)), np.sort(np.asarray(test, dtype=int))


def file_seed(rel_path, seed):
    """A seed per file, independent of the order and number of files evaluated."""
    return (zlib.crc32(str(rel_path).encode()) + 7919 * seed) % (2**31 - 1)


# -- BSI ------------------------------------------------------------------------------------


def _clause_stats(traces):
    """Per trace: G(p), F(p) and the first step of p (``T`` when never), every column."""
    always = np.array([t.all(axis=0) for t in traces])
    ever = np.array([t.any(axis=0) for t in traces])
    first = np.array([np.where(t.any(axis=0), t.argmax(axis=0), len(t)) for t in traces])
    return always, ever, first


def select_roles(traces, y, names, *, min_support=0.9, max_globals=6, max_subtasks=6):
    """Screen the candidate clauses of BSI on the training data and cap their number.

    With a negation for every proposition there are ``2 n`` global candidates and subtasks:
    up to 14 of each on these files, about ``10**21`` hypotheses for Prior 2, most of them
    contradictions (``G(p) & G(!p)``) that no positive satisfies. Clauses that training
    positives violate cannot raise the posterior of a specification, so only propositions
    whose clause holds on at least ``min_support`` of the training positives are kept (the
    margin leaves room for label noise):

    * global candidate ``p`` when ``G(p)`` holds on enough positives;
    * subtask ``w`` when ``F(w)`` holds on enough positives.

    Candidates are then ranked by how well their clauses separate the classes: for globals
    the positive-minus-negative rate of ``G(p)``; for subtasks the best such gap among
    ``F(w)`` and the orders ``(!b U a)`` involving ``w`` whose positive rate passes
    ``min_support``. Only the ``max_globals`` and ``max_subtasks`` best are kept (ties: plain
    propositions before negations, then name order).

    Parameters
    ----------
    traces : list of ndarray of shape (T_i, n_names), dtype bool
    y : ndarray of shape (n_traces,)
        1 for positives, 0 for negatives.
    names : list of str
        Column names.
    min_support, max_globals, max_subtasks : see above.

    Returns
    -------
    globals, subtasks : list of str
        In rank order.
    screened : dict
        Numbers of candidates that passed the screening (``"globals"``, ``"subtasks"``).

    Examples
    --------
    >>> t = np.array([[1, 0], [1, 1]], dtype=bool)      # columns p, q
    >>> u = np.array([[0, 0], [1, 0]], dtype=bool)
    >>> select_roles([t, t, u], np.array([1, 1, 0]), ["p", "q"])
    (['p'], ['q', 'p'], {'globals': 1, 'subtasks': 2})
    """
    y = np.asarray(y)
    pos, neg = y == 1, y == 0
    if not pos.any():
        return [], [], {"globals": 0, "subtasks": 0}
    always, ever, first = _clause_stats(traces)
    lengths = np.array([len(t) for t in traces])

    def rate(truth, mask):
        return float(truth[mask].mean()) if mask.any() else 0.0

    def tie(k):
        return (names[k].startswith(NEG), names[k])

    n = len(names)
    g_ok = [k for k in range(n) if rate(always[:, k], pos) >= min_support]
    g_gap = {k: rate(always[:, k], pos) - rate(always[:, k], neg) for k in g_ok}
    s_ok = [k for k in range(n) if rate(ever[:, k], pos) >= min_support]
    s_gap = {k: rate(ever[:, k], pos) - rate(ever[:, k], neg) for k in s_ok}
    for a in s_ok:
        for b in s_ok:
            if a == b:
                continue
            # (!b U a): a happens, and no b strictly before the first a
            order = (first[:, a] < lengths) & (first[:, a] <= first[:, b])
            if rate(order, pos) >= min_support:
                gap = rate(order, pos) - rate(order, neg)
                s_gap[a] = max(s_gap[a], gap)
                s_gap[b] = max(s_gap[b], gap)
    globals_ = sorted(g_ok, key=lambda k: (-g_gap[k], *tie(k)))[:max_globals]
    subtasks = sorted(s_ok, key=lambda k: (-s_gap[k], *tie(k)))[:max_subtasks]
    return ([names[k] for k in globals_], [names[k] for k in subtasks],
            {"globals": len(g_ok), "subtasks": len(s_ok)})


def fit_bsi(X_train, y_train, cfg, random_state=0):
    """Augment with negations, screen the roles, fit :class:`BSIClassifier`.

    Parameters
    ----------
    X_train : list of DataFrame
        Training traces with named boolean columns.
    y_train : ndarray
        1 / 0 labels.
    cfg : Config
    random_state : int
        Seed of the MCMC chains (unused by exact inference).

    Returns
    -------
    augmenter : NegationAugmenter
    clf : BSIClassifier
    info : dict
        ``fit_s`` (wall seconds: augmentation, screening and fit), ``globals``, ``subtasks``
        (the roles used), ``screened_*`` (candidates before the caps).
    """
    t0 = time.perf_counter()
    augmenter = NegationAugmenter(prefix=NEG).fit(X_train)
    Xa = augmenter.transform(X_train)
    names = [str(n) for n in augmenter.get_feature_names_out()]
    arrays = [np.asarray(x, dtype=bool) for x in Xa]
    globals_, subtasks, screened = select_roles(
        arrays, y_train, names, min_support=cfg.min_support,
        max_globals=cfg.max_globals, max_subtasks=cfg.max_subtasks)
    clf = BSIClassifier(prior=cfg.prior, likelihood=cfg.likelihood, global_candidates=globals_,
                        subtasks=subtasks, inference="auto", max_exact_hypotheses=cfg.max_exact,
                        n_samples=cfg.n_samples, n_chains=cfg.n_chains, n_jobs=1,
                        random_state=random_state)
    with warnings.catch_warnings():
        # R-hat warnings are recorded per file (mcmc_rhat), not printed 400 times
        warnings.simplefilter("ignore")
        clf.fit(Xa, y_train)
    info = {"fit_s": time.perf_counter() - t0, "globals": globals_, "subtasks": subtasks,
            "screened_globals": screened["globals"], "screened_subtasks": screened["subtasks"]}
    return augmenter, clf, info


# -- Scarlet --------------------------------------------------------------------------------


def _rename(formula, mapping):
    """The formula with its atoms renamed through ``mapping`` (others kept)."""
    if isinstance(formula, Atom):
        return Atom(mapping.get(formula.name, formula.name))
    children = [_rename(c, mapping) for c in formula.children]
    return type(formula)(*children) if children else formula


def scarlet_semantics(formula, last=LAST):
    """Rewrite a formula read with Scarlet's semantics for :mod:`bsi_sklearn.ltl`.

    Scarlet evaluates ``X phi`` at the last step of a finite trace as false (strong next, as
    in LTLf); :mod:`bsi_sklearn.ltl` reads the repeated last state there. With a proposition
    ``last`` true exactly at the last step, ``X phi`` becomes ``!last & X phi``, equal to
    Scarlet's ``X phi`` at every step. ``F``, ``G``, ``U`` and the Boolean operators agree.

    >>> print(scarlet_semantics(parse_ltl("F(X(a))")))
    F(!__last__ & X(a))
    """
    if isinstance(formula, Next):
        return And(Not(Atom(last)), Next(scarlet_semantics(formula.operand, last)))
    if isinstance(formula, Atom) or not formula.children:
        return formula
    return type(formula)(*[scarlet_semantics(c, last) for c in formula.children])


def parse_scarlet_formula(text, names=None):
    """Parse a formula printed by Scarlet into a :class:`~bsi_sklearn.ltl.Formula`.

    Scarlet prints formulas two ways: ``repr`` in prefix notation (``&(F(a),X(!(b)))``)
    and ``prettyPrint`` in infix with a space after unary operators (``(F a) & (X (! b))``,
    the form of its CSV output). Both are accepted. The result keeps Scarlet's atoms,
    renamed through ``names`` (Scarlet atom -> proposition name) when given; evaluate it
    with :func:`evaluate_scarlet_formula`, which applies Scarlet's strong next.

    Parameters
    ----------
    text : str
        The formula.
    names : mapping, default=None
        Scarlet atom -> proposition name.

    Returns
    -------
    formula : Formula

    Raises
    ------
    ValueError
        When the text is not a formula, or names an atom missing from ``names``.

    Examples
    --------
    >>> print(parse_scarlet_formula("((F v0) & (F v1)) & (X (! v2))",
    ...                             names={"v0": "a", "v1": "b", "v2": "c"}))
    F(a) & F(b) & X(!c)
    >>> parse_scarlet_formula("F(&(a,F(b)))") == parse_ltl("F(a & F(b))")
    True
    """
    if not isinstance(text, str) or not text.strip():
        raise ValueError(f"empty Scarlet formula {text!r}")
    formula = parse_ltl(text.strip())
    if names is not None:
        missing = sorted(formula.atoms - set(names))
        if missing:
            raise ValueError(f"Scarlet formula {text!r} names unknown atoms {missing}")
        formula = _rename(formula, dict(names))
    return formula


def with_last(X):
    """Traces with an extra boolean column :data:`LAST`, true at the last step only."""
    out = []
    for x in X:
        x = pd.DataFrame(x).copy()
        x[LAST] = np.arange(len(x)) == len(x) - 1
        out.append(x)
    return out


def evaluate_scarlet_formula(formula, X):
    """Truth of a Scarlet formula on traces (DataFrames), under Scarlet's finite semantics.

    >>> trace = pd.DataFrame({"a": [False, True]})
    >>> evaluate_scarlet_formula(parse_scarlet_formula("X a"), [trace]).tolist()
    [True]
    >>> evaluate_scarlet_formula(parse_scarlet_formula("X (X a)"), [trace]).tolist()
    [False]
    """
    return scarlet_semantics(formula).evaluate(with_last(X))


_WORKER = r"""
import json, logging, sys, time
try:  # die with the benchmark process (Linux), not after a long inference
    import ctypes, signal
    ctypes.CDLL("libc.so.6").prctl(1, signal.SIGKILL)
except Exception:
    pass
logging.disable(logging.CRITICAL)
from Scarlet.inferLTL import inferLTL
from Scarlet.sample import Sample
print(json.dumps({"ready": True}), flush=True)
for line in sys.stdin:
    req = json.loads(line)
    sample = Sample(positive=[], negative=[])
    sample.readFromFile(req["trace"])
    t0 = time.perf_counter()
    try:
        f = inferLTL(sample, req["csv"], ["F", "G", "X", "&", "|", "!"], "SC", 0, False,
                     False, req["thres"], {})
        out = {"formula": None if f is None else repr(f)}
    except Exception as exc:  # reported per file, the worker goes on
        out = {"error": type(exc).__name__ + ": " + str(exc)[:200]}
    out["seconds"] = time.perf_counter() - t0
    print(json.dumps(out), flush=True)
"""


def ensure_scarlet(target_dir, install=True, verbose=1):
    """Path of a directory from which ``import Scarlet`` works, installing it if needed.

    ``pip install --target`` keeps Scarlet and its dependencies (``lark`` 1.x among them)
    out of the project's environment; the worker process puts the directory first on its
    ``PYTHONPATH``.
    """
    target_dir = Path(target_dir)
    if (target_dir / "Scarlet" / "inferLTL.py").is_file():
        return target_dir
    if not install:
        raise RuntimeError(f"Scarlet is not installed in {target_dir}")
    cmd = [sys.executable, "-m", "pip", "install", "--quiet", "--disable-pip-version-check",
           "--target", str(target_dir), f"scarlet-ltl=={SCARLET_VERSION}"]
    if verbose:
        print(f"Installing Scarlet (PyPI scarlet-ltl {SCARLET_VERSION}, MIT) into {target_dir}"
              f" for this benchmark only:\n  {shlex.join(cmd)}", file=sys.stderr)
    target_dir.parent.mkdir(parents=True, exist_ok=True)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL if not verbose else None)
    return target_dir


class ScarletWorker:
    """A long-lived process running Scarlet on one training sample at a time.

    One process for the whole run saves Scarlet's import time (seconds) on every file; a
    request that outlives ``timeout`` kills the process (restarted on the next request) and
    keeps the best formula Scarlet had written to its CSV by then, if any.
    """

    def __init__(self, site_dir, timeout=60.0):
        self.site_dir = str(site_dir)
        self.timeout = float(timeout)
        self.proc = None
        self.tmp = tempfile.TemporaryDirectory(prefix="bsi-scarlet-")

    def _start(self):
        env = dict(os.environ)
        env["PYTHONPATH"] = self.site_dir + os.pathsep + env.get("PYTHONPATH", "")
        self.proc = subprocess.Popen(
            [sys.executable, "-u", "-c", _WORKER], stdin=subprocess.PIPE,
            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, env=env,
            cwd=self.tmp.name)
        reply = self._read(120.0)
        if reply is None or not reply.get("ready"):
            self.close()
            raise RuntimeError("the Scarlet worker did not start (is scarlet-ltl installed?)")

    def _read(self, timeout):
        ready, _, _ = select.select([self.proc.stdout], [], [], timeout)
        if not ready:
            return None
        line = self.proc.stdout.readline()
        return json.loads(line) if line else {"error": "worker exited"}

    def close(self):
        """Stop the worker process."""
        if self.proc is not None:
            self.proc.kill()
            self.proc.wait()
            self.proc = None

    def learn(self, positives, negatives, n_props, thres=0.0):
        """Run Scarlet on boolean traces; returns a dict.

        ``thres`` is Scarlet's bound on the fraction of misclassified training traces
        (0: the formula must separate them all).

        Keys: ``status`` (``ok``, ``timeout``, ``none`` when Scarlet found no formula,
        ``error``), ``formula`` (text over the atoms ``v0, v1, ...`` naming the columns,
        or None), ``seconds`` (Scarlet's own time, or wall time up to the timeout).
        """
        if self.proc is None or self.proc.poll() is not None:
            self._start()
        sample = Path(self.tmp.name) / "train.trace"
        csv = Path(self.tmp.name) / "progress.csv"
        csv.unlink(missing_ok=True)

        def line(t):
            return ";".join(",".join("1" if v else "0" for v in row) for row in t)

        # Scarlet reads the alphabet line with its newline: the file must not end with one.
        text = "\n".join([*map(line, positives), "---", *map(line, negatives), "---",
                          "F,G,X,!,&,|", "---", ",".join(f"v{i}" for i in range(n_props))])
        sample.write_text(text)
        t0 = time.perf_counter()
        self.proc.stdin.write(json.dumps(
            {"trace": str(sample), "csv": str(csv), "thres": float(thres)}) + "\n")
        self.proc.stdin.flush()
        reply = self._read(self.timeout)
        if reply is None:
            self.close()
            return {"status": "timeout", "formula": _last_csv_formula(csv),
                    "seconds": time.perf_counter() - t0}
        if "error" in reply:
            self.close()
            return {"status": "error", "formula": None, "seconds": reply.get("seconds"),
                    "error": reply["error"]}
        status = "ok" if reply["formula"] is not None else "none"
        return {"status": status, "formula": reply["formula"], "seconds": reply["seconds"]}


def _last_csv_formula(csv):
    """The last formula Scarlet wrote to its progress CSV (prettyPrint), or None."""
    try:
        rows = pd.read_csv(csv)
    except (OSError, ValueError, pd.errors.EmptyDataError):
        return None
    rows = rows.dropna(subset=["Formula"])
    return None if rows.empty else str(rows["Formula"].iloc[-1])


# -- one file -------------------------------------------------------------------------------


def _accuracy(pred, y):
    return float(np.mean(np.asarray(pred, dtype=bool) == np.asarray(y, dtype=bool))) if len(
        y) else float("nan")


def evaluate_file(path, data_dir, cfg, scarlet=None):
    """Evaluate BSI (and Scarlet when a :class:`ScarletWorker` is given) on one file.

    Returns one row (dict) of the per-file table.
    """
    path = Path(path)
    rel = path.resolve().relative_to(Path(data_dir).resolve())
    tf = read_trace_file(path)
    X, y = tf.X, tf.y
    seed = file_seed(rel, cfg.seed)
    train, test = split_indices(y, cfg.test_size, seed)
    X_tr, y_tr = [X[i] for i in train], y[train]
    X_te, y_te = [X[i] for i in test], y[test]
    names = [str(n) for n in tf.feature_names]
    aug_names = names + [NEG + n for n in names]
    target = tf.target
    target_spec = target.to_specification(names=aug_names) if target is not None else None
    row = {
        "family": family_of(path, data_dir), "file": str(rel), "n_props": tf.n_props,
        "trace_length": int(np.median([len(x) for x in X])),
        "n_train_pos": int(y_tr.sum()), "n_train_neg": int(len(y_tr) - y_tr.sum()),
        "n_test_pos": int(y_te.sum()), "n_test_neg": int(len(y_te) - y_te.sum()),
        "target": None if target is None else str(target),
        "in_template": target_spec is not None,
        "target_test_accuracy": (_accuracy(target.evaluate(X_te), y_te)
                                 if target is not None and len(test) else float("nan")),
        # label noise can leave few training positives that satisfy the target
        "target_train_pos_rate": (float(target.evaluate(
            [x for x, lab in zip(X_tr, y_tr) if lab == 1]).mean())
            if target is not None and y_tr.any() else float("nan")),
    }
    augmenter, clf, info = fit_bsi(X_tr, y_tr, cfg, random_state=seed)
    Xa_te = augmenter.transform(X_te) if len(test) else []
    spec = clf.map_specification_
    row.update({
        "bsi_inference": clf.inference_, "bsi_hypotheses": int(clf.n_hypotheses_),
        "bsi_globals": " ".join(info["globals"]), "bsi_subtasks": " ".join(info["subtasks"]),
        "bsi_screened_globals": info["screened_globals"],
        "bsi_screened_subtasks": info["screened_subtasks"],
        "bsi_fit_s": info["fit_s"],
        "bsi_train_accuracy": float(clf.score(augmenter.transform(X_tr), y_tr)),
        "bsi_accuracy": float(clf.score(Xa_te, y_te)) if len(test) else float("nan"),
        "bsi_map": spec.to_ltl(),
        "bsi_map_accuracy": (_accuracy([spec.satisfied_by(x) for x in Xa_te], y_te)
                             if len(test) else float("nan")),
        "bsi_map_probability": float(clf.posterior_.probabilities[0]),
        "mcmc_rhat": (float(clf.mcmc_diagnostics_["rhat"]) if clf.mcmc_diagnostics_
                      else float("nan")),
    })
    if target_spec is not None:
        row["recovered"] = bool(target_spec.clauses() <= spec.clauses())
        row["recovered_exactly"] = bool(target_spec == spec)
    else:
        row["recovered"] = row["recovered_exactly"] = None
    row.update({"scarlet_status": "skipped", "scarlet_formula": None,
                "scarlet_accuracy": float("nan"), "scarlet_s": float("nan")})
    if scarlet is not None:
        row.update(scarlet_columns(path, data_dir, cfg, scarlet))
    return row


# -- the run --------------------------------------------------------------------------------


def scarlet_subset(files, every):
    """Every ``every``-th file of each folder (the first included): where Scarlet runs."""
    if every <= 1:
        return set(files)
    chosen, seen = set(), {}
    for f in sorted(files):
        k = seen.get(f.parent, 0)
        if k % every == 0:
            chosen.add(f)
        seen[f.parent] = k + 1
    return chosen


def quick_files(files, per_folder=2):
    """The first ``per_folder`` files of each folder."""
    out, seen = [], {}
    for f in sorted(files):
        seen[f.parent] = seen.get(f.parent, 0) + 1
        if seen[f.parent] <= per_folder:
            out.append(f)
    return out


def _warm_up():
    """One exact and one MCMC fit, so numba compilation is not timed on the first file."""
    rng = np.random.default_rng(0)
    X = [rng.random((5, 3)) < 0.5 for _ in range(8)]
    y = np.array([1, 0] * 4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        BSIClassifier(inference="exact", random_state=0).fit(X, y)
        BSIClassifier(inference="mcmc", n_samples=50, n_chains=1, random_state=0).fit(X, y)


def run_evaluation(files, data_dir, cfg, scarlet_files=None):
    """Evaluate every file; Scarlet on ``scarlet_files`` (all when None) if ``cfg.scarlet``.

    BSI fits run in ``cfg.n_jobs`` processes; Scarlet runs afterwards, one file at a time, in
    its worker process. Returns the per-file DataFrame.
    """
    from joblib import Parallel, delayed
    from tqdm.auto import tqdm

    files = [Path(f) for f in files]
    _warm_up()
    bar = tqdm(total=len(files), desc="BSI", disable=not cfg.verbose)
    rows = {}
    if cfg.n_jobs == 1:
        for f in files:
            rows[f] = evaluate_file(f, data_dir, cfg)
            bar.update()
    else:
        jobs = Parallel(n_jobs=cfg.n_jobs, return_as="generator")(
            delayed(evaluate_file)(f, data_dir, cfg) for f in files)
        for f, row in zip(files, jobs):
            rows[f] = row
            bar.update()
    bar.close()
    if cfg.scarlet:
        chosen = set(files) if scarlet_files is None else set(map(Path, scarlet_files))
        site = ensure_scarlet(cfg.scarlet_dir, verbose=cfg.verbose)
        worker = ScarletWorker(site, timeout=cfg.scarlet_timeout)
        try:
            for f in tqdm([f for f in files if f in chosen], desc="Scarlet",
                          disable=not cfg.verbose):
                scarlet_row = scarlet_columns(f, data_dir, cfg, worker)
                rows[f].update(scarlet_row)
        finally:
            worker.close()
    return pd.DataFrame([rows[f] for f in files])


def scarlet_columns(path, data_dir, cfg, worker):
    """Run Scarlet on the training split of a file; the ``scarlet_*`` columns of its row."""
    tf = read_trace_file(path)
    rel = Path(path).resolve().relative_to(Path(data_dir).resolve())
    X, y = tf.X, tf.y
    train, test = split_indices(y, cfg.test_size, file_seed(rel, cfg.seed))
    arrays = [np.asarray(X[i], dtype=bool) for i in train]
    # label-noise benchmarks get Scarlet's noise option: with 0 it must fit the noise
    noisy = "misclass" in family_of(path, data_dir)
    res = worker.learn([a for a, i in zip(arrays, train) if y[i] == 1],
                       [a for a, i in zip(arrays, train) if y[i] == 0], tf.n_props,
                       thres=cfg.scarlet_noisy_thres if noisy else cfg.scarlet_thres)
    out = {"scarlet_status": res["status"], "scarlet_formula": None,
           "scarlet_accuracy": float("nan"),
           "scarlet_s": res["seconds"] if res["seconds"] is not None else float("nan")}
    if res.get("error"):
        out["scarlet_error"] = res["error"]
    if res["formula"] is not None:
        names = [str(n) for n in tf.feature_names]
        formula = parse_scarlet_formula(res["formula"],
                                        names={f"v{i}": n for i, n in enumerate(names)})
        out["scarlet_formula"] = str(formula)
        if len(test):
            out["scarlet_accuracy"] = _accuracy(
                evaluate_scarlet_formula(formula, [X[i] for i in test]), y[test])
    return out


# -- report ---------------------------------------------------------------------------------


def _mean(s):
    s = pd.to_numeric(s, errors="coerce").dropna()
    return float(s.mean()) if len(s) else float("nan")


def _median(s):
    s = pd.to_numeric(s, errors="coerce").dropna()
    return float(s.median()) if len(s) else float("nan")


def _group_stats(g, min_support):
    ran = g[g["scarlet_status"] != "skipped"]
    rec = g[g["in_template"]]
    ident = rec[rec["target_train_pos_rate"] >= min_support]
    scored = ran[ran["scarlet_accuracy"].notna()]
    return {
        "files": len(g),
        "bsi_accuracy": _mean(g["bsi_accuracy"]),
        "bsi_map_accuracy": _mean(g["bsi_map_accuracy"]),
        "target_accuracy": _mean(g["target_test_accuracy"]),
        "in_template": len(rec),
        "recovered": int(rec["recovered"].astype(bool).sum()) if len(rec) else 0,
        "recovery_rate": float(rec["recovered"].astype(bool).mean()) if len(rec) else float(
            "nan"),
        "identifiable": len(ident),
        "recovered_identifiable": int(ident["recovered"].astype(bool).sum()),
        "recovered_exactly": int(rec["recovered_exactly"].astype(bool).sum()) if len(rec) else 0,
        "bsi_fit_s_median": _median(g["bsi_fit_s"]),
        "scarlet_files": len(ran),
        "scarlet_timeouts": int((ran["scarlet_status"] == "timeout").sum()),
        "scarlet_failed": int(ran["scarlet_status"].isin(["error", "none"]).sum()),
        "scarlet_scored": len(scored),
        "scarlet_timeouts_scored": int((scored["scarlet_status"] == "timeout").sum()),
        # both learners on the files where Scarlet returned a formula
        "bsi_accuracy_on_scarlet_files": _mean(scored["bsi_accuracy"]),
        "scarlet_accuracy": _mean(scored["scarlet_accuracy"]),
        "scarlet_s_median": _median(ran["scarlet_s"]),
    }


def summarize(df, min_support=Config.min_support):
    """Per-family and overall statistics (a DataFrame indexed by family, ``ALL`` last).

    ``identifiable``: in-template files whose target holds on at least ``min_support`` of
    the training positives (under label noise it may hold on few of them).
    """
    rows = {fam: _group_stats(g, min_support) for fam, g in df.groupby("family", sort=True)}
    rows["ALL"] = _group_stats(df, min_support)
    return pd.DataFrame.from_dict(rows, orient="index")


def _f(x, digits=3):
    if x is None or (isinstance(x, float) and not np.isfinite(x)):
        return "-"
    return f"{x:.{digits}f}"


def write_report(df, summary, out, cfg, command, seconds, csv_path):
    """Write the Markdown report."""
    info = machine_info()
    lines = [
        "# External benchmarks: BSI vs Scarlet on samples2LTL / Scarlet traces",
        "",
        f"Generated by `{command}` on {info['date']} in {seconds / 60:.1f} min "
        f"(commit {info.get('commit', '?')}). Machine: {info['cpu']}, "
        f"{info['usable_cores']} usable cores, {info.get('memory_gib', '?')} GiB, "
        f"load average {info.get('load_average', '?')} at the end (the machine is shared: "
        "timings are noisy); Python {python}, numpy {numpy}, numba {numba}, scikit-learn "
        "{sk}. Per-file results: `{csv}`.".format(
            python=info["python"], numpy=info["numpy"], numba=info["numba"],
            sk=info["scikit-learn"], csv=csv_path),
        "",
        "Data: `../shared/benchmarks-data` (read-only; MIT, see its README): samples2LTL "
        "finite-trace benchmarks (Dwyer patterns, noise-free `perfect_class` and 5 % label "
        "noise `5pc_misclass`) and Scarlet's RQ2 `Varying_form` benchmarks.",
        "",
        "## Protocol",
        "",
        f"* Split: per file, stratified {1 - cfg.test_size:.0%} train / {cfg.test_size:.0%} "
        f"test, seeded by the file's path (seed {cfg.seed}); a class with fewer than two "
        "traces stays in training, so some test sets hold one class only.",
        "* BSI: `NegationAugmenter` adds `!p` for every proposition; every proposition and "
        "negation is a candidate global and subtask, screened on the training positives: "
        f"`G(p)` (resp. `F(w)`) must hold on >= {cfg.min_support:.0%} of them, then the "
        f"{cfg.max_globals} globals and {cfg.max_subtasks} subtasks that best separate the "
        "classes are kept (`select_roles`; without this the support reaches 10^21 "
        "hypotheses, and MCMC from prior draws sits on contradictions `G(p) & G(!p)`). "
        f"`BSIClassifier(prior={cfg.prior!r}, likelihood={cfg.likelihood!r})`, epsilon by "
        f"the paper's rule; exact inference up to {cfg.max_exact:,} hypotheses, else MCMC "
        f"({cfg.n_chains} chains x {cfg.n_samples:,} samples). Accuracy is the posterior "
        "vote (`predict`); the MAP specification's own accuracy is beside it. Fit time "
        "includes augmentation and screening.",
        "* Recovery (targets in the BSI template: `G(p)`, `G(!p)`, `F(p)`, conjunctions of "
        "`F`): the MAP specification contains every clause of the target "
        "(`Formula.to_specification`); `exact` counts MAP == target.",
        "* Scarlet: `scarlet-ltl` " + SCARLET_VERSION + " (operators F, G, X, &, |, !; "
        f"loss threshold {cfg.scarlet_thres} on noise-free files and "
        f"{cfg.scarlet_noisy_thres} on the `5pc_misclass` ones, Scarlet's option for noisy "
        "samples: with 0 it must separate mislabelled traces too and mostly times out) on "
        "the same training split, "
        f"{cfg.scarlet_timeout:.0f} s per file; on timeout the best formula it had written "
        "so far is scored. Its formula is evaluated by `bsi_sklearn.ltl` with Scarlet's "
        "strong next (`X` false at the last step).",
    ]
    if cfg.scarlet and cfg.scarlet_every > 1:
        lines.append(f"* Scarlet ran on every {cfg.scarlet_every}-th file of each folder "
                     "(the first included) to keep the run short; its columns compare both "
                     "learners on those files only.")
    if not cfg.scarlet:
        lines.append("* Scarlet: not run (`--no-scarlet`).")
    if cfg.quick:
        lines.append("* `--quick`: two files per folder; not the full evaluation.")
    a = summary.loc["ALL"]
    lines += [
        "",
        "## Overall",
        "",
        f"* {int(a['files'])} files; BSI mean test accuracy **{_f(a['bsi_accuracy'])}** "
        f"(MAP specification {_f(a['bsi_map_accuracy'])}; the target itself "
        f"{_f(a['target_accuracy'])}), median fit {_f(a['bsi_fit_s_median'], 2)} s.",
        f"* In-template targets: {int(a['in_template'])} files, recovered "
        f"{int(a['recovered'])} (**{_f(a['recovery_rate'])}**), the MAP equal to the target "
        f"in {int(a['recovered_exactly'])}. Where the target holds on >= "
        f"{cfg.min_support:.0%} of the training positives ({int(a['identifiable'])} files; "
        "label noise leaves fewer in some small noisy files): recovered "
        f"{int(a['recovered_identifiable'])}.",
    ]
    if cfg.scarlet:
        lines.append(
            f"* Scarlet ran on {int(a['scarlet_files'])} files and gave a formula on "
            f"{int(a['scarlet_scored'])} ({int(a['scarlet_timeouts'])} timeouts at "
            f"{cfg.scarlet_timeout:.0f} s, {int(a['scarlet_timeouts_scored'])} of them with a "
            f"formula found by then; {int(a['scarlet_failed'])} errors or no formula). On those "
            f"{int(a['scarlet_scored'])} files: Scarlet mean test accuracy "
            f"**{_f(a['scarlet_accuracy'])}**, BSI **{_f(a['bsi_accuracy_on_scarlet_files'])}**"
            f". Median time: Scarlet {_f(a['scarlet_s_median'], 2)} s, BSI "
            f"{_f(a['bsi_fit_s_median'], 2)} s. Files where Scarlet gave no formula count for "
            "neither learner in this comparison.")
    header = ["family", "files", "BSI acc", "MAP acc", "target acc", "in template",
              "recovered", "recovered / identifiable", "BSI fit (median s)"]
    if cfg.scarlet:
        header += ["Scarlet files", "timeouts", "with formula", "BSI acc (same files)",
                   "Scarlet acc", "Scarlet s (median)"]
    table = []
    for fam, s in summary.iterrows():
        r = [f"**{fam}**" if fam == "ALL" else fam, int(s["files"]), _f(s["bsi_accuracy"]),
             _f(s["bsi_map_accuracy"]), _f(s["target_accuracy"]), int(s["in_template"]),
             f"{int(s['recovered'])} ({_f(s['recovery_rate'], 2)})" if s["in_template"]
             else "-",
             f"{int(s['recovered_identifiable'])}/{int(s['identifiable'])}" if s["in_template"]
             else "-", _f(s["bsi_fit_s_median"], 2)]
        if cfg.scarlet:
            r += [int(s["scarlet_files"]), int(s["scarlet_timeouts"]), int(s["scarlet_scored"]),
                  _f(s["bsi_accuracy_on_scarlet_files"]), _f(s["scarlet_accuracy"]),
                  _f(s["scarlet_s_median"], 2)]
        table.append(r)
    lines += ["", "## Per family", "", md_table(header, table)]
    figure = _figure(summary, cfg, Path(out))
    if figure:
        lines += ["", f"![test accuracy per family]({figure})"]
    # per target formula: what BSI finds for each pattern
    lines += ["", "## Per target formula", "",
              "The MAP specification shown is the most frequent one among the files of that "
              "target (with its count).", ""]
    header = ["target", "in template", "files", "BSI acc", "recovered", "most frequent MAP"]
    if cfg.scarlet:
        header += ["Scarlet acc", "most frequent Scarlet formula"]
    table = []
    for tgt, g in df.groupby("target", sort=False):
        maps = g["bsi_map"].value_counts()
        rec = g["recovered"].dropna().astype(bool)
        r = [f"`{tgt}`", "yes" if g["in_template"].iloc[0] else "no", len(g),
             _f(_mean(g["bsi_accuracy"])),
             f"{int(rec.sum())}/{len(rec)}" if len(rec) else "-",
             f"`{maps.index[0]}` ({maps.iloc[0]})"]
        if cfg.scarlet:
            sf = g["scarlet_formula"].dropna().value_counts()
            r += [_f(_mean(g["scarlet_accuracy"])),
                  f"`{sf.index[0]}` ({sf.iloc[0]})" if len(sf) else "-"]
        table.append(r)
    lines += [md_table(header, table)]
    lines += ["", "## Notes", ""] + [f"* {n}" for n in _notes(df, cfg)]
    Path(out).write_text("\n".join(lines) + "\n")


def _figure(summary, cfg, out):
    """Bar chart of test accuracy per family; returns its path relative to ``out``."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    fams = [f for f in summary.index if f != "ALL"] + ["ALL"]
    labels = [f.replace("samples2LTL/", "").replace("_misclass", "").replace(
        "perfect_class", "perfect").replace("disjunctionOfExistence", "disj.") for f in fams]
    bars = [("BSI, all files", "bsi_accuracy"), ("target formula", "target_accuracy")]
    if cfg.scarlet:
        bars += [("BSI, Scarlet's files", "bsi_accuracy_on_scarlet_files"),
                 ("Scarlet", "scarlet_accuracy")]
    fig, ax = plt.subplots(figsize=(10, 4))
    width = 0.8 / len(bars)
    x = np.arange(len(fams))
    for k, (label, col) in enumerate(bars):
        ax.bar(x + (k - (len(bars) - 1) / 2) * width,
               summary.loc[fams, col].astype(float).fillna(0), width, label=label)
    ax.set_xticks(x, labels, rotation=30, ha="right", fontsize=8)
    ax.set_ylim(0, 1.05)
    ax.set_ylabel("mean test accuracy")
    ax.legend(fontsize=8, ncol=len(bars), loc="lower center", bbox_to_anchor=(0.5, 1.0),
              frameon=False)
    fig.tight_layout()
    folder = out.parent / "figures"
    folder.mkdir(parents=True, exist_ok=True)
    stem = "accuracy" if out.stem == "RESULTS_external" else out.stem
    name = f"external_{stem}.png"
    fig.savefig(folder / name, dpi=110)
    plt.close(fig)
    return f"figures/{name}"


def _notes(df, cfg):
    notes = []
    one_class = int(((df["n_test_pos"] == 0) | (df["n_test_neg"] == 0)).sum())
    notes.append(f"{one_class} files have a one-class test split (a class with one trace "
                 "only, kept for training).")
    inf = df["bsi_inference"].value_counts().to_dict()
    notes.append(f"BSI inference: {inf}; largest support {int(df['bsi_hypotheses'].max()):,} "
                 f"hypotheses; slowest fit {df['bsi_fit_s'].max():.2f} s "
                 f"({df.loc[df['bsi_fit_s'].idxmax(), 'file']}).")
    capped = int(((df["bsi_screened_subtasks"] > cfg.max_subtasks)
                  | (df["bsi_screened_globals"] > cfg.max_globals)).sum())
    notes.append(f"{capped} files had more screened candidates than the caps "
                 f"({cfg.max_globals} globals, {cfg.max_subtasks} subtasks).")
    if "mcmc_rhat" in df and df["mcmc_rhat"].notna().any():
        bad = int((df["mcmc_rhat"] > 1.05).sum())
        notes.append(f"MCMC fits with split-R-hat > 1.05: {bad}.")
    return notes


def main(argv=None):
    """Command-line entry point."""
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--data", type=Path, default=DEFAULT_DATA,
                   help="folder of the benchmark traces (default ../shared/benchmarks-data)")
    p.add_argument("--quick", action="store_true", help="two files per folder, short timeouts")
    p.add_argument("--out", type=Path, default=None,
                   help="Markdown report, the per-file CSV beside it (.csv); default "
                        "benchmarks/RESULTS_external.md, with --quick a temporary folder")
    p.add_argument("--no-scarlet", action="store_true", help="do not run Scarlet")
    p.add_argument("--n-jobs", type=int, default=1, help="BSI fits in parallel (default 1)")
    p.add_argument("--scarlet-timeout", type=float, default=None,
                   help="seconds per file (default 20, 10 with --quick)")
    p.add_argument("--scarlet-every", type=int, default=None,
                   help="run Scarlet on every k-th file of each folder (default 6, 1 with "
                        "--quick; 1 = all)")
    p.add_argument("--scarlet-thres", type=float, default=Config.scarlet_thres,
                   help="Scarlet's loss bound on noise-free files (0: separate every trace)")
    p.add_argument("--scarlet-noisy-thres", type=float, default=Config.scarlet_noisy_thres,
                   help="Scarlet's loss bound on the label-noise (*misclass*) files")
    p.add_argument("--scarlet-dir", default=str(DEFAULT_SCARLET_DIR),
                   help="where Scarlet is (or gets) installed")
    p.add_argument("--max-exact", type=int, default=Config.max_exact)
    p.add_argument("--max-subtasks", type=int, default=Config.max_subtasks)
    p.add_argument("--max-globals", type=int, default=Config.max_globals)
    p.add_argument("--min-support", type=float, default=Config.min_support)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--verbose", type=int, default=1)
    args = p.parse_args(argv)
    try:
        files = find_trace_files(args.data)
    except ValueError as exc:
        p.error(str(exc))
    cfg = Config(
        seed=args.seed, min_support=args.min_support, max_globals=args.max_globals,
        max_subtasks=args.max_subtasks, max_exact=args.max_exact, scarlet=not args.no_scarlet,
        scarlet_timeout=args.scarlet_timeout or (10.0 if args.quick else Config.scarlet_timeout),
        scarlet_every=args.scarlet_every or (1 if args.quick else Config.scarlet_every),
        scarlet_thres=args.scarlet_thres, scarlet_noisy_thres=args.scarlet_noisy_thres,
        scarlet_dir=args.scarlet_dir, quick=args.quick,
        n_jobs=args.n_jobs, verbose=args.verbose)
    if args.quick:
        files = quick_files(files)
    if args.out is None:
        # a --quick run must not overwrite the recorded results
        args.out = (Path(tempfile.mkdtemp(prefix="bsi-external-")) / "RESULTS_external.md"
                    if args.quick else HERE / "RESULTS_external.md")
    t0 = time.perf_counter()
    df = run_evaluation(files, args.data, cfg, scarlet_subset(files, cfg.scarlet_every))
    summary = summarize(df, cfg.min_support)
    csv_path = Path(args.out).with_suffix(".csv")
    df.to_csv(csv_path, index=False)
    command = "python benchmarks/external.py " + shlex.join(sys.argv[1:] if argv is None
                                                           else list(argv))
    try:
        shown_csv = csv_path.resolve().relative_to(HERE.parent)
    except ValueError:
        shown_csv = csv_path
    write_report(df, summary, args.out, cfg, command.strip(), time.perf_counter() - t0,
                 shown_csv)
    if cfg.verbose:
        print(summary.to_string(float_format=lambda x: f"{x:.3f}"))
        print(f"wrote {args.out} and {csv_path}")
    return df, summary


if __name__ == "__main__":
    main()
