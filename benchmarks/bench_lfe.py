"""Issue-4 numbers: the default LFE dataset simulated, annotated and turned into propositions.

    python benchmarks/bench_lfe.py [--quick] [--repeats N] [--out DIR]   # standalone
    python benchmarks/run.py --only lfe                                  # in the suite
"""

import os
import sys

os.environ.setdefault("MPLBACKEND", "Agg")  # figures are written to files, never shown

import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)

# isort: split

from _common import Section, fmt_n, fmt_s, md_table, save_figure, target, time_call  # noqa: E402
from sklearn.utils import check_random_state  # noqa: E402

from lfe import (  # noqa: E402
    LFEPropositionExtractor,
    annotate_scenarios,
    random_scenario_config,
    simulate_scenario,
)

N_DEFAULT = 24  # scenarios of load_lfe_dataset()
TARGET_S = 20.0  # issue 4: the default dataset simulated and extracted in under 20 s


def default_plan(n_scenarios=N_DEFAULT, random_state=0):
    """The configurations and seeds ``make_lfe_dataset(n, random_state)`` simulates."""
    rng = check_random_state(random_state)
    plan = []
    for k in range(n_scenarios):
        config = random_scenario_config(rng)
        plan.append((config, int(rng.randint(0, 2**31 - 1)), f"lfe-{k:03d}"))
    return plan


def simulate(plan):
    """Every scenario of ``plan``, in order."""
    return [simulate_scenario(config, seed, scenario_id=sid) for config, seed, sid in plan]


def run(cfg):
    sec = Section("lfe", "LFE domain (issue 4): simulation, annotation and proposition "
                         "extraction of the default dataset")
    reps = cfg.pick(max(3, cfg.repeats), 1)
    warmup = cfg.pick(1, 0)
    plan = default_plan()
    sec.add(f"The default dataset of `lfe.load_lfe_dataset()`: {N_DEFAULT} offensive-counter-air "
            "missions (18 friendly aircraft, 4-12 hostile fighters, 0-5 SAM sites, 10 s step), "
            "the same configurations and seeds as `make_lfe_dataset(24, random_state=0)`. "
            f"Median wall and CPU time over {reps} timed call{'s' * (reps != 1)} (after "
            f"{warmup} warm-up call{'s' * (warmup != 1)}), one process, one thread; on a "
            "shared machine the CPU time is the steadier number.")

    t_sim, c_sim, scenarios, _ = time_call(lambda: simulate(plan), reps, warmup=warmup)
    t_ann, c_ann, _, _ = time_call(lambda: annotate_scenarios(scenarios, noise=0.04,
                                                              time_noise=10.0, random_state=0),
                                   reps, warmup=warmup)
    paper = LFEPropositionExtractor()
    t_ext, c_ext, traces, _ = time_call(lambda: paper.fit_transform(scenarios), reps,
                                        warmup=warmup)
    extended = LFEPropositionExtractor(propositions="extended")
    t_extx, c_extx, traces_x, _ = time_call(lambda: extended.fit_transform(scenarios), reps,
                                            warmup=warmup)

    n = len(scenarios)
    track_rows = sum(len(sc.tracks) for sc in scenarios)
    n_weapons = sum(len(sc.weapons) for sc in scenarios)
    steps = [len(tr) for tr in traces]
    rows = [
        ["simulate (`simulate_scenario` x 24)", fmt_s(t_sim), fmt_s(c_sim), fmt_n(n / t_sim),
         f"{fmt_n(track_rows)} track rows, {fmt_n(n_weapons)} weapons"],
        ["annotate (`annotate_scenarios`, the commander)", fmt_s(t_ann), fmt_s(c_ann),
         fmt_n(n / t_ann), "MO1-MO3 and four phase times"],
        ["extract, paper propositions (11)", fmt_s(t_ext), fmt_s(c_ext), fmt_n(n / t_ext),
         f"traces of {min(steps)}-{max(steps)} steps, {fmt_n(sum(steps))} in all"],
        [f"extract, extended propositions ({traces_x[0].shape[1]})", fmt_s(t_extx),
         fmt_s(c_extx), fmt_n(n / t_extx), ""],
    ]
    sec.add(md_table(["step", "wall", "cpu", "scenarios/s", "notes"], rows))
    whole = t_sim + t_ext
    sec.add(f"Simulating and extracting the whole default dataset takes {fmt_s(whole)} "
            f"({fmt_s(whole + t_ann)} with the annotation); the target is {TARGET_S:g} s.")

    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.2))
    labels = ["simulate", "annotate", "extract (paper)", "extract (extended)"]
    rates = [n / t_sim, n / t_ann, n / t_ext, n / t_extx]
    ax.barh(labels, rates, color=["C0", "C1", "C2", "C3"])
    ax.set_xscale("log")
    ax.set_xlabel("scenarios / s (log scale)")
    ax.invert_yaxis()
    ax.set_title(f"LFE default dataset ({n} scenarios)")
    ax.grid(True, axis="x", alpha=0.3)
    sec.add(save_figure(fig, cfg, "lfe_rates"))

    sec.data = {
        "n_scenarios": n, "track_rows": track_rows, "weapons": n_weapons,
        "trace_steps": int(sum(steps)),
        "simulate_s": t_sim, "annotate_s": t_ann, "extract_s": t_ext,
        "extract_extended_s": t_extx,
        "simulate_per_s": n / t_sim, "annotate_per_s": n / t_ann, "extract_per_s": n / t_ext,
        "extract_extended_per_s": n / t_extx,
        "targets": [target(f"default LFE dataset ({n} scenarios) simulated and extracted",
                           f"< {TARGET_S:g} s", f"{fmt_s(whole)} ({fmt_n(n / t_sim)} "
                           f"scenarios/s simulated, {fmt_n(n / t_ext)} /s extracted)",
                           whole < TARGET_S)],
    }
    return sec


def main(argv=None):
    """Run this benchmark alone and print its Markdown."""
    import argparse
    import tempfile
    from pathlib import Path

    from _common import Config

    parser = argparse.ArgumentParser(prog="benchmarks/bench_lfe.py", description=__doc__)
    parser.add_argument("--quick", action="store_true", help="one repeat, no warm-up")
    parser.add_argument("--repeats", type=int, default=7, help="timed calls (median; default 7)")
    parser.add_argument("--out", default=None,
                        help="folder for figures/ (default: a temporary folder)")
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error(f"--repeats must be at least 1, got {args.repeats}")
    out = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="bench_lfe_"))
    cfg = Config(quick=args.quick, repeats=args.repeats, out=out)
    sec = run(cfg)
    print(f"## {sec.title}\n")
    print("\n\n".join(sec.text))
    for t in sec.data["targets"]:
        print(f"\ntarget: {t['name']}: {t['measured']} (wanted {t['target']}) -> "
              f"{'met' if t['ok'] else 'MISSED'}")
    print(f"\nfigures in {cfg.figures}")
    return 0 if all(t["ok"] is not False for t in sec.data["targets"]) else 1


if __name__ == "__main__":
    sys.exit(main())
