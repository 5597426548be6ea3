"""``bsi-lfe study``'s arguments, in a module that imports nothing heavy.

``bsi-lfe study --help`` builds its parser from here without loading the study (pandas,
scikit-learn, torch); :func:`run` imports :mod:`lfe.study` when the command runs. The
defaults it shows are :mod:`lfe._settings`'s, which :mod:`lfe.study` reads too.
"""

from lfe._settings import STUDY_DEFAULTS, STUDY_QUICK

__all__ = ["add_arguments", "run"]


def add_arguments(parser):
    """Arguments of ``bsi-lfe study``."""
    d, q = STUDY_DEFAULTS, STUDY_QUICK

    def listed(values):
        return ",".join(f"{v:g}" if isinstance(v, float) else str(v) for v in values)

    parser.add_argument("--sizes", type=str, default=None, metavar="N,N,...",
                        help=f"training sizes (default: {listed(d['sizes'])}; "
                             f"--quick: {listed(q['sizes'])})")
    parser.add_argument("--repeats", type=int, default=None,
                        help=f"independent simulated datasets (default: {d['repeats']}; "
                             f"--quick: {q['repeats']})")
    parser.add_argument("--test-size", type=int, default=None,
                        help=f"fresh test missions per repeat (default: {d['test_size']}; "
                             f"--quick: {q['test_size']})")
    parser.add_argument("--noise", type=str, default=None, metavar="P,P,...",
                        help="label-noise rates, each verdict flipped with this probability "
                             f"(default: {listed(d['noise'])}; --quick: {listed(q['noise'])})")
    parser.add_argument("--propositions", type=str, default=None, metavar="SET,...",
                        help=f"proposition sets (default: {listed(d['propositions'])}; "
                             f"--quick: {listed(q['propositions'])})")
    parser.add_argument("--n-jobs", type=int, default=None,
                        help="parallel workers (default: 1; -1: every core); the files do not "
                             "depend on it")
    parser.add_argument("--seed", type=int, default=0,
                        help="root of every seed (default: 0)")
    parser.add_argument("--out", default="study", metavar="DIR",
                        help="output directory; a rerun with the same arguments resumes "
                             "(default: study)")
    parser.add_argument("--quick", action="store_true",
                        help="small sizes, networks and MCMC runs: a smoke test, not a result")
    parser.add_argument("--verbose", type=int, default=1, help="0: no progress bar")


def run(args):
    """Run the study (:func:`lfe.study.run`)."""
    from lfe import study

    return study.run(args)
