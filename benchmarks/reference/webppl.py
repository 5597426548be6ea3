"""Run the paper's model in webppl (``bsi_model.wppl``) on demonstrations prepared in Python.

webppl is installed on demand from the npm registry into ``benchmarks/reference/node_modules``
(``npm install``, versions pinned by ``package.json``); when node or npm is missing, or the
install fails, :func:`find_webppl` says why and the caller skips the reference run.
"""

import json
import math
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
MODEL = HERE / "bsi_model.wppl"
WEBPPL_BIN = HERE / "node_modules" / ".bin" / "webppl"

__all__ = ["find_webppl", "problem_from_demos", "run_webppl", "key_to_specification",
           "WebpplUnavailable"]


class WebpplUnavailable(RuntimeError):
    """webppl cannot be run here; the message says why."""


def find_webppl(install=True, timeout=600):
    """Path of the webppl executable, installing it with npm when allowed.

    Raises
    ------
    WebpplUnavailable
        node or npm is absent, installing is not allowed, or ``npm install`` failed.
    """
    if shutil.which("node") is None:
        raise WebpplUnavailable("node is not installed (https://nodejs.org); "
                                "the webppl reference run is skipped")
    if WEBPPL_BIN.exists():
        return WEBPPL_BIN
    if not install:
        raise WebpplUnavailable(
            f"webppl is not installed in {HERE / 'node_modules'} and installing was not "
            "allowed; run `npm install` in benchmarks/reference/"
        )
    if shutil.which("npm") is None:
        raise WebpplUnavailable("npm is not installed; the webppl reference run is skipped")
    try:
        proc = subprocess.run(["npm", "install", "--no-audit", "--no-fund"], cwd=HERE,
                              capture_output=True, text=True, timeout=timeout)
    except (OSError, subprocess.SubprocessError) as exc:
        raise WebpplUnavailable(f"`npm install` in {HERE} failed: {exc}") from None
    if proc.returncode != 0 or not WEBPPL_BIN.exists():
        tail = (proc.stderr or proc.stdout).strip().splitlines()[-3:]
        raise WebpplUnavailable(f"`npm install` in {HERE} failed: {' / '.join(tail)}")
    return WEBPPL_BIN


def problem_from_demos(X, y, roles, *, prior="sets_of_chains", likelihood="cb", p_global=0.8,
                       p_eventual=0.8, p_part=0.3, n_new=5.0, epsilon=None, input="truth"):
    """The JSON problem of ``bsi_model.wppl``: the demonstrations, labels, hyperparameters.

    ``input="truth"`` passes the clause truth of every demonstration, from the same
    precomputation our fit uses, so both programs see identical data; ``input="traces"``
    passes the traces themselves (the columns the template reads), and webppl checks the
    formula on them at every likelihood evaluation. Returns ``(problem, resolved_roles)``.
    """
    from bsi_sklearn._clauses import clause_truth
    from bsi_sklearn._validation import check_traces, resolve_roles
    from bsi_sklearn.likelihood import resolve_log_epsilon

    traces = check_traces(X)
    r = resolve_roles(roles.get("global_candidates"), roles.get("subtasks"),
                      roles.get("conditions"), traces.n_props, traces.feature_names)
    truth = clause_truth(traces, r)
    y = np.ones(traces.n_demos, dtype=int) if y is None else np.asarray(y, dtype=int)
    problem = {
        "n_globals": r.n_globals,
        "n_subtasks": r.n_subtasks,
        "prior": prior,
        "likelihood": likelihood,
        "p_global": p_global,
        "p_eventual": p_eventual,
        "p_part": p_part,
        "n_new": n_new,
        "log_eps": resolve_log_epsilon(epsilon, r.n_globals, r.n_subtasks),
        "labels": [int(v) for v in y],
        "input": input,
    }
    if input == "truth":
        problem["truth"] = truth.astype(int).tolist()
    elif input == "traces":
        demos = []
        for i in range(traces.n_demos):
            tr = traces.data[traces.offsets[i]:traces.offsets[i + 1]].astype(int)
            demos.append({
                "tau": [tr[:, p].tolist() for p in r.global_idx],
                "omega": [tr[:, p].tolist() for p in r.subtask_idx],
                "pi": [1 if c < 0 else int(tr[0, c]) for c in r.condition_idx],
            })
        problem["traces"] = demos
    else:
        raise ValueError(f"input must be 'truth' or 'traces', got {input!r}")
    return problem, r


def run_webppl(problem, *, seed, method="MCMC", samples=10_000, burn=100, timeout=3600,
               webppl=None):
    """Run ``bsi_model.wppl`` once.

    Returns
    -------
    dict
        ``dist`` (key -> probability), ``inference_s`` (wall time of ``Infer`` measured inside
        webppl), ``process_s`` (wall time of the whole node process: start-up, compilation of
        the program, inference), ``seed``.
    """
    webppl = webppl or find_webppl(install=False)
    payload = dict(problem, method=method, samples=int(samples), burn=int(burn))
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "problem.json")
        with open(path, "w") as fh:
            json.dump(payload, fh)
        t0 = time.perf_counter()
        proc = subprocess.run(
            [str(webppl), str(MODEL), "--require", "fs", "--random-seed", str(int(seed)),
             "--", "--data", path],
            capture_output=True, text=True, timeout=timeout, cwd=HERE,
        )
        process_s = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"webppl failed ({proc.returncode}): {proc.stderr.strip()[-2000:]}")
    line = next((ln for ln in proc.stdout.splitlines() if ln.startswith("{")), None)
    if line is None:
        raise RuntimeError(f"webppl printed no result: {proc.stdout[-2000:]}")
    out = json.loads(line)
    dist = {}
    for key, p in zip(out["support"], out["probs"]):
        dist[key] = dist.get(key, 0.0) + float(p)
    total = math.fsum(dist.values())
    dist = {k: v / total for k, v in dist.items()}
    return {"dist": dist, "inference_s": float(out["seconds"]), "process_s": process_s,
            "seed": int(seed)}


def key_to_specification(key, roles):
    """Turn a webppl key ``g:..|f:..|o:a>b,..`` into a ``Specification`` over ``roles``."""
    from bsi_sklearn.specification import Specification

    parts = dict(chunk.split(":", 1) for chunk in key.split("|"))
    g_names, s_names = roles.global_names(), roles.subtask_names()

    def ints(text):
        return [int(v) for v in text.split(",") if v != ""]

    orders = [tuple(s_names[int(v)] for v in pair.split(">"))
              for pair in parts["o"].split(",") if pair]
    return Specification(globals=[g_names[j] for j in ints(parts["g"])],
                         eventuals=[s_names[w] for w in ints(parts["f"])],
                         orders=orders, conditions=roles.condition_names())


def to_specification_dist(dist, roles):
    """``{Specification: probability}`` from a webppl key distribution."""
    out = {}
    for key, p in dist.items():
        spec = key_to_specification(key, roles)
        out[spec] = out.get(spec, 0.0) + p
    return out
