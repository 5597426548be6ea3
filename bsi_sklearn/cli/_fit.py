"""``bsi fit FILE...``: fit BSI on trace files and print the MAP specification and posterior.

The parser needs nothing heavy: numpy, pandas and BSI are imported when the command runs, so
that ``bsi fit --help`` is quick.
"""

import argparse
import re
from numbers import Integral

from bsi_sklearn.cli._files import (
    add_format_argument,
    check_output_file,
    input_format,
    load_demonstrations,
    unique_stems,
)

__all__ = ["add_arguments", "run", "parse_conditions"]

# The choices of --prior and --likelihood, written here so that `bsi fit --help` need not load
# numba (tests/cli/test_cli_fit.py checks them against bsi_sklearn.model.priors.PRIORS and
# bsi_sklearn.model.likelihood.LIKELIHOODS).
PRIOR_CHOICES = ("linear_chain", "sets_of_chains", "forest")
LIKELIHOOD_CHOICES = ("cb", "ci", "calibrated")

_DESCRIPTION = """\
Fit BSI on each FILE (one model per file) and print the MAP specification, the training
accuracy and the most probable specifications.

Input files:
  *.trace  samples2LTL / Scarlet: positive traces, '---', negative traces, '---', operators
           [, '---', depth, '---', target | '---', alphabet]. One trace a line, time steps
           separated by ';', the 0/1 propositions of a step by ',' (e.g. 1,0;1,1); a
           lasso trace 1,0;1,1::1 (loop from step 1) is read as its steps, which is exact
           for the template's clauses.
  *.csv    long format, one row per time step of a demonstration:
             demo_id,t,<proposition>...[,label]
           demo_id names the demonstration, the optional t counts its steps 0,1,2,...
           (consecutive; without it the rows are the steps, in order), every other column
           is a 0/1 proposition, and the optional label (constant within a demonstration) is
           1 for acceptable, 0 for unacceptable (other labels: name the acceptable one with
           --pos-label); without it every demonstration is acceptable. Example:
             demo_id,t,safe,picked,placed,label
             0,0,1,0,0,1
             0,1,1,1,0,1
             0,2,1,1,1,1
  *.xes, *.xes.gz  an event log (XES, streamed): one case per trace, its events ordered by
           time:timestamp, one proposition per activity (concept:name), true from the step
           of its first occurrence on (step 0: nothing has happened yet), so F(a) reads
           "a occurs" and (!b U a) "a occurs before any b". The label of a case is the
           trace attribute named by --label (e.g. --label outcome --pos-label accepted), or
           comes from a CSV table --labels FILE (case id, label); without one, every case
           is acceptable.
  event-log CSV  one row per event, pm4py's columns case:concept:name, concept:name,
           time:timestamp (or name them with --case-id, --activity, --timestamp) and the
           label column (case:<label> or <label>, constant within a case). A .csv is read
           as an event log when its header has the case id column (or with --format
           event-log), otherwise as the long format above. Example:
             case:concept:name,concept:name,time:timestamp,case:ok
             c1,order,2024-01-01T10:00:00,1
             c1,ship,2024-01-02T09:00:00,1
The extension decides the format (any other is an error); --format reads every FILE as one.

Roles: by default (--roles infer) each role option not given is read from the
demonstrations: the global candidates are the propositions true at every step of some
acceptable demonstration, the subtasks those false at the first step and true later in some
demonstration, and a subtask's condition (if any) the proposition whose initial value best
separates the acceptable demonstrations that complete it from those that skip it
(docs/roles.md). With --roles all, every proposition is a global candidate and a subtask,
with no conditions (the paper's setting): the support is huge (exact inference still finishes
when the data are peaked) and the answer may hold clauses that every demonstration
satisfies, so they say nothing. Say which propositions play which role with --globals,
--subtasks and --conditions (names, or column indices counted from 0; give the FILEs first,
since --globals and --subtasks take every name that follows them, or end their list with
--); a role given is used as is. A bad file or option exits with status 2 and a message
naming the file, line or option."""

_EXAMPLE = """\
examples:
  bsi fit demos.csv --globals safe --subtasks picked placed --conditions placed=picked
  bsi fit log.xes --label outcome --pos-label accepted"""


def parse_conditions(tokens):
    """``["w=pi,w2=pi2", ...]`` -> ``{"w": "pi", "w2": "pi2"}`` (order kept).

    Parameters
    ----------
    tokens : list of str
        Pairs ``subtask=condition``, separated by commas or given as several tokens.

    Returns
    -------
    conditions : dict
        Subtask -> condition, both still names or index strings.

    Raises
    ------
    ValueError
        For a pair without ``=``, an empty side or a subtask given twice.

    Examples
    --------
    >>> parse_conditions(["placed=picked,2=0"])
    {'placed': 'picked', '2': '0'}
    >>> parse_conditions(["placed"])
    Traceback (most recent call last):
    ...
    ValueError: --conditions: 'placed' is not a pair subtask=condition (e.g. placed=picked)
    """
    out = {}
    for token in tokens:
        for pair in (p.strip() for p in token.split(",")):
            if not pair:
                continue
            w, eq, pi = (s.strip() for s in pair.partition("="))
            if not eq or not w or not pi:
                raise ValueError(f"--conditions: {pair!r} is not a pair subtask=condition "
                                 "(e.g. placed=picked)")
            if w in out:
                raise ValueError(f"--conditions: subtask {w!r} is given twice")
            out[w] = pi
    return out


def _conditions_type(text):
    try:
        parse_conditions([text])
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc).removeprefix("--conditions: ")) from None
    return text


_FILES_HINT = ("; --globals, --subtasks and --conditions take every word after them: give "
               "the FILEs first (bsi fit FILE... --globals ...), or end the option's list "
               "with --")


def _with_files_hint(error):
    """``parser.error`` that explains a FILE taken by a list option."""
    def report(message):
        if "required: FILE" in message:
            message += _FILES_HINT
        error(message)
    return report


def add_arguments(parser):
    """Arguments of ``bsi fit`` (and its description, with the input formats)."""
    parser.description = _DESCRIPTION
    parser.epilog = _EXAMPLE
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.error = _with_files_hint(parser.error)
    parser.add_argument("files", nargs="+", metavar="FILE",
                        help=".trace files (samples2LTL / Scarlet), long-format CSV files or "
                             "event logs (XES, event-log CSV)")
    parser.add_argument("--globals", nargs="*", metavar="PROP", default=None,
                        help="propositions that may be required to hold always, G(p) "
                             "(default: by --roles; give none for no G clauses)")
    parser.add_argument("--subtasks", nargs="*", metavar="PROP", default=None,
                        help="subtask-completion propositions, F(w) and ordering clauses "
                             "(default: by --roles; give none for no subtasks)")
    parser.add_argument("--conditions", nargs="+", metavar="W=PI", default=None,
                        type=_conditions_type,
                        help="condition of a subtask, read at t = 0: subtask=condition pairs "
                             "separated by commas or spaces (default: by --roles)")
    parser.add_argument("--roles", choices=["infer", "all"], default="infer",
                        help="what the role options not given become: read from the "
                             "demonstrations (infer) or every proposition in every role and "
                             "no conditions (all, the paper's setting) (default: %(default)s)")
    parser.add_argument("--prior", choices=PRIOR_CHOICES, default="sets_of_chains",
                        help="prior over the order of subtasks: one chain, sets of chains or "
                             "a forest (default: %(default)s)")
    parser.add_argument("--likelihood", choices=LIKELIHOOD_CHOICES, default="calibrated",
                        help="the size principle calibrated on the demonstrations "
                             "(calibrated), the paper's complexity-based likelihood (cb, the "
                             "size principle) or the complexity-independent one (ci) "
                             "(default: %(default)s)")
    for name, clauses in (("global", "G"), ("eventual", "F(w)")):
        parser.add_argument(f"--p-{name}", type=_inclusion, default=0.8, metavar="P",
                            help=f"prior inclusion probability of each {clauses} clause, or "
                                 "learned: unknown, uniform and integrated out, so that a "
                                 "clause the data do not ask for is left out "
                                 "(default: %(default)s)")
    parser.add_argument("--p-part", type=_inclusion, default=0.3, metavar="P",
                        help="with --prior sets_of_chains: probability of starting a new chain "
                             "after each subtask, or learned: unknown, uniform and integrated "
                             "out, so that an order the data do not ask for is left out "
                             "(default: %(default)s)")
    parser.add_argument("--flip-prior", nargs=2, type=float, default=None, metavar=("A", "B"),
                        help="with --likelihood ci or calibrated: the rate at which labels "
                             "are wrong is unknown, Beta(A, B) distributed on (0, 1/2) (mostly "
                             "right labels) and integrated out; prints its posterior mean and "
                             "interval")
    parser.add_argument("--inference", choices=["auto", "exact", "mcmc"], default="auto",
                        help="exact enumeration, MCMC, or auto: exact when the support is "
                             "small enough (default: %(default)s)")
    parser.add_argument("--n-samples", type=_n_samples, default="auto",
                        help="MCMC samples per chain, or auto: until the chains agree, at "
                             "most 10000 (default: %(default)s)")
    parser.add_argument("--top", type=int, default=5,
                        help="posterior entries to print (default: %(default)s)")
    parser.add_argument("--seed", type=int, default=0,
                        help="random seed of the MCMC chains (default: %(default)s)")
    parser.add_argument("--pos-label", default=None, metavar="LABEL",
                        help="the label of acceptable demonstrations, when the labels are "
                             "not 0/1 (e.g. --pos-label yes)")
    parser.add_argument("--label", default=None, metavar="ATTR",
                        help="event logs: the trace attribute holding each case's label "
                             "(XES case attribute; in CSV the column case:ATTR or ATTR)")
    parser.add_argument("--labels", default=None, metavar="CSV",
                        help="event logs: the labels as a CSV table (case id, label) instead "
                             "of --label")
    parser.add_argument("--case-id", default=None, metavar="COLUMN",
                        help="event logs: the case id column (default: case:concept:name)")
    parser.add_argument("--activity", default=None, metavar="COLUMN",
                        help="event logs: the activity column (default: concept:name)")
    parser.add_argument("--timestamp", default=None, metavar="COLUMN",
                        help="event logs: the timestamp column (default: time:timestamp; "
                             "without one, the file's order)")
    parser.add_argument("--templates", nargs="+", metavar="TEMPLATE", default=None,
                        help="pattern clauses beside the paper's template: a set (unary, "
                             "declare, all), catalogue names "
                             "(Response, Absence, AtMostOnce, ...) or LTLf formulas with "
                             "placeholders, quoted ('G(x -> F(y))'); default: none, the "
                             "paper's template (BSIClassifier(templates=...)). On an event "
                             "log, --encoding current reads them as Declare does")
    parser.add_argument("--encoding", choices=["occurred", "current"], default="occurred",
                        help="event logs: a proposition per activity, true once it has "
                             "occurred, or only at its own events (EventLogEncoder; default: "
                             "%(default)s)")
    parser.add_argument("--negations", action=argparse.BooleanOptionalAction, default=True,
                        help="event logs: also the negation !a of every activity, so that "
                             "G(!a) states absence(a), a never occurs (default: on)")
    parser.add_argument("--repeats", action="store_true",
                        help="event logs: also a<=1, 'a occurred at most once so far', for "
                             "every activity repeated in a case, so that G(a<=1) states "
                             "absence2(a), a occurs at most once (default: off)")
    add_format_argument(parser, event_logs=True)
    parser.add_argument("--save", default=None, metavar="JSON",
                        help="write the posterior as JSON (Posterior.to_json, written in one "
                             "step); with several FILEs, each one's name is added: "
                             "posterior_<stem>.json (with the folder too when two FILEs "
                             "share a name)")


def _word_or(word, cast, what):
    """An option's type: the keyword ``word`` or a ``cast`` value (its range checked later)."""
    def read(token):
        if token == word:
            return token
        try:
            return cast(token)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be '{word}' or {what}, got "
                                             f"{token!r}") from None
    return read


#: ``--n-samples``; ``--p-global``, ``--p-eventual``, ``--p-part``.
_n_samples = _word_or("auto", int, "an integer")
_inclusion = _word_or("learned", float, "a number in [0, 1]")


def _option_constraints():
    from bsi_sklearn.classifier import BSIClassifier
    from bsi_sklearn.param_validation import Interval

    return {
        "n_samples": BSIClassifier._parameter_constraints["n_samples"],
        "p_global": BSIClassifier._parameter_constraints["p_global"],
        "p_eventual": BSIClassifier._parameter_constraints["p_eventual"],
        "p_part": BSIClassifier._parameter_constraints["p_part"],
        "top": [Interval(Integral, 1, None, closed="left")],
        "seed": [Interval(Integral, 0, 2**32 - 1, closed="both")],
    }

_OPTION_OF = {"global_candidates": "--globals", "subtasks": "--subtasks",
              "conditions": "--conditions"}


def _pos_label(token, y):
    """``--pos-label`` as a value of the labels' type (an integer for integer labels)."""
    if token is None or y is None:
        return None
    import numpy as np

    values = np.unique(y).tolist()
    if token in values or not values:
        return token
    for cast in (int, float):
        try:
            value = cast(token)
        except ValueError:
            continue
        if value in values:
            return value
    raise ValueError(f"--pos-label {token!r} is not among the labels {values}")


def _outputs(args):
    """The posterior file of every input FILE (``None`` without ``--save``), checked."""
    if args.save is None:
        return [None] * len(args.files)
    out = check_output_file(args.save, "--save")
    if len(args.files) == 1:
        return [out]
    return [out.with_name(f"{out.stem}_{stem}{out.suffix}")
            for stem in unique_stems(args.files)]


def _save(posterior, out):
    """Write ``posterior`` to ``out`` in one step; the line that says so."""
    from bsi_sklearn.io.posterior_file import MAX_LISTED

    try:
        posterior.to_json(out)
    except OSError as exc:
        raise ValueError(f"--save {out}: cannot write ({exc.strerror or exc}); the previous "
                         "file, if any, is unchanged") from None
    line = f"saved      : {out}"
    if len(posterior) > MAX_LISTED:
        left = float(posterior.probabilities[MAX_LISTED:].sum())
        line += (f" (the {MAX_LISTED:,} most probable of {len(posterior):,} specifications; "
                 f"the others, {left:.3g} of the listed mass, as dropped_mass)")
    return line


def _proposition(token, names):
    """A name when it is one of ``names``, else a column index when it is an integer."""
    if token in names or not re.fullmatch(r"\d+", token):
        return token
    return int(token)


def _templates(names):
    """``--templates``: none is the paper's template, one set's name is that set."""
    from bsi_sklearn.specification.templates import TEMPLATE_SETS

    if not names:
        return "paper"
    return names[0] if len(names) == 1 and names[0] in TEMPLATE_SETS else names


def _roles(args, names, path):
    """The role options resolved against one file's propositions (as estimator parameters)."""
    from bsi_sklearn.data.roles import resolve_roles

    def props(tokens):
        return None if tokens is None else [_proposition(t, names) for t in tokens]

    conditions = None
    if args.conditions is not None:
        conditions = {_proposition(w, names): _proposition(pi, names)
                      for w, pi in parse_conditions(args.conditions).items()}
    roles = dict(global_candidates=props(args.globals), subtasks=props(args.subtasks),
                 conditions=conditions)
    try:
        resolve_roles(*roles.values(), len(names), names)
    except ValueError as exc:
        message = str(exc)
        for param, option in _OPTION_OF.items():
            if message.startswith(param):
                message = option + message[len(param):]
                break
        raise ValueError(f"{path}: {message}") from None
    return roles


def _event_log_options(args):
    """``read_event_log``'s keyword arguments from the event-log options."""
    return dict(label=args.label, labels=args.labels, pos_label=args.pos_label,
                case_id=args.case_id, activity=args.activity, timestamp=args.timestamp,
                encoder=dict(encoding=args.encoding, negations=args.negations,
                             repeats=args.repeats))


def _option_names(message):
    """The reader's parameter names as the command's options."""
    for param, option in ((r"\bpos_label=", "--pos-label "), (r"\bpos_label\b", "--pos-label"),
                          (r"(?<![-\w])labels=", "--labels"),
                          (r"(?<![-\w])label=", "--label"),
                          (r"(?<![-\w])case_id=", "--case-id"),
                          (r"(?<![-\w])activity=", "--activity")):
        message = re.sub(param, option, message)
    return message


def run(args):
    """Fit on every file (one model per file) and print the results."""
    import numpy as np

    from bsi_sklearn.classifier import BSIClassifier
    from bsi_sklearn.param_validation import check_options

    check_options(args, _option_constraints())
    if args.conditions is not None:
        parse_conditions(args.conditions)
    outputs = _outputs(args)
    event_log = _event_log_options(args)
    for path, out in zip(args.files, outputs):
        try:
            X, y, target, _ = load_demonstrations(path, args.format, event_log)
        except ValueError as exc:
            raise ValueError(_option_names(str(exc))) from None
        is_log = input_format(path, args.format, event_log) == "event-log"
        names = [str(c) for c in X[0].columns]
        if args.pos_label is not None and y is None:
            raise ValueError(f"{path}: --pos-label {args.pos_label!r} is given, but the file "
                             "has no labels (every demonstration is acceptable)")
        # An event log's labels are already 0/1 (the reader applied --pos-label).
        pos_label = None if is_log else _pos_label(args.pos_label, y)
        flip = None if args.flip_prior is None else tuple(args.flip_prior)
        clf = BSIClassifier(prior=args.prior, likelihood=args.likelihood, roles=args.roles,
                            flip_prior=flip, p_global=args.p_global,
                            p_eventual=args.p_eventual, p_part=args.p_part,
                            inference=args.inference,
                            n_samples=args.n_samples,
                            random_state=args.seed, pos_label=pos_label,
                            templates=_templates(args.templates),
                            **_roles(args, names, path))
        y = np.ones(len(X), dtype=int) if y is None else np.asarray(y)
        try:
            clf.fit(X, y)
        except ValueError as exc:
            message = re.sub(r"\bpos_label\b", "--pos-label", str(exc))
            message = re.sub(r"\bflip_prior\b", "--flip-prior", message)
            message = re.sub(r"\blikelihood='(\w+)'", r"--likelihood \1", message)
            message = re.sub(r"^templates: ", "--templates: ", message)
            raise ValueError(f"{path}: {message}") from None
        n_good = int((y == clf.classes_[1]).sum())
        print(f"== {path}: {len(X)} demonstrations ({n_good} acceptable), "
              f"{clf.n_features_in_} propositions, {clf.inference_} inference")
        if target is not None:
            print(f"target     : {target}")
        used = clf.roles_
        print(f"roles      : globals {' '.join(map(str, used['global_candidates'])) or '-'}; "
              f"subtasks {' '.join(map(str, used['subtasks'])) or '-'}; conditions "
              + (", ".join(f"{w}={c}" for w, c in used["conditions"].items()) or "-"))
        # Readable: orders as chains, clauses every demonstration satisfies set apart as
        # untested; the full formula beneath when it differs (and in the --save file).
        spec = clf.map_specification_
        # An event log's negated columns are the encoder's "!a" (none with --no-negations:
        # an activity named "!x" is then an atom); other inputs follow that naming.
        negations = None if not is_log else (
            {f"!{n}": n for n in names if f"!{n}" in names} if args.negations else {})
        readable = spec.readable(clf.vacuous_clauses_, negations=negations)
        print(f"MAP        : {readable}")
        if readable != spec.to_ltl():
            print(f"full MAP   : {spec.to_ltl()}")
        if is_log:  # the MAP's clauses as Declare constraints on the cases
            from bsi_sklearn.report.wording import describe_event_log_specification

            repeats = ({f"{n}<=1": n for n in names if f"{n}<=1" in names}
                       if args.repeats else {})
            for i, line in enumerate(describe_event_log_specification(
                    spec, clf.vacuous_clauses_, negations=negations, repeats=repeats)):
                print(f"{'reading    :' if i == 0 else '':<12} {line}")
        print(f"accuracy   : {clf.score(X, y):.3f} (training set)")
        if flip is not None:
            low, high = clf.flip_rate_interval_
            print(f"flip rate  : {clf.flip_rate_:.3f} [{low:.3f}, {high:.3f}] (posterior mean, "
                  "95 % interval)")
        frame = clf.posterior_.to_frame(k=args.top, negations=negations)[["probability",
                                                                          "readable"]]
        width = int(frame["readable"].str.len().max())
        print(frame.to_string(justify="left", formatters={
            "probability": "{:.4f}".format, "readable": f"{{:<{width}}}".format}))
        if out is not None:
            print(_save(clf.posterior_, out))
    return 0
