"""The pattern library's truth at real sizes: every template, its instances over all propositions.

For each catalogue template, :func:`bsi_sklearn.model.patterns.pattern_truth` on every instance
over ``n_props`` propositions (ordered pairs for an asymmetric binary template), on ``n_demos``
random demonstrations of ``T`` steps (each proposition true with probability 0.1, as sparse as
event logs' "current activity" columns). One user template (``G(x -> F(y))``, the generic
evaluator) on the same data, for its cost against the catalogue's recurrence of the same
formula (``Response``). Compiled first (one warm-up call on a tiny problem); best of
``--repeats`` calls; peak memory is the output array (``n_demos x n_instances`` bytes).

    python benchmarks/bench_patterns.py            # about 2 minutes on one core
    python benchmarks/bench_patterns.py --quick

Writes ``benchmarks/RESULTS_patterns.md``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)

# isort: split

import numpy as np
from _common import machine_info, md_table

from bsi_sklearn.model.patterns import TEMPLATES, get_template, instantiate, pattern_truth

HERE = Path(__file__).resolve().parent


def _data(n_demos, steps, n_props, seed=0):
    rng = np.random.default_rng(seed)
    data = (rng.random((n_demos * steps, n_props)) < 0.1).astype(np.uint8)
    return data, np.arange(0, n_demos * steps + 1, steps, dtype=np.int64)


def _best(fn, repeats):
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes (a smoke run)")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", type=Path, default=HERE / "RESULTS_patterns.md")
    args = ap.parse_args(argv)
    sizes = [(1_000, 20, 20), (10_000, 20, 40)] if not args.quick else [(200, 10, 8)]
    user = get_template("G(x -> F(y))")
    tiny, tiny_off = _data(2, 3, 2)
    for t in list(TEMPLATES.values()) + [user]:  # compile outside the timings
        pattern_truth(t, tiny, tiny_off, [list(range(len(t.slots)))])
    rows, growth = [], []
    for n_demos, steps, n_props in sizes:
        data, offsets = _data(n_demos, steps, n_props)
        for t in list(TEMPLATES.values()) + [user]:
            cols = np.array(instantiate(t, range(n_props)), dtype=np.int64)
            if t is user:
                cols = cols[: max(1, len(cols) // 10)]  # a tenth: its rate is what matters
            wall, out = _best(lambda t=t, c=cols, d=data, o=offsets: pattern_truth(t, d, o, c),
                              args.repeats)
            cells = n_demos * steps * len(cols)
            rows.append([f"{n_demos:,} x {steps} x {n_props}", t.name, t.family,
                         f"{len(cols):,}", f"{wall:.3f}", f"{cells / wall / 1e6:,.0f}",
                         f"{out.nbytes / 2**20:,.1f}"])
            if t.name in ("Response", user.name):
                growth.append((t.name, n_demos * steps, len(cols), wall))
    info = machine_info()
    text = [
        "# Pattern library: truth at real sizes (issue 28)",
        "",
        f"Command: `python benchmarks/bench_patterns.py{' --quick' if args.quick else ''}`",
        "",
        f"Machine: {info['cpu']}, {info['usable_cores']} usable cores, "
        f"{info.get('memory_gib', '?')} GiB; Python {info['python']}, numpy {info['numpy']}, "
        f"numba {info['numba']}. Date: {info['date']}. Commit: `{info['commit']}`. "
        f"Load average at the end: {info.get('load_average')}.",
        "",
        "Every instance of each template over all propositions (a user template on a tenth "
        "of its instances), random demonstrations with each proposition true at a step with "
        "probability 0.1; best of "
        f"{args.repeats} calls after compilation. Rate: demonstration-steps x instances a "
        "second; memory: the uint8 truth returned.",
        "",
        md_table(["demos x steps x propositions", "template", "family", "instances",
                  "seconds", "M cells/s", "truth MiB"], rows),
        "",
        "The catalogue's recurrence against the generic evaluator of the same formula "
        "(`Response` = `G(x -> F(y))`), cells a second:",
        "",
    ]
    by = {}
    for name, steps_total, n_inst, wall in growth:
        by.setdefault(name, []).append(steps_total * n_inst / wall)
    for name, rates in by.items():
        text.append(f"- `{name}`: " + ", ".join(f"{r / 1e6:,.0f} M" for r in rates))
    args.out.write_text("\n".join(text) + "\n", encoding="utf-8")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
