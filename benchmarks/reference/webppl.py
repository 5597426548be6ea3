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
           "to_specification_dist", "most_probable", "map_agrees", "plan_samples",
           "WebpplUnavailable"]

PRIORS = ("sets_of_chains", "forest")
LIKELIHOODS = ("cb", "ci")
INPUTS = ("truth", "traces")
METHODS = ("MCMC", "enumerate")


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
    from bsi_sklearn.data.roles import resolve_roles
    from bsi_sklearn.data.traces import check_traces
    from bsi_sklearn.model.clauses import clause_truth
    from bsi_sklearn.model.likelihood import resolve_log_epsilon

    for name, value, allowed in (("prior", prior, PRIORS), ("likelihood", likelihood, LIKELIHOODS),
                                 ("input", input, INPUTS)):
        if value not in allowed:
            raise ValueError(f"{name} must be one of {list(allowed)}, got {value!r}")
    traces = check_traces(X)
    r = resolve_roles(roles.get("global_candidates"), roles.get("subtasks"),
                      roles.get("conditions"), traces.n_props, traces.feature_names)
    truth = clause_truth(traces, r)
    y = np.ones(traces.n_demos, dtype=int) if y is None else np.asarray(y, dtype=int)
    if y.shape != (traces.n_demos,) or not np.isin(y, (0, 1)).all():
        raise ValueError(f"y must hold one 0/1 label per demonstration ({traces.n_demos}), "
                         f"got {y.tolist()!r}")
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
    return problem, r


def run_webppl(problem, *, seed, method="MCMC", samples=10_000, burn=100, timeout=3600,
               webppl=None):
    """Run ``bsi_model.wppl`` once.

    Returns
    -------
    dict
        ``dist`` (key -> probability), ``inference_s`` (wall time of ``Infer`` measured inside
        webppl), ``inference_cpu_s`` (node's CPU time during ``Infer``: less sensitive to
        other load on the machine), ``process_s`` (wall time of the whole node process:
        start-up, compilation of the program, inference), ``seed``.
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {list(METHODS)}, got {method!r}")
    if method == "MCMC" and (int(samples) < 1 or int(burn) < 0):
        raise ValueError(f"samples must be >= 1 and burn >= 0, got {samples!r} and {burn!r}")
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
    return {"dist": dist, "inference_s": float(out["seconds"]),
            "inference_cpu_s": float(out.get("cpu_seconds", "nan")), "process_s": process_s,
            "seed": int(seed)}


def key_to_specification(key, roles):
    """Turn a webppl key ``g:..|f:..|o:a>b,..`` into a ``Specification`` over ``roles``.

    Indices refer to ``roles.global_names()`` (after ``g:``) and ``roles.subtask_names()``
    (after ``f:`` and in the ``a>b`` order pairs, *a precedes b*). The ``Specification`` closes
    the orders transitively, so a key listing only a chain's edges and one listing every
    ancestor -> descendant pair (what ``bsi_model.wppl`` prints) give the same formula.

    Raises
    ------
    ValueError
        The key is malformed or an index is out of range; the message quotes the key.
    """
    from bsi_sklearn.specification import Specification

    g_names, s_names = roles.global_names(), roles.subtask_names()
    try:
        parts = dict(chunk.split(":", 1) for chunk in key.split("|"))
        if sorted(parts) != ["f", "g", "o"]:
            raise ValueError

        def ints(text, names):
            out = [int(v) for v in text.split(",") if v != ""]
            if any(i < 0 or i >= len(names) for i in out):
                raise ValueError
            return out

        orders = []
        for pair in parts["o"].split(","):
            if pair:
                a, b = ints(pair.replace(">", ","), s_names)
                orders.append((s_names[a], s_names[b]))
        globals_ = [g_names[j] for j in ints(parts["g"], g_names)]
        eventuals = [s_names[w] for w in ints(parts["f"], s_names)]
    except ValueError:
        raise ValueError(f"malformed webppl formula key {key!r} for {len(g_names)} global "
                         f"candidates and {len(s_names)} subtasks") from None
    return Specification(globals=globals_, eventuals=eventuals, orders=orders,
                         conditions=roles.condition_names())


def to_specification_dist(dist, roles):
    """``{Specification: probability}`` from a webppl key distribution."""
    out = {}
    for key, p in dist.items():
        spec = key_to_specification(key, roles)
        out[spec] = out.get(spec, 0.0) + p
    return out


def most_probable(dist):
    """The most probable outcome of ``{outcome: probability}`` (webppl: most frequent formula).

    Examples
    --------
    >>> most_probable({"g:0|f:|o:": 0.3, "g:|f:|o:": 0.7})
    'g:|f:|o:'
    """
    if not dist:
        raise ValueError("the distribution is empty")
    return max(dist.items(), key=lambda kv: kv[1])[0]


def map_agrees(spec, exact, rtol=1e-9):
    """Whether ``spec`` is a MAP of the ``exact`` posterior ``{Specification: probability}``.

    Ties count: when several formulas share the largest exact probability (up to ``rtol``),
    any of them agrees.

    Examples
    --------
    >>> map_agrees("b", {"a": 0.4, "b": 0.4, "c": 0.2}), map_agrees("c", {"a": 0.6, "c": 0.4})
    (True, False)
    """
    if not exact:
        raise ValueError("the exact posterior is empty")
    top = max(exact.values())
    return exact.get(spec, 0.0) >= top * (1.0 - rtol)


def plan_samples(rate, samples, max_seconds):
    """How many samples to time so that one run stays under ``max_seconds``.

    ``rate`` is the measured samples per second of a pilot run. Returns ``(n, extrapolated)``:
    ``n = samples`` when the full run fits, else the largest round number that fits (at least
    100) and ``extrapolated=True``: its time is to be scaled by ``samples / n``.

    Examples
    --------
    >>> plan_samples(rate=500.0, samples=10_000, max_seconds=60)
    (10000, False)
    >>> plan_samples(rate=5.0, samples=10_000, max_seconds=1200)
    (6000, True)
    """
    if rate <= 0 or samples < 1 or max_seconds <= 0:
        raise ValueError(f"rate, samples and max_seconds must be positive, got {rate!r}, "
                         f"{samples!r}, {max_seconds!r}")
    if samples / rate <= max_seconds:
        return int(samples), False
    fit = rate * max_seconds
    n = max(100, int(10 ** math.floor(math.log10(fit))) * int(fit // 10 ** math.floor(
        math.log10(fit))))
    return min(n, int(samples)), True
