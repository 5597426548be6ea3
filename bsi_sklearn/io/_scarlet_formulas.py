"""The ``formulas.txt`` of Scarlet's benchmark folders: the target of a file ``f-NN-...``.

Line ``NN`` of ``formulas.txt`` holds the target formula, alone (``F(&(a,F(b)))``) or with
the alphabet and the trace lengths the benchmark was generated with, separated by ``;``
(``G(!(p));p,q;8,10,12``, the layout of Scarlet's RQ1 benchmarks).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from bsi_sklearn.ltl import Formula, parse_ltl

__all__ = ["ScarletTarget", "scarlet_target"]

_SCARLET_NAME = re.compile(r"^f-(\d+)-")


@dataclass(frozen=True)
class ScarletTarget:
    """One line of ``formulas.txt``.

    Attributes
    ----------
    formula : Formula
    source : str
        ``"<formulas.txt path>:<line>"``.
    alphabet : tuple of str or None
        The proposition names, when the line gives them.
    lengths : tuple of int or None
        The trace lengths of the benchmark, when the line gives them.
    """

    formula: Formula
    source: str
    alphabet: tuple | None = None
    lengths: tuple | None = None


def _error(formulas, number, message):
    return ValueError(f"{formulas}, line {number}: {message}")


def _parse_line(line, formulas, number):
    fields = [f.strip() for f in line.split(";")]
    if len(fields) > 3:
        raise _error(formulas, number, f"expected 'formula[;alphabet[;lengths]]', found "
                                       f"{len(fields)} fields separated by ';'")
    try:
        formula = parse_ltl(fields[0])
    except ValueError as exc:
        raise _error(formulas, number, f"target formula: {exc}") from None
    alphabet = lengths = None
    if len(fields) > 1:
        alphabet = tuple(a.strip() for a in fields[1].split(","))
        if any(not a for a in alphabet) or len(set(alphabet)) != len(alphabet):
            raise _error(formulas, number, f"alphabet {fields[1]!r} has empty or repeated "
                                           "names")
        unknown = sorted(formula.atoms - set(alphabet))
        if unknown:
            raise _error(formulas, number, f"the formula mentions {unknown}, which are not in "
                                           f"its alphabet {list(alphabet)}")
    if len(fields) > 2:
        items = [x.strip() for x in fields[2].split(",")]
        if not all(re.fullmatch(r"\d+", x) and int(x) > 0 for x in items):
            raise _error(formulas, number, f"trace lengths {fields[2]!r} are not positive "
                                           "integers separated by ','")
        lengths = tuple(int(x) for x in items)
    return formula, alphabet, lengths


def scarlet_target(path, formulas):
    """The target of the Scarlet benchmark file ``path`` (``f-NN-...``), or None.

    Parameters
    ----------
    path : str or None
        The ``.trace`` file.
    formulas : "auto", path or None
        ``"auto"``: ``formulas.txt`` in the file's folder or the one above, when the name
        starts with ``f-NN-``; a path: that file (the name must start with ``f-NN-``);
        ``None``: no target.

    Returns
    -------
    target : ScarletTarget or None

    Raises
    ------
    ValueError
        Naming the formulas file and line: no such line, a bad formula, alphabet or lengths.
    """
    if formulas is None or path is None:
        return None
    match = _SCARLET_NAME.match(Path(path).name)
    if formulas == "auto":
        if match is None:
            return None
        here = Path(path).resolve().parent
        found = [c for c in (here / "formulas.txt", here.parent / "formulas.txt")
                 if c.is_file()]
        if not found:
            return None
        formulas = found[0]
    elif match is None:
        raise ValueError(f"{path}: formulas was given, but the file name does not start with "
                         "'f-NN-' (NN is the line of the target in the formulas file)")
    number = int(match.group(1))
    lines = Path(formulas).read_text(encoding="utf-8").splitlines()
    if not 1 <= number <= len(lines):
        raise ValueError(f"{path}: the target is line {number} of {formulas}, which has "
                         f"{len(lines)} lines")
    formula, alphabet, lengths = _parse_line(lines[number - 1], formulas, number)
    return ScarletTarget(formula, f"{formulas}:{number}", alphabet, lengths)
