"""Scarlet (Raha et al., TACAS 2022) for the external benchmarks: its formulas, its semantics, its
worker process.

Scarlet prints formulas over atoms ``v0, v1, ...`` (:func:`parse_scarlet_formula` reads both of
its notations) and evaluates ``X`` as a strong next on finite traces
(:func:`evaluate_scarlet_formula` applies that semantics with :mod:`bsi_sklearn.ltl`).
:func:`ensure_scarlet` installs PyPI ``scarlet-ltl`` into a private directory and
:class:`ScarletWorker` runs it, one training sample at a time, in ``_scarlet_worker.py``.
Used by ``external.py``; nothing here fits BSI.
"""

from __future__ import annotations

import json
import os
import select
import shlex
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

from bsi_sklearn.ltl import And, Atom, Next, Not, parse_ltl

__all__ = [
    "DEFAULT_SCARLET_DIR",
    "LAST",
    "SCARLET_VERSION",
    "ScarletWorker",
    "ensure_scarlet",
    "evaluate_scarlet_formula",
    "parse_scarlet_formula",
    "scarlet_semantics",
    "with_last",
]

HERE = Path(__file__).resolve().parent
WORKER = HERE / "_scarlet_worker.py"
SCARLET_VERSION = "0.0.4"
DEFAULT_SCARLET_DIR = Path.home() / ".cache" / "bsi-sklearn" / f"scarlet-ltl-{SCARLET_VERSION}"
LAST = "__last__"  # proposition true at the last step: Scarlet's strong next needs it


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
            [sys.executable, "-u", str(WORKER)], stdin=subprocess.PIPE,
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
