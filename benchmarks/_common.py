"""Shared helpers of the benchmark modules: timing, configuration, tables, figures."""

import datetime
import os
import platform
import statistics
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ["Config", "Section", "time_call", "machine_info", "md_table", "fmt_s", "fmt_n",
           "save_figure", "repo_root", "target", "problem_roles", "parse_param"]


def repo_root():
    """The repository root (the parent of ``benchmarks/``)."""
    return Path(__file__).resolve().parent.parent


@dataclass
class Config:
    """What every benchmark module receives."""

    quick: bool = False
    repeats: int = 5
    out: Path = field(default_factory=lambda: repo_root() / "benchmarks")
    install_webppl: bool = True

    @property
    def figures(self):
        path = self.out / "figures"
        path.mkdir(parents=True, exist_ok=True)
        return path

    def pick(self, full, quick):
        """``quick`` in --quick mode, else ``full``."""
        return quick if self.quick else full


@dataclass
class Section:
    """The Markdown a benchmark contributes to RESULTS.md, with its raw numbers."""

    name: str
    title: str
    text: list = field(default_factory=list)
    data: dict = field(default_factory=dict)
    seconds: float = 0.0

    def add(self, *chunks):
        self.text.extend(chunks)


def time_call(fn, repeats, warmup=1):
    """Median wall and CPU (this process) seconds of ``fn()`` over ``repeats`` calls.

    Returns ``(median_wall, median_cpu, last_result, all_walls)``.
    """
    result = None
    for _ in range(warmup):
        result = fn()
    walls, cpus = [], []
    for _ in range(max(1, repeats)):
        c0, t0 = time.process_time(), time.perf_counter()
        result = fn()
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
    return statistics.median(walls), statistics.median(cpus), result, walls


def _cpu_model():
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _git_commit():
    try:
        out = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=repo_root(),
                             capture_output=True, text=True, timeout=10)
        return out.stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def machine_info():
    """CPU, cores, memory, versions, date: the header of RESULTS.md."""
    import numba
    import sklearn

    info = {
        "date": datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z"),
        "cpu": _cpu_model(),
        "logical_cores": os.cpu_count(),
        "usable_cores": len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
        else os.cpu_count(),
        "platform": platform.platform(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "numba": numba.__version__,
        "scikit-learn": sklearn.__version__,
        "commit": _git_commit(),
    }
    try:
        pages = os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
        info["memory_gib"] = round(pages / 2**30, 1)
    except (ValueError, OSError, AttributeError):
        pass
    try:
        info["load_average"] = tuple(round(x, 2) for x in os.getloadavg())
    except OSError:
        pass
    try:
        import torch

        info["torch"] = torch.__version__
    except ImportError:
        pass
    return info


def fmt_s(seconds):
    """Seconds in a readable unit."""
    if seconds is None or not np.isfinite(seconds):
        return "-"
    if seconds < 1e-3:
        return f"{seconds * 1e6:.0f} us"
    if seconds < 1:
        return f"{seconds * 1e3:.1f} ms"
    return f"{seconds:.2f} s"


def fmt_n(x, digits=3):
    """A count or rate with thousands separators / significant digits."""
    if x is None:
        return "-"
    if isinstance(x, (int, np.integer)):
        return f"{int(x):,}"
    if not np.isfinite(x):
        return str(x)
    if abs(x) >= 1000:
        return f"{x:,.0f}"
    return f"{x:.{digits}g}"


def md_table(header, rows):
    """A GitHub Markdown table."""
    lines = ["| " + " | ".join(header) + " |", "| " + " | ".join("---" for _ in header) + " |"]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def save_figure(fig, cfg, name):
    """Save a matplotlib figure as ``figures/<name>.png``; return the Markdown image link."""
    import matplotlib.pyplot as plt

    path = cfg.figures / f"{name}.png"
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return f"![{name}](figures/{name}.png)"


def python_cmd():
    """The interpreter running the benchmarks (for subprocess measurements)."""
    return sys.executable


def target(name, wanted, measured, ok):
    """One row of the targets table: ``ok`` is True, False, or None (not measured)."""
    return {"name": name, "target": wanted, "measured": measured,
            "ok": None if ok is None else bool(ok)}


def clause_problem(X, roles):
    """``(traces, resolved roles, clause truth)`` of demonstrations, as ``fit`` computes them."""
    from bsi_sklearn.data.roles import resolve_roles
    from bsi_sklearn.data.traces import check_traces
    from bsi_sklearn.model.clauses import clause_truth

    traces = check_traces(X)
    r = resolve_roles(roles["global_candidates"], roles["subtasks"], roles["conditions"],
                      traces.n_props, traces.feature_names)
    return traces, r, clause_truth(traces, r)


def problem_roles(roles):
    """``BSIClassifier`` keyword arguments for a roles dict."""
    return dict(global_candidates=roles["global_candidates"], subtasks=roles["subtasks"],
                conditions=roles["conditions"])


def parse_param(text):
    """``NAME=VALUE`` (a Python literal) as a ``(name, value)`` pair: a command line's
    classifier parameter.

    >>> parse_param("p_global=0.5")
    ('p_global', 0.5)
    """
    import argparse
    import ast

    name, sep, value = text.partition("=")
    if not sep or not name.isidentifier():
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got {text!r}")
    try:
        return name, ast.literal_eval(value)
    except (ValueError, SyntaxError):
        raise argparse.ArgumentTypeError(f"{text!r}: VALUE must be a Python literal "
                                         "(quote strings: likelihood=\"'ci'\")") from None
