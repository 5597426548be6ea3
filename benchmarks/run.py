"""Run the bsi-sklearn benchmark suite and write RESULTS.md (with figures/*.png).

    python benchmarks/run.py                 # full suite (about 10 minutes on 2 cores)
    python benchmarks/run.py --quick         # every size shrunk: about a minute
    python benchmarks/run.py --quick --only exact,predict --out /tmp/bench
    python benchmarks/run.py --only scaling,reference
    python benchmarks/run.py --list          # the benchmarks by name

The benchmarks ship with the repository, not with the installed package: this script is their
only entry point, and the package never loads anything from this folder.

Every benchmark is a module ``bench_<name>.py`` next to this file with a ``run(cfg)`` function
returning a ``Section`` (Markdown, raw numbers, and the targets it checks). Timings are medians
over ``--repeats`` calls after a warm-up call (numba compiled); see each section for details.
"""

import argparse
import importlib
import json
import os
import sys
import time
import traceback
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")  # figures are written to files, never shown
HERE = Path(__file__).resolve().parent
import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)

# isort: split

from _common import Config, Section, fmt_s, machine_info, md_table  # noqa: E402

#: name -> (module, one-line description), in the order of RESULTS.md. Modules that are not
#: there (``bench_lfe`` and ``bench_reference`` are written separately) are skipped with a note.
BENCHMARKS = {
    "core": ("bench_core", "issue-2 numbers: 10,000-sample fit, throughput, exact 5 x 5, "
                           "1,000 x 1,000 x 6 fit"),
    "scaling": ("bench_scaling", "fit time vs demonstrations, trace length, subtasks"),
    "throughput": ("bench_throughput", "coordinate updates (MH steps) per second, 1 and 2 "
                                       "chains in parallel"),
    "exact": ("bench_exact", "exact enumeration time vs number of hypotheses"),
    "exact_limit": ("bench_exact_limit", "issue-13 targets: the dinner table and 2 x 9 exactly, "
                                         "against one chain; ten subtasks; peak memory"),
    "exact_noroles": ("bench_exact_noroles", "issue-19 targets: LFE missions without roles, "
                                             "the default classifier exact within a second"),
    "accuracy": ("bench_accuracy", "MCMC posterior vs exact enumeration (total variation)"),
    "mcmc_mixing": ("bench_mcmc_mixing", "issue-19 targets: default MCMC fits vs exact on the "
                                         "LFE template and samples2LTL files"),
    "predict": ("bench_predict", "predict_proba throughput"),
    "monitor": ("bench_monitor", "runtime monitoring: PosteriorMonitor.update and "
                                 "monitor_proba steps per second"),
    "memory": ("bench_memory", "peak memory of a fit (fresh process per size)"),
    "first_call": ("bench_first_call", "first fit in a fresh process: cached and cold "
                                       "numba compilation"),
    "lstm": ("bench_lstm", "LSTM baselines: training time per fold on LFE-sized data"),
    "lfe": ("bench_lfe", "the large-force-exercise domain end to end"),
    "reference": ("bench_reference", "the paper's model in webppl, side by side"),
}


def add_arguments(parser):
    """Options of the benchmark suite.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The parser to extend.

    Returns
    -------
    parser : argparse.ArgumentParser

    Examples
    --------
    >>> p = add_arguments(argparse.ArgumentParser())
    >>> args = p.parse_args(["--quick", "--only", "exact,predict"])
    >>> args.quick, args.only, args.out
    (True, 'exact,predict', None)
    """
    parser.add_argument("--quick", action="store_true",
                        help="shrink every size (about a minute; used by the tests); the "
                             "numbers are not the recorded ones")
    parser.add_argument("--only", default=None, metavar="NAME[,NAME...]",
                        help="run only these benchmarks (comma-separated; see --list)")
    parser.add_argument("--repeats", type=int, default=None,
                        help="timed calls per measurement, the median is reported "
                             "(default 7, --quick 2)")
    parser.add_argument("--out", default=None, metavar="DIR",
                        help="folder for RESULTS.md, results.json and figures/ "
                             "(default: the benchmarks/ folder itself)")
    parser.add_argument("--no-install", action="store_true",
                        help="never run `npm install` for the webppl reference "
                             "(implied by --quick)")
    parser.add_argument("--list", action="store_true", help="list the benchmarks and exit")
    parser.add_argument("--note", default=None, metavar="TEXT",
                        help="a paragraph for the header of RESULTS.md (e.g. the conditions "
                             "of the run)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    return parser


def build_parser():
    """The argument parser of ``python benchmarks/run.py``."""
    return add_arguments(argparse.ArgumentParser(
        prog="benchmarks/run.py", description="Run the bsi-sklearn benchmark suite."))


def parse_args(argv=None):
    """Parse the suite's options."""
    return build_parser().parse_args(argv)


def select(only):
    """Names to run, validated."""
    if not only:
        return list(BENCHMARKS)
    names = [n.strip() for n in only.split(",") if n.strip()]
    unknown = [n for n in names if n not in BENCHMARKS]
    if unknown:
        raise ValueError(f"unknown benchmark(s) {', '.join(unknown)}; choose among "
                         f"{', '.join(BENCHMARKS)}")
    return names


def _targets_table(sections):
    rows = []
    for sec in sections:
        for t in sec.data.get("targets", []):
            status = {True: "met", False: "**missed**", None: "n/a"}[t["ok"]]
            rows.append([t["name"], t["target"], t["measured"], status, sec.name])
    if not rows:
        return None
    return md_table(["target", "wanted", "measured", "status", "section"], rows)


def write_results(sections, info, cfg, total_s, argv_text, note=None):
    """RESULTS.md and results.json in ``cfg.out``."""
    lines = [
        "# bsi-sklearn benchmark results",
        "",
        f"Generated by `{argv_text}` on {info['date']} in {total_s:.0f} s"
        + (" (**--quick**: shrunk sizes, not the recorded numbers)" if cfg.quick else "")
        + f" on {info.get('usable_cores', '?')} cores ({info.get('cpu', 'unknown CPU')}).",
        "",
    ]
    if note:
        lines += [f"**Note.** {note}", ""]
    lines += [
        "## Machine",
        "",
        md_table(["", ""], [[k, v] for k, v in info.items() if k != "date"]),
        "",
        "Timings are medians over repeated calls after a warm-up call (numba kernels "
        "compiled or loaded from the on-disk cache); `wall` is elapsed time, `cpu` the "
        "process CPU time. The machine is shared: the load average above was taken when "
        "the run started.",
        "",
        "Recorded by their own commands, beside this file: "
        "[`RESULTS_lfe.md`](RESULTS_lfe.md) (`bsi-lfe compare`, the paper's table), "
        "[`RESULTS_reproduce.md`](RESULTS_reproduce.md) (`bsi reproduce synthetic|dinner`, "
        "the paper's claims), [`RESULTS_reference.md`](RESULTS_reference.md) "
        "(`benchmarks/bench_reference.py`, webppl side by side), "
        "[`RESULTS_external.md`](RESULTS_external.md) (`benchmarks/external.py`, "
        "samples2LTL / Scarlet benchmarks).",
        "",
    ]
    table = _targets_table(sections)
    if table:
        lines += ["## Targets (issues 2, 7 and 13)", "", table, ""]
    for sec in sections:
        lines += [f"## {sec.title}", ""]
        lines += [chunk.rstrip() + "\n" for chunk in sec.text]
        lines += [f"*({sec.name}: {sec.seconds:.0f} s)*", ""]
    history = HERE / "HISTORY.md"
    if history.is_file():
        lines += [history.read_text().rstrip(), ""]
    out = cfg.out
    out.mkdir(parents=True, exist_ok=True)
    (out / "RESULTS.md").write_text("\n".join(lines))
    payload = {"machine": info, "quick": cfg.quick, "total_seconds": total_s,
               "sections": {s.name: s.data for s in sections}}
    (out / "results.json").write_text(json.dumps(payload, indent=1, default=_jsonable))


def _jsonable(x):
    try:
        import numpy as np

        if isinstance(x, np.generic):
            return x.item()
        if isinstance(x, np.ndarray):
            return x.tolist()
    except ImportError:
        pass
    return str(x)


def _command_text(args, prog):
    """The command line that reproduces a run, for the header of RESULTS.md."""
    parts = [prog]
    if args.quick:
        parts.append("--quick")
    if args.only:
        parts.append(f"--only {args.only}")
    if args.repeats is not None:
        parts.append(f"--repeats {args.repeats}")
    if args.no_install:
        parts.append("--no-install")
    return " ".join(parts)


def _load(module_name):
    """The benchmark module, or None when its file is not there."""
    try:
        return importlib.import_module(module_name)
    except ModuleNotFoundError as exc:
        if exc.name == module_name:
            return None
        raise


def run_suite(args, prog="python benchmarks/run.py"):
    """Run the benchmarks selected by parsed ``args``; returns the exit status.

    The status is 1 when a benchmark raised (its section then says so), 0 otherwise.
    """
    from tqdm.auto import tqdm

    if args.list:
        for name, (module_name, desc) in BENCHMARKS.items():
            there = (HERE / f"{module_name}.py").is_file()
            print(f"{name:12s} {desc}" + ("" if there else f" [{module_name}.py missing]"))
        return 0
    names = select(args.only)
    cfg = Config(quick=args.quick)
    cfg.repeats = args.repeats if args.repeats is not None else (2 if args.quick else 7)
    if cfg.repeats < 1:
        raise ValueError(f"--repeats must be at least 1, got {cfg.repeats}")
    if args.out is not None:
        cfg.out = Path(args.out).resolve()
    cfg.install_webppl = not (args.no_install or args.quick)
    info = machine_info()
    t_all = time.perf_counter()
    sections, failed = [], []
    bar = tqdm(names, desc="benchmarks", unit="section", disable=args.quiet)
    for name in bar:
        module_name, desc = BENCHMARKS[name]
        bar.set_postfix_str(name)
        tqdm.write(f"[bench] {name}: {desc} ...")
        t0 = time.perf_counter()
        try:
            module = _load(module_name)
            if module is None:
                sec = Section(name, f"{name} (not run)")
                sec.add(f"Skipped: `benchmarks/{module_name}.py` is not in this checkout.")
                sec.data = {"skipped": True}
            else:
                sec = module.run(cfg)
        except Exception as exc:  # one broken benchmark must not hide the others
            failed.append(name)
            traceback.print_exc()
            sec = Section(name, f"{name} (failed)")
            sec.add(f"The benchmark raised `{type(exc).__name__}: {exc}`.")
            sec.data = {"failed": True}
        sec.seconds = time.perf_counter() - t0
        sections.append(sec)
        tqdm.write(f"[bench] {name}: {fmt_s(sec.seconds)}")
        for t in sec.data.get("targets", []):
            tqdm.write(f"    {t['name']}: {t['measured']} (wanted {t['target']})")
    bar.close()
    total = time.perf_counter() - t_all
    write_results(sections, info, cfg, total, _command_text(args, prog), args.note)
    print(f"[bench] wrote {cfg.out / 'RESULTS.md'} ({total:.0f} s)")
    if failed:
        print(f"[bench] failed: {', '.join(failed)}", file=sys.stderr)
    return 1 if failed else 0


def main(argv=None):
    """Entry point of ``python benchmarks/run.py``; returns the exit status.

    A bad option value (an unknown benchmark name, ``--repeats 0``) prints
    ``benchmarks/run.py: error: ...`` on stderr and gives status 2, as argparse does.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return run_suite(args)
    except ValueError as exc:
        print(f"{parser.prog}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
