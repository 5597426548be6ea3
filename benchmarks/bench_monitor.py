"""Runtime monitoring: steps per second of ``PosteriorMonitor.update`` and ``monitor_proba``.

    python benchmarks/bench_monitor.py           # writes benchmarks/RESULTS_monitor.md
    python benchmarks/run.py --only monitor      # as a section of RESULTS.md
"""

import sys
import time
from pathlib import Path

import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)

# isort: split

import numpy as np
from _common import Config, Section, fmt_n, machine_info, md_table, problem_roles, target
from _data import make_demos

from bsi_sklearn import BSIClassifier

TARGET_STEPS_PER_S = 1e5


def _steps_per_s(fn, n_steps, repeats):
    fn()  # warm-up: numba compiled, caches filled
    walls = []
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        fn()
        walls.append(time.perf_counter() - t0)
    return n_steps / min(walls)  # the fastest pass: least disturbed by other processes


def run(cfg):
    """Monitor a long trace step by step and in batch; a section of RESULTS.md."""
    sec = Section("monitor", "runtime monitoring (steps per second)")
    X, y, roles = make_demos(2, 50, seed=7)
    clf = BSIClassifier(**problem_roles(roles), inference="mcmc", random_state=0).fit(X, y)
    n_specs = len(clf.posterior_)
    total = cfg.pick(20_000, 2_000)
    lengths = cfg.pick([10, 100, 1_000, 10_000], [10, 100, 1_000])
    rows, data = [], {"n_specifications": n_specs, "length": lengths, "update": [],
                      "update_int": [], "batch": []}
    for L in lengths:
        Xt, _, _ = make_demos(max(1, total // L), L, seed=8)
        traces = [x.astype(bool) for x in Xt]
        as_int = [x.astype(np.int64) for x in Xt]
        n_steps = sum(len(x) for x in Xt)
        mon = clf.monitor()

        def step_by_step(traces=traces, mon=mon):
            for trace in traces:
                mon.reset()
                for row in trace:
                    mon.update(row)

        def step_by_step_int(traces=as_int, mon=mon):
            for trace in traces:
                mon.reset()
                for row in trace:
                    mon.update(row)

        upd = _steps_per_s(step_by_step, n_steps, cfg.repeats)
        upd_int = _steps_per_s(step_by_step_int, n_steps, cfg.repeats)
        batch = _steps_per_s(lambda Xt=Xt: clf.monitor_proba(Xt), n_steps, cfg.repeats)
        data["update"].append(upd)
        data["update_int"].append(upd_int)
        data["batch"].append(batch)
        rows.append([fmt_n(L), fmt_n(n_steps), fmt_n(upd), fmt_n(upd_int), fmt_n(batch)])
    sec.add(
        f"A posterior of {n_specs:,} specifications (MCMC on 2 acceptable demonstrations of "
        "`benchmarks/_data.make_demos`, 5 globals x 5 subtasks with conditions, Prior 2) "
        "monitors synthetic traces. `update` is one Python call per step (a boolean row; "
        "the integer column validates 0/1 values too) and returns a `Verdict`; "
        "`monitor_proba` is the batch form (one numba loop over every step of every trace, "
        "validation included). Down the table the traces get longer and fewer (about "
        f"{total:,} steps in all): the rate must not fall with the length, since a step's "
        "cost is independent of the trace's length. The fastest of the timed passes (the "
        "machine is shared: see the load average above)."
    )
    sec.add(md_table(["mean trace length", "steps", "update (bool) steps/s",
                      "update (int) steps/s", "monitor_proba steps/s"], rows))
    steady = [u for L, u in zip(lengths, data["update"]) if L >= 100]
    worst = min(steady)
    sec.add(f"The target is read on traces of at least 100 steps: {fmt_n(worst)} steps/s. On "
            "10-step traces every trace also pays its reset and the "
            "steps where clauses change (each one sums the posterior: O(n_specifications)), "
            "so fewer steps per second there.")
    sec.data = {**data, "targets": [target(
        f"update() with a ~1,000-formula posterior ({n_specs:,})",
        f">= {fmt_n(TARGET_STEPS_PER_S)} steps/s",
        f"{fmt_n(worst)} steps/s (slowest length >= 100)", worst >= TARGET_STEPS_PER_S)]}
    return sec


def example_figure(path):
    """The README picture: a new demonstration monitored under a posterior of few data."""
    from bsi_sklearn.datasets import make_poi_threat_demos
    from bsi_sklearn.monitor.figure import monitor_frame, plot_monitor

    data = make_poi_threat_demos(2, n_demos=8, n_negative=8, random_state=3)
    train = [0, 1, 8]
    clf = BSIClassifier(**data.roles, random_state=0).fit(
        [data.traces[i] for i in train], data.labels[train])
    frame = monitor_frame(clf.posterior_, data.traces[10])  # visits POIs out of order
    ax = plot_monitor(frame, title="Scenario 2, fitted on 2 good and 1 bad demonstrations: a "
                                   "new one that visits POIs out of order")
    ax.figure.savefig(path, dpi=90)
    return frame


def main(argv=None):
    """Run the section alone and write ``RESULTS_monitor.md`` next to this file."""
    quick = "--quick" in (sys.argv[1:] if argv is None else argv)
    cfg = Config(quick=quick, repeats=2 if quick else 5)
    sec = run(cfg)
    info = machine_info()
    text = "\n\n".join([f"# {sec.title}",
                        f"Measured on {info['date']} on {info.get('cpu', 'unknown CPU')} "
                        f"({info.get('usable_cores', '?')} usable cores, load average "
                        f"{info.get('load_average', '?')}, commit {info.get('commit', '?')})"
                        + (" (--quick)" if quick else "") + ".", *sec.text,
                        md_table(["target", "wanted", "measured", "met"],
                                 [[t["name"], t["target"], t["measured"], t["ok"]]
                                  for t in sec.data["targets"]])])
    out = Path(__file__).resolve().parent / "RESULTS_monitor.md"
    if not quick:
        out.write_text(text + "\n")
        example_figure(out.parent / "figures" / "monitor_example.png")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
