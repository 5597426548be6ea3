"""``bsi monitor POSTERIOR FILE...``: replay demonstrations against a saved posterior.

For every demonstration of every file (``.trace`` or long-format CSV), the posterior
(:meth:`Posterior.to_json`, e.g. from ``bsi fit ... --save``) monitors it step by step; the
verdicts go to ``<file>_<demo>_monitor.csv`` and their plot, with the clause events marked, to
``<file>_<demo>_monitor.png`` in ``--out``. ``<file>`` is the input's stem (with its folders
when two inputs share a name), ``<demo>`` the demonstration's ``demo_id`` (CSV) or position
(``.trace``), made file-safe and unique.
"""

import io as _io

from bsi_sklearn.cli._files import (
    add_format_argument,
    check_input,
    check_output_dir,
    load_demonstrations,
    unique_names,
    unique_stems,
)

__all__ = ["add_arguments", "run"]


def add_arguments(parser):
    """Arguments of ``bsi monitor``."""
    parser.add_argument("posterior", metavar="POSTERIOR",
                        help="a posterior saved as JSON (bsi fit ... --save POSTERIOR)")
    parser.add_argument("files", nargs="+", metavar="FILE",
                        help=".trace files or long-format CSV files of demonstrations")
    parser.add_argument("--out", default="bsi_monitor", metavar="DIR",
                        help="folder for the tables and plots (default: ./bsi_monitor)")
    parser.add_argument("--no-plot", action="store_true", help="write the tables only")
    add_format_argument(parser)


def _check_propositions(posterior, X, path, posterior_path):
    """The file's propositions must be the posterior's (by name, or by number)."""
    from bsi_sklearn.data.values import names_difference

    names = posterior.feature_names_in_
    given = list(X[0].columns)
    if names is not None and given != list(names):
        expected, got = [str(n) for n in names], [str(n) for n in given]
        difference = names_difference(expected, got, "proposition", "the file", "the posterior")
        raise ValueError(f"{path}: its propositions {got} are not those of the posterior "
                         f"{posterior_path} {expected}: {difference} (a posterior of another "
                         "task?)")
    if names is None and len(given) != len(posterior.roles.names):
        raise ValueError(f"{path}: {len(given)} propositions, but the posterior "
                         f"{posterior_path} is over {len(posterior.roles.names)}")


def run(args):
    """Monitor every demonstration and write its table and plot; prints one line each.

    Every input is read and monitored before anything is written, and the outputs are
    written all or none (:func:`~bsi_sklearn.io.write_files_atomic`): a bad input or a failed
    write (read-only folder, full disk) leaves ``--out`` as it was.
    """
    import numpy as np

    from bsi_sklearn.io import write_files_atomic
    from bsi_sklearn.monitor.figure import monitor_frame, plot_monitor
    from bsi_sklearn.posterior import Posterior

    check_input(args.posterior)
    posterior = Posterior.read_json(args.posterior)
    stems = unique_stems(args.files)
    out = check_output_dir(args.out, "--out")
    files, lines = {}, []
    for path, stem in zip(args.files, stems):
        X, _, _, ids = load_demonstrations(path, args.format)
        _check_propositions(posterior, X, path, args.posterior)
        for demo, trace, name in zip(ids, X, unique_names(ids)):
            if posterior.feature_names_in_ is None:
                trace = np.asarray(trace)
            try:
                frame = monitor_frame(posterior, trace)
            except ValueError as exc:
                raise ValueError(f"{path}, demonstration {demo!r}: {exc}") from None
            base = out / f"{stem}_{name}_monitor"
            files[base.with_suffix(".csv")] = frame.to_csv(index=False)
            if not args.no_plot:
                ax = plot_monitor(frame, title=f"{path}, demonstration {demo}")
                png = _io.BytesIO()
                ax.figure.savefig(png, format="png", dpi=90)
                files[base.with_suffix(".png")] = png.getvalue()
            end = frame.iloc[-1]
            first = frame.loc[frame["p_violated"] >= 0.5, "step"]
            lines.append(f"{path} [{demo}]: {len(frame) - 1} steps, P(satisfied) at the end "
                         f"{end['p_satisfied']:.3f}"
                         + (f", mostly violated from step {int(first.iloc[0])}"
                            if len(first) else "")
                         + f" -> {base.name}.csv")
    write_files_atomic(files)
    for line in lines:
        print(line)
    return 0

