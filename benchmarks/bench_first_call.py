"""First fit in a fresh process: numba kernels loaded from the disk cache, or compiled cold."""

import json
import os
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

from _common import Section, fmt_s, md_table, python_cmd, repo_root, target

CHILD = Path(__file__).resolve().parent / "_first_call_child.py"


def fresh_process(env_extra=None, timeout=600, args=()):
    """Run the child in a new interpreter; its JSON plus the process wall time."""
    env = dict(os.environ)
    env.update(env_extra or {})
    t0 = time.perf_counter()
    proc = subprocess.run([python_cmd(), str(CHILD), *args], capture_output=True, text=True,
                          env=env, cwd=repo_root(), timeout=timeout)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"first-call child failed: {proc.stderr.strip()[-2000:]}")
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    out["process_s"] = wall
    return out


def run(cfg):
    sec = Section("first_call", "First call in a fresh process (numba compilation and cache)")
    sec.add("A new Python process imports `bsi_sklearn`, fits a tiny problem with MCMC, "
            "calls `predict_proba`, then fits it exactly (`benchmarks/_first_call_child.py`). "
            "*Cached*: the kernels' on-disk numba cache (`cache=True`) is already filled, the "
            "usual case after the first run on a machine. *Cold*: `NUMBA_CACHE_DIR` points to "
            "an empty folder, so every kernel compiles, as on the very first call after "
            "installation.")
    # make sure the default cache is filled before timing the cached case
    fresh_process()
    warm = [fresh_process() for _ in range(cfg.pick(3, 1))]
    cold = []
    if not cfg.quick:  # compilation is deterministic work: one run
        with tempfile.TemporaryDirectory() as tmp:
            cold.append(fresh_process({"NUMBA_CACHE_DIR": tmp}))
    keys = [("import_s", "import bsi_sklearn"), ("mcmc_fit_s", "first MCMC fit"),
            ("predict_s", "first predict_proba"), ("exact_fit_s", "first exact fit"),
            ("process_s", "whole process (interpreter start to exit)")]
    rows = []
    for k, label in keys:
        w = statistics.median(r[k] for r in warm)
        c = statistics.median(r[k] for r in cold) if cold else None
        rows.append([label, fmt_s(w), fmt_s(c) if c is not None else "(skipped in --quick)"])
    sec.add(md_table(["step", "cached (median)", "cold compile (median)"], rows))
    data = {"cached": warm, "cold": cold}
    first_cached = statistics.median(r["import_s"] + r["mcmc_fit_s"] for r in warm)
    targets = [target("first call in a fresh process (import + first fit), numba cache filled",
                      "< 10 s", fmt_s(first_cached), first_cached < 10)]
    if cold:
        first_cold = statistics.median(r["import_s"] + r["mcmc_fit_s"] for r in cold)
        all_cold = statistics.median(r["process_s"] for r in cold)
        targets.append(target("first call in a fresh process, cold numba cache (compiles)",
                              "< 10 s (report)", f"{fmt_s(first_cold)} (MCMC fit); "
                              f"{fmt_s(all_cold)} with predict and exact", first_cold < 10))
        comp = {}
        for r in cold:
            for name, s in r["compile_s"].items():
                comp.setdefault(name, []).append(s)
        crow = sorted(((statistics.median(v), k) for k, v in comp.items()), reverse=True)
        total = sum(s for s, _ in crow)
        sec.add("Where the cold start goes: numba compilation per top-level kernel (callees "
                "are compiled inside their caller), median of the cold runs:")
        sec.add(md_table(["kernel", "compile time", "share"],
                         [[f"`{k}`", fmt_s(s), f"{s / total:.0%}"] for s, k in crow]))
        data["compile_s"] = {k: s for s, k in crow}
    if not cfg.quick:
        _quick_start(sec, data, targets)
    data["targets"] = targets
    sec.data = data
    return sec


def _compile_step(cache, timeout=1200):
    """``python -m bsi_sklearn.compile`` into ``cache``; its wall seconds."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    t0 = time.perf_counter()
    proc = subprocess.run([python_cmd(), "-m", "bsi_sklearn.compile"], capture_output=True,
                          text=True, env=env, cwd=repo_root(), timeout=timeout)
    if proc.returncode != 0:
        raise RuntimeError(f"compile step failed: {proc.stderr.strip()[-2000:]}")
    return time.perf_counter() - t0


def _quick_start(sec, data, targets):
    # Issue 29: a new user's first fit, the README's quick start (import included), in a
    # fresh environment: with no set-up, and after the documented one (the compile step).
    with tempfile.TemporaryDirectory() as tmp:
        cold = fresh_process({"NUMBA_CACHE_DIR": tmp}, args=["quickstart"])
    with tempfile.TemporaryDirectory() as tmp:
        setup_s = _compile_step(tmp)
        after = fresh_process({"NUMBA_CACHE_DIR": tmp}, args=["quickstart"])
    sec.add("The README's quick start (roles given, `inference=\"auto\"`: exact) as the first "
            "fit of a new interpreter, import included (`_first_call_child.py quickstart`), "
            "in a fresh environment: an empty `NUMBA_CACHE_DIR` (*no set-up*), or one the "
            "compile step `python -m bsi_sklearn.compile` filled first (*after set-up*, the "
            "README's set-up; the step's own time beside it).")
    rows = [["no set-up (compiles what the fit calls)", fmt_s(cold["process_s"]),
             fmt_s(cold["fit_s"]), str(len(cold["compile_s"]))],
            ["after set-up", fmt_s(after["process_s"]), fmt_s(after["fit_s"]),
             str(len(after["compile_s"]))],
            ["the set-up itself (`python -m bsi_sklearn.compile`)", fmt_s(setup_s), "", ""]]
    sec.add(md_table(["quick start", "whole process", "fit", "kernels compiled"], rows))
    data["quick_start"] = {"no_setup": cold, "after_setup": after, "setup_s": setup_s}
    targets.append(target("first fit in a fresh environment, import included, after the "
                          "documented set-up (README quick start)", "<= 5 s",
                          fmt_s(after["process_s"]), after["process_s"] <= 5))
    targets.append(target("first fit in a fresh environment, import included, no set-up "
                          "(README quick start; one line says it compiles)", "<= 15 s",
                          fmt_s(cold["process_s"]), cold["process_s"] <= 15))
