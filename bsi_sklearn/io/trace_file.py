"""The ``.trace`` files of samples2LTL / Scarlet: reading (errors name the line) and writing."""

from __future__ import annotations

import os
import re
from dataclasses import dataclass

import numpy as np
import pandas as pd

from bsi_sklearn.data.traces import check_traces
from bsi_sklearn.io._atomic import write_atomic
from bsi_sklearn.io._scarlet_formulas import scarlet_target
from bsi_sklearn.ltl import Formula, parse_ltl

__all__ = ["TraceFile", "read_trace_file", "load_trace_file", "write_trace_file"]

_SEPARATOR = "---"
_DEFAULT_OPERATORS = ("G", "F", "!", "U", "&", "|", "->", "X")


@dataclass(frozen=True, eq=False)
class TraceFile:
    """Everything a ``.trace`` file holds.

    Attributes
    ----------
    positives, negatives : list of ndarray of shape (T_i, n_props), dtype bool
        Traces in file order.
    feature_names : list of str
        Proposition names: the alphabet when the file has one (Scarlet), else
        ``x0, x1, ...`` (the names samples2LTL targets use).
    operators : tuple of str
        Operators the learner may use (the file's operator line).
    depth : int or None
        Depth of the target formula (samples2LTL files).
    alphabet : tuple of str or None
        The alphabet line (Scarlet files).
    target : Formula or None
        The target formula: the file's own (samples2LTL), or for a Scarlet benchmark file
        ``f-NN-...`` line ``NN`` of the ``formulas.txt`` beside it.
    target_source : str or None
        Where the target came from: ``"file"`` or ``"<formulas.txt path>:<line>"``.
    path : str or None
        The file read.
    loop_starts : tuple
        For every trace of :attr:`X` (positives, then negatives), the step where its loop
        starts for a samples2LTL lasso trace ``steps::k``, else None. A lasso ``u v``
        (``v`` from step ``k`` on, repeated forever) is read as its listed steps, ``u`` then
        one copy of ``v``: every clause of the BSI template has the same truth value on both
        (``G p`` and ``F p`` see the same states, and the first ``w_a`` with any ``w_b``
        before it lies within ``u v``). A general formula, such as a file's target, may not.
    lengths : tuple of int or None
        The trace lengths a Scarlet benchmark was generated with (its ``formulas.txt`` line).
    target_alphabet : tuple of str or None
        The target's alphabet as its ``formulas.txt`` line gives it. Scarlet's benchmarks
        publish it as the letters the formula is over, which may be fewer than the file's
        (``a,b,c`` for traces over ``a,b,c,d``); :attr:`feature_names` stay the file's.
    """

    positives: list
    negatives: list
    feature_names: list
    operators: tuple = _DEFAULT_OPERATORS
    depth: int | None = None
    alphabet: tuple | None = None
    target: Formula | None = None
    target_source: str | None = None
    path: str | None = None
    loop_starts: tuple = ()
    lengths: tuple | None = None
    target_alphabet: tuple | None = None

    @property
    def n_props(self):
        """Number of propositions per step."""
        return len(self.feature_names)

    @property
    def X(self):
        """Positives then negatives, as DataFrames with :attr:`feature_names` columns."""
        columns = pd.Index(list(self.feature_names))
        return [pd.DataFrame(t, columns=columns) for t in (*self.positives, *self.negatives)]

    @property
    def y(self):
        """Labels of :attr:`X`: 1 for positives, 0 for negatives."""
        return np.r_[np.ones(len(self.positives), dtype=np.int64),
                     np.zeros(len(self.negatives), dtype=np.int64)]


class _Lines:
    """Lines of a text file with 1-based numbers, for error messages."""

    def __init__(self, text, name):
        self.name = name
        self.lines = text.split("\n")
        if self.lines and self.lines[-1] == "":
            self.lines.pop()  # a final newline ends the last line
        self.lines = [line.rstrip("\r") for line in self.lines]

    def error(self, lineno, message):
        return ValueError(f"{self.name}, line {lineno}: {message}")


def _split_sections(lines):
    """Sections between ``---`` lines as lists of (1-based line number, text).

    Also returns, per section, the line to blame when it is empty: the ``---`` line that
    closes it, or for the last section the ``---`` line that opens it.
    """
    sections, current, blame = [], [], []
    opened = 1
    for k, line in enumerate(lines.lines, start=1):
        if line.strip() == _SEPARATOR:
            sections.append(current)
            blame.append(k)
            current, opened = [], k
        else:
            current.append((k, line))
    sections.append(current)
    blame.append(opened)
    return sections, blame


_EXPECTED = ("expected time steps separated by ';' and the 0/1 propositions of a step by ',' "
             "(e.g. '1,0;1,1')")


def _check_separators(lines, lineno, stripped):
    """Raise when a trace line that does not parse uses separators other than ',' and ';'."""
    odd = sorted(set(stripped) - set("01,; \t"))
    if odd:
        shown = stripped if len(stripped) <= 40 else stripped[:37] + "..."
        raise lines.error(lineno, f"{shown!r} is not a trace: unexpected character(s) "
                                  f"{''.join(odd)!r}; {_EXPECTED}")
    spaced = re.search(r"[01][ \t]+[01]", stripped)
    if spaced:
        raise lines.error(lineno, f"values separated by whitespace ({spaced.group()!r}); "
                                  f"{_EXPECTED}")


_WELL_FORMED = re.compile(r"[01](?:,[01])*(?:;[01](?:,[01])*)*")


def _parse_lasso(lines, lineno, text, n_props):
    """One trace line, finite or a lasso ``steps::k`` -> (bool array, n_props, k or None)."""
    steps, sep, start = text.strip().partition("::")
    if not sep:
        return (*_parse_trace(lines, lineno, steps, n_props), None)
    if "::" in start:
        raise lines.error(lineno, "a second '::' in a lasso trace 'steps::start'")
    arr, n_props = _parse_trace(lines, lineno, steps, n_props)
    if not re.fullmatch(r"\d+", start.strip()) or not int(start) < len(arr):
        raise lines.error(lineno, f"the lasso start {start.strip()!r} after '::' must be a "
                                  f"step of the trace, 0 to {len(arr) - 1}")
    return arr, n_props, int(start)


def _parse_trace(lines, lineno, text, n_props):
    """One finite trace line ``0,1;1,1;...`` -> bool array (T, n_props)."""
    stripped = text.strip()
    if _WELL_FORMED.fullmatch(stripped):
        # Fast path: every other byte is a 0/1 digit; steps must all have n_props values.
        n_steps = stripped.count(";") + 1
        digits = np.frombuffer(stripped.encode("ascii"), dtype=np.uint8)[::2]
        width = n_props if n_props is not None else stripped.index(";") // 2 + 1 if (
            n_steps > 1) else len(digits)
        if len(digits) == n_steps * width and all(
            len(step) == 2 * width - 1 for step in stripped.split(";")
        ):
            return (digits == ord("1")).reshape(n_steps, width), width
    if not stripped:
        raise lines.error(lineno, "empty trace (a trace needs at least one time step)")
    steps = stripped.split(";")
    rows = []
    for s, step in enumerate(steps):
        values = step.split(",")
        if step.strip() == "":
            raise lines.error(lineno, f"time step {s} is empty (two ';' in a row or a "
                                      "trailing ';')")
        if n_props is None:
            n_props = len(values)
        elif len(values) != n_props:
            _check_separators(lines, lineno, stripped)
            raise lines.error(lineno, f"time step {s} has {len(values)} propositions, "
                                      f"expected {n_props}")
        row = []
        for p, v in enumerate(values):
            v = v.strip()
            if v not in ("0", "1"):
                if len(v) > 1:
                    _check_separators(lines, lineno, stripped)
                raise lines.error(lineno, f"time step {s}, proposition {p} has value {v!r}; "
                                          "values must be 0 or 1")
            row.append(v == "1")
        rows.append(row)
    return np.array(rows, dtype=bool), n_props


def _one_line(lines, section, what, blame):
    content = [(k, t) for k, t in section if t.strip()]
    if len(content) != 1:
        k = content[1][0] if len(content) > 1 else blame
        raise lines.error(k, f"the {what} section must hold exactly one line, found "
                             f"{len(content)}")
    return content[0]


def read_trace_file(path, *, formulas="auto"):
    r"""Read a ``.trace`` file of samples2LTL / Scarlet with everything it holds.

    The format: positive traces, ``---``, negative traces, ``---``, the operator line, then
    either (samples2LTL) ``---``, the formula depth, ``---``, the target formula in prefix
    notation, or (Scarlet) ``---``, the alphabet. One trace a line, time steps separated by
    ``;``, the 0/1 propositions of a step by ``,``. A final newline and Windows line ends
    are accepted.

    Parameters
    ----------
    path : str or path-like
        The file.
    formulas : "auto", path or None, default="auto"
        Where a Scarlet benchmark file ``f-NN-...`` without its own target finds it: line
        ``NN`` of this file. ``"auto"`` looks for ``formulas.txt`` in the file's folder and
        the folder above (the layout of Scarlet's benchmarks); ``None`` reads no target
        from outside the file. A ``formulas.txt`` line may give the target's alphabet as
        published: the letters the formula is over, which may be a subset of the file's
        (recorded as :attr:`TraceFile.target_alphabet`; the columns keep the file's names).

    Returns
    -------
    trace_file : TraceFile

    Raises
    ------
    ValueError
        For a malformed file (missing separators, uneven proposition counts, values other
        than 0/1, empty traces, a bad depth, target or alphabet), naming the file and the
        1-based line; for a target whose ``formulas.txt`` alphabet has a letter the file's
        alphabet does not, naming both files, the line and the letters.

    See Also
    --------
    load_trace_file : The same, as ``(X, y, target)``.
    write_trace_file : The inverse.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> text = "1,0;1,1\n1,1\n---\n0,1;0,0\n---\nG,F,!,&\n---\n1\n---\nG(x0)\n"
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     path = pathlib.Path(tmp) / "demo.trace"
    ...     _ = path.write_text(text)
    ...     tf = read_trace_file(path)
    >>> tf.feature_names, tf.depth, str(tf.target)
    (['x0', 'x1'], 1, 'G(x0)')
    >>> [t.shape for t in tf.positives], len(tf.negatives)
    ([(2, 2), (1, 2)], 1)
    """
    path = os.fspath(path)
    with open(path, encoding="utf-8") as fh:
        text = fh.read()
    return _parse_trace_text(text, path, formulas=formulas)


def _parse_trace_text(text, path, formulas="auto"):
    name = str(path) if path is not None else "<trace text>"
    lines = _Lines(text, name)
    sections, blame = _split_sections(lines)
    if len(sections) < 3:
        last = len(lines.lines)
        raise lines.error(max(last, 1), f"missing '---' separator: found {len(sections) - 1}, "
                                        "expected at least 2 (positives --- negatives --- "
                                        "operators)")
    if len(sections) > 6:
        raise lines.error(blame[5], "too many '---' separators (at most 5: positives, "
                                    "negatives, operators, depth, target, alphabet)")
    n_props = None
    traces, loops = [], []
    for section in sections[:2]:
        parsed = []
        for lineno, t in section:
            arr, n_props, loop = _parse_lasso(lines, lineno, t, n_props)
            parsed.append(arr)
            loops.append(loop)
        traces.append(parsed)
    if n_props is None:
        raise ValueError(f"{name}: the file holds no traces (positives and negatives are "
                         "both empty)")
    _, op_line = _one_line(lines, sections[2], "operators", blame[2])
    operators = tuple(o.strip() for o in op_line.split(",") if o.strip())

    depth = alphabet = target = source = None
    rest = sections[3:]
    if rest:
        lineno, first = _one_line(lines, rest[0], "depth or alphabet", blame[3])
        if first.strip().lstrip("-").isdigit():
            depth = int(first)
            if depth < 0:
                raise lines.error(lineno, f"depth must be >= 0, got {depth}")
            if len(rest) > 1:
                lineno, formula = _one_line(lines, rest[1], "target formula", blame[4])
                try:
                    target = parse_ltl(formula.strip(), notation="prefix")
                except ValueError as exc:
                    raise lines.error(lineno, f"target formula: {exc}") from None
                source = "file"
                target_line = lineno
            alphabet_section = (rest[2], blame[5]) if len(rest) > 2 else None
        else:
            if len(rest) > 1:
                raise lines.error(blame[3], "unexpected section after the alphabet")
            alphabet_section = (rest[0], blame[3])
        if alphabet_section is not None:
            section, at = alphabet_section
            lineno, line = _one_line(lines, section, "alphabet", at)
            alphabet = tuple(a.strip() for a in line.split(","))
            if any(not a for a in alphabet) or len(set(alphabet)) != len(alphabet):
                raise lines.error(lineno, f"alphabet {line!r} has empty or repeated names")
            if len(alphabet) != n_props:
                raise lines.error(lineno, f"the alphabet has {len(alphabet)} names but the "
                                          f"traces have {n_props} propositions")
    feature_names = list(alphabet) if alphabet is not None else [f"x{i}" for i in range(n_props)]
    if target is not None:
        unknown = sorted(target.atoms - set(feature_names))
        if unknown:
            raise lines.error(target_line, f"the target mentions {unknown}, which are not "
                                           f"among the propositions {feature_names}")
    lengths = target_alphabet = None
    if target is None:
        found = scarlet_target(path, formulas)
        if found is not None:
            target, source, lengths = found.formula, found.source, found.lengths
            target_alphabet = found.alphabet
            feature_names = _names_from_formulas(name, found, alphabet, feature_names)
            unknown = sorted(target.atoms - set(feature_names))
            if unknown:
                raise ValueError(f"{name}: the target {source} mentions {unknown}, which are "
                                 f"not among the propositions {feature_names}")
    return TraceFile(positives=traces[0], negatives=traces[1], feature_names=feature_names,
                     operators=operators, depth=depth, alphabet=alphabet, target=target,
                     target_source=source, path=None if path is None else str(path),
                     loop_starts=tuple(loops), lengths=lengths,
                     target_alphabet=target_alphabet)


def _names_from_formulas(name, found, alphabet, feature_names):
    """The propositions' names given what ``formulas.txt`` says of the target's alphabet.

    The file's own alphabet line names its columns; the ``formulas.txt`` alphabet is the
    formula's, and Scarlet publishes it as a subset (``a,b,c`` over traces ``a,b,c,d``), in
    any order. Without an alphabet line the ``formulas.txt`` one names the columns, and must
    then have one letter per column: which columns a shorter one meant is not written down.
    """
    if found.alphabet is None:
        return feature_names
    if alphabet is None:
        if len(found.alphabet) != len(feature_names):
            raise ValueError(f"{name}: {found.source} names {len(found.alphabet)} "
                             f"propositions {list(found.alphabet)}, but the traces have "
                             f"{len(feature_names)} and the file has no alphabet line to "
                             "name them")
        return list(found.alphabet)
    missing = [a for a in found.alphabet if a not in alphabet]
    if missing:
        raise ValueError(f"{name}: the target's alphabet {list(found.alphabet)} on "
                         f"{found.source} has {missing}, which the file's alphabet "
                         f"{list(alphabet)} does not carry")
    return feature_names


def load_trace_file(path, *, formulas="auto"):
    r"""Load a samples2LTL / Scarlet ``.trace`` file as ``(X, y, target)``.

    Parameters
    ----------
    path : str or path-like
        The file (format in :func:`read_trace_file`).
    formulas : "auto", path or None, default="auto"
        Where a Scarlet benchmark file finds its target (see :func:`read_trace_file`).

    Returns
    -------
    X : list of DataFrame of shape (T_i, n_props)
        Positives then negatives; boolean columns ``x0, x1, ...`` or the file's alphabet.
    y : ndarray of shape (n_demos,), dtype int64
        1 for positives, 0 for negatives.
    target : Formula or None
        The target formula, when known.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> text = "1,0;1,1\n---\n0,1\n---\nG,F,!,&\n---\n1\n---\nG(x0)"
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     path = pathlib.Path(tmp) / "demo.trace"
    ...     _ = path.write_text(text)
    ...     X, y, target = load_trace_file(path)
    >>> y
    array([1, 0])
    >>> target.evaluate(X)
    array([ True, False])
    """
    tf = read_trace_file(path, formulas=formulas)
    return tf.X, tf.y, tf.target


def _formula_text(target):
    if target is None:
        return None
    if isinstance(target, Formula):
        return target.to_prefix()
    if isinstance(target, str):
        return parse_ltl(target).to_prefix()
    raise ValueError(f"target must be a Formula, a string or None, got {type(target).__name__}")


def write_trace_file(path, X, y, *, operators=_DEFAULT_OPERATORS, depth=None, target=None,
                     alphabet=None):
    """Write traces in the ``.trace`` format (the inverse of :func:`read_trace_file`).

    Parameters
    ----------
    path : str, path-like or file-like
        Destination (a writable text buffer is accepted).
    X : demonstrations
        Any format accepted by :func:`bsi_sklearn.data.traces.check_traces`.
    y : array-like of shape (n_demos,)
        1 (or True) for positives, 0 for negatives.
    operators : sequence of str, default=("G", "F", "!", "U", "&", "|", "->", "X")
        The operator line.
    depth : int, default=None
        Written (samples2LTL layout) when given or when a target is given (then
        ``target.depth`` by default).
    target : Formula or str, default=None
        Written in prefix notation (samples2LTL layout).
    alphabet : sequence of str, default=None
        Written last (Scarlet layout, or after the target).

    Examples
    --------
    >>> import io, numpy as np
    >>> buf = io.StringIO()
    >>> write_trace_file(buf, [np.array([[1, 0], [1, 1]]), np.array([[0, 1]])], [1, 0],
    ...                  target="G(x0)")
    >>> print(buf.getvalue(), end="")
    1,0;1,1
    ---
    0,1
    ---
    G,F,!,U,&,|,->,X
    ---
    1
    ---
    G(x0)
    """
    traces = check_traces(X, estimator_name="write_trace_file")
    y = np.asarray(y)
    if y.shape != (traces.n_demos,):
        raise ValueError(f"y must hold one label per demonstration ({traces.n_demos}), "
                         f"got shape {y.shape}")
    if not np.isin(y, (0, 1)).all():
        raise ValueError("y must be 0/1 (or booleans)")
    target_text = _formula_text(target)
    if target_text is not None and depth is None:
        depth = parse_ltl(target_text).depth
    blocks = [[], []]
    for i in range(traces.n_demos):
        tr = traces.trace(i).astype(np.uint8)
        blocks[0 if y[i] else 1].append(";".join(",".join(map(str, row)) for row in tr))
    parts = ["\n".join(blocks[0]), "\n".join(blocks[1]), ",".join(operators)]
    if depth is not None:
        parts.append(str(int(depth)))
        if target_text is not None:
            parts.append(target_text)
    if alphabet is not None:
        alphabet = [str(a) for a in alphabet]
        if len(alphabet) != traces.n_props:
            raise ValueError(f"alphabet has {len(alphabet)} names for {traces.n_props} "
                             "propositions")
        parts.append(",".join(alphabet))
    text = ""
    for k, part in enumerate(parts):
        text += (part + "\n" if part else "") + (f"{_SEPARATOR}\n" if k < len(parts) - 1 else "")
    if hasattr(path, "write"):
        path.write(text)
    else:
        write_atomic(os.fspath(path), text)
