"""Declarative parameter validation: constraint objects and the checks built from them.

Estimators declare ``_parameter_constraints = {"name": [constraint, ...]}`` as scikit-learn's
do, and call :func:`validate_params` first in ``fit``; plain functions and command lines use
the same constraints (:func:`validate_params`, :func:`check_options`, :func:`option_type`). A
value is valid when it satisfies at least one constraint of its list. scikit-learn's own
``sklearn.utils._param_validation`` is private and changes between releases; this module has
the same shape and is public.

A constraint is one of

- ``None``: the value is ``None``;
- a type (``dict``, ``str``, :class:`~bsi_sklearn.Specification`, ``numbers.Integral``,
  ``numbers.Real``...): an instance of it; booleans are never integers or reals here;
- ``"boolean"``: ``bool`` or ``numpy.bool_``;
- ``"random_state"``: what :func:`sklearn.utils.check_random_state` accepts (``None``, an
  integer in ``[0, 2**32 - 1]``, a ``numpy.random.RandomState``);
- ``callable``: a callable;
- :class:`Interval`: an integer or a real number in a range; NaN never passes, and infinity
  passes only a bound written as ``math.inf`` and closed on that side;
- :class:`StrOptions` / :class:`Options`: one of a few values;
- :class:`Satisfies`: any predicate, with the words that describe it.

The error, :class:`InvalidParameterError` (a ``ValueError`` and a ``TypeError``), names the
caller, the parameter and what is allowed::

    BSIClassifier: p_part must be a number in [0.0, 1.0], got 1.5
"""

from __future__ import annotations

import argparse
import math
import numbers
from collections.abc import Mapping

import numpy as np

__all__ = ["NONZERO_INTEGER", "Interval", "InvalidParameterError", "Options", "Satisfies",
           "StrOptions", "check_options", "describe", "option_type", "is_satisfied",
           "validate_params"]

_CLOSED = ("left", "right", "both", "neither")


class InvalidParameterError(ValueError, TypeError):
    """A parameter value outside its declared constraints.

    Both a ``ValueError`` and a ``TypeError``, like scikit-learn's, so callers catching
    either keep working.

    Attributes
    ----------
    parameter : str
        The parameter's name (``"--option"`` for a command-line option).
    value : object
        The value given.
    caller : str or None
        The estimator, function or command the parameter belongs to.
    """

    def __init__(self, message, *, parameter=None, value=None, caller=None):
        super().__init__(message)
        self.parameter = parameter
        self.value = value
        self.caller = caller


def _is_bool(value):
    return isinstance(value, (bool, np.bool_))


def _format_bound(x):
    if x == math.inf:
        return "inf"
    if x == -math.inf:
        return "-inf"
    return str(x)


def _article(words):
    return "an" if words[:1] and words[0].lower() in "aeiou" else "a"


class Interval:
    """Integers or real numbers in a range.

    Parameters
    ----------
    type : {numbers.Integral, numbers.Real}
        ``Integral`` accepts integers (Python or NumPy), ``Real`` also floats. Booleans pass
        neither.
    left, right : float or None
        Bounds; ``None`` leaves that side unbounded (but finite for reals).
    closed : {"left", "right", "both", "neither"}
        Which bounds belong to the interval.

    Notes
    -----
    NaN is never in an interval. Infinity is in it only when the bound on its side is written
    ``math.inf`` (or ``-math.inf``) and is closed, so ``Interval(Real, 0, None,
    closed="left")`` means finite numbers ``>= 0``.

    Examples
    --------
    >>> from numbers import Integral, Real
    >>> p = Interval(Real, 0, 1, closed="both")
    >>> p.is_satisfied_by(0.5), p.is_satisfied_by(True), p.is_satisfied_by(float("nan"))
    (True, False, False)
    >>> str(p), str(Interval(Integral, 1, None, closed="left"))
    ('a number in [0, 1]', 'an integer >= 1')
    >>> str(Interval(Real, 0, None, closed="neither"))
    'a positive number'
    """

    def __init__(self, type, left, right, *, closed):
        if type not in (numbers.Integral, numbers.Real):
            raise ValueError(f"Interval type must be numbers.Integral or numbers.Real, got {type}")
        if closed not in _CLOSED:
            raise ValueError(f"closed must be one of {list(_CLOSED)}, got {closed!r}")
        for bound in (left, right):
            if bound is not None and (_is_bool(bound) or not isinstance(bound, numbers.Real)
                                      or math.isnan(bound)):
                raise ValueError(f"Interval bounds must be numbers or None, got {bound!r}")
        if left is not None and right is not None and left > right:
            raise ValueError(f"Interval left bound {left} is above its right bound {right}")
        self.type = type
        self.left = left
        self.right = right
        self.closed = closed

    def is_satisfied_by(self, value):
        """Whether ``value`` lies in the interval."""
        if _is_bool(value) or not isinstance(value, self.type):
            return False
        if self.type is numbers.Real:
            value = float(value)
            if math.isnan(value):
                return False
            if math.isinf(value):
                bound = self.right if value > 0 else self.left
                closed = self.closed in (("right", "both") if value > 0 else ("left", "both"))
                return bound is not None and math.isinf(bound) and bound == value and closed
        if self.left is not None:
            if value < self.left or (value == self.left and self.closed in ("right", "neither")):
                return False
        if self.right is not None:
            if value > self.right or (value == self.right and self.closed in ("left", "neither")):
                return False
        return True

    def __str__(self):
        integer = self.type is numbers.Integral
        noun = "integer" if integer else "number"
        left_in = self.closed in ("left", "both")
        right_in = self.closed in ("right", "both")
        if self.left is not None and self.right is not None:
            lo = "[" if left_in else "("
            hi = "]" if right_in else ")"
            return (f"{_article(noun)} {noun} in {lo}{_format_bound(self.left)}, "
                    f"{_format_bound(self.right)}{hi}")
        finite = "" if integer else "finite "
        if self.left is None and self.right is None:
            return f"{_article(finite + noun)} {finite}{noun}"
        if self.right is None:
            if not integer and self.left == 0 and not left_in:
                return "a positive number"
            op = ">=" if left_in else ">"
            return f"{_article(finite + noun)} {finite}{noun} {op} {_format_bound(self.left)}"
        op = "<=" if right_in else "<"
        return f"{_article(finite + noun)} {finite}{noun} {op} {_format_bound(self.right)}"

    def __repr__(self):
        return (f"Interval({self.type.__name__}, {self.left!r}, {self.right!r}, "
                f"closed={self.closed!r})")


class Options:
    """One of a few values of a given type.

    Parameters
    ----------
    type : type
        The values' type; booleans are not integers here (``True`` is not the option ``1``).
    options : iterable
        The allowed values, in the order the message lists them (a set is sorted).

    Examples
    --------
    >>> from numbers import Integral
    >>> scenario = Options(Integral, {1, 2, 3})
    >>> scenario.is_satisfied_by(2), scenario.is_satisfied_by(True), str(scenario)
    (True, False, 'one of [1, 2, 3]')
    """

    def __init__(self, type, options):
        self.type = type
        if isinstance(options, (set, frozenset)):
            options = sorted(options)
        self.options = tuple(options)

    def is_satisfied_by(self, value):
        """Whether ``value`` is one of the options (and of the right type)."""
        if self.type is not bool and _is_bool(value):
            return False
        if not isinstance(value, self.type):
            return False
        try:
            return value in self.options
        except TypeError:  # pragma: no cover - unhashable or incomparable
            return False

    def __str__(self):
        return f"one of {list(self.options)}"

    def __repr__(self):
        return f"{type(self).__name__}({self.type.__name__}, {list(self.options)!r})"


class StrOptions(Options):
    """One of a few strings.

    Parameters
    ----------
    options : iterable of str
        The allowed strings, in the order the message lists them (a set is sorted).

    Examples
    --------
    >>> prior = StrOptions(("linear_chain", "sets_of_chains", "forest"))
    >>> prior.is_satisfied_by("forest"), str(prior)
    (True, "one of ['linear_chain', 'sets_of_chains', 'forest']")
    """

    def __init__(self, options):
        super().__init__(str, options)


class Satisfies:
    """Any check the other constraints do not express: a predicate and its description.

    Parameters
    ----------
    predicate : callable
        ``predicate(value) -> bool``; an exception it raises counts as ``False``.
    description : str
        What the predicate accepts, as it reads after "must be" (``"a non-empty string"``).

    Examples
    --------
    >>> non_empty = Satisfies(lambda v: isinstance(v, str) and v != "", "a non-empty string")
    >>> non_empty.is_satisfied_by(""), str(non_empty)
    (False, 'a non-empty string')
    """

    def __init__(self, predicate, description):
        self.predicate = predicate
        self.description = description

    def is_satisfied_by(self, value):
        """Whether the predicate accepts ``value``."""
        try:
            return bool(self.predicate(value))
        except Exception:  # noqa: BLE001 - a failing predicate rejects the value
            return False

    def __str__(self):
        return self.description

    def __repr__(self):
        return f"Satisfies({self.description!r})"


#: An integer other than 0 (``n_jobs``: -1 means every core, 0 is meaningless).
NONZERO_INTEGER = Satisfies(
    lambda v: isinstance(v, numbers.Integral) and not _is_bool(v) and v != 0,
    "a non-zero integer",
)

_SEED = Interval(numbers.Integral, 0, 2**32 - 1, closed="both")

_TYPE_WORDS = {
    numbers.Integral: "an integer",
    numbers.Real: "a number",
    str: "a string",
    bool: "a bool",
    dict: "a dict",
    Mapping: "a mapping",
}


def is_satisfied(constraint, value):
    """Whether ``value`` satisfies ``constraint`` (any of the module docstring's kinds).

    Examples
    --------
    >>> from numbers import Integral
    >>> is_satisfied(Integral, 3), is_satisfied(Integral, True), is_satisfied(None, None)
    (True, False, True)
    """
    if constraint is None:
        return value is None
    if isinstance(constraint, str):
        if constraint == "boolean":
            return _is_bool(value)
        if constraint == "random_state":
            return (value is None or _SEED.is_satisfied_by(value)
                    or isinstance(value, np.random.RandomState))
        raise ValueError(f"unknown constraint {constraint!r}")
    if constraint is callable:
        return callable(value)
    if isinstance(constraint, type):
        if constraint in (numbers.Integral, numbers.Real) and _is_bool(value):
            return False
        return isinstance(value, constraint)
    if hasattr(constraint, "is_satisfied_by"):
        return constraint.is_satisfied_by(value)
    raise ValueError(f"unknown constraint {constraint!r}")


def describe(constraint):
    """The words for one constraint, as they read after "must be".

    Examples
    --------
    >>> from numbers import Real
    >>> describe(None), describe("boolean"), describe(dict), describe(Interval(Real, 0, None,
    ...                                                                         closed="left"))
    ('None', 'a bool', 'a dict', 'a finite number >= 0')
    """
    if constraint is None:
        return "None"
    if isinstance(constraint, str):
        if constraint == "boolean":
            return "a bool"
        if constraint == "random_state":
            return "None, an integer in [0, 2**32 - 1] or a numpy.random.RandomState"
        raise ValueError(f"unknown constraint {constraint!r}")
    if constraint is callable:
        return "a callable"
    if isinstance(constraint, type):
        if constraint in _TYPE_WORDS:
            return _TYPE_WORDS[constraint]
        name = constraint.__name__
        return f"{_article(name)} {name}"
    return str(constraint)


def _join(words):
    words = list(words)
    if len(words) == 1:
        return words[0]
    return f"{', '.join(words[:-1])} or {words[-1]}"


def _check(name, value, constraints, caller):
    if isinstance(constraints, str) and constraints == "no_validation":
        return
    if not isinstance(constraints, (list, tuple)):
        raise TypeError(
            f"the constraints of {name} must be a list of constraints or 'no_validation', "
            f"got {constraints!r}"
        )
    if any(is_satisfied(c, value) for c in constraints):
        return
    prefix = f"{caller}: " if caller else ""
    raise InvalidParameterError(
        f"{prefix}{name} must be {_join(describe(c) for c in constraints)}, got {value!r}",
        parameter=name,
        value=value,
        caller=caller,
    )


def validate_params(params, constraints, caller):
    """Check every parameter of ``params`` that has constraints.

    Parameters
    ----------
    params : mapping
        Parameter name -> value (``estimator.get_params(deep=False)`` for an estimator, or the
        arguments of a function).
    constraints : mapping
        Parameter name -> list of constraints, or ``"no_validation"``. A value is valid when
        it satisfies at least one constraint of its list. Parameters without an entry are not
        checked.
    caller : str or None
        Who the parameters belong to (an estimator's class name, a function's name), named
        in the error.

    Raises
    ------
    InvalidParameterError
        For the first parameter, in the order of ``constraints``, that satisfies none of its
        constraints.

    Examples
    --------
    >>> from numbers import Integral, Real
    >>> constraints = {"k": [Interval(Integral, 1, None, closed="left")],
    ...                "tol": [Interval(Real, 0, 1, closed="left"), None]}
    >>> validate_params({"k": 5, "tol": None}, constraints, "top_k")
    >>> validate_params({"k": 5, "tol": 1.0}, constraints, "top_k")
    Traceback (most recent call last):
    ...
    bsi_sklearn.param_validation.InvalidParameterError: top_k: tol must be a number in [0, 1) \
or None, got 1.0
    """
    for name, allowed in constraints.items():
        if name in params:
            _check(name, params[name], allowed, caller)


def check_options(args, constraints):
    """Check parsed command-line options against constraints, named as on the command line.

    Run it first in a subcommand, before any work, so a bad option fails at once and writes
    nothing; the command line reports the error with its program and subcommand.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed options.
    constraints : mapping
        Option destination (``"n_scenarios"``) -> list of constraints, as for
        :func:`validate_params`. An option left at ``None`` was not given and is not checked,
        and ``None`` is not listed among the allowed values, so the constraints of a
        function's parameters serve its options as they are.

    Raises
    ------
    InvalidParameterError
        Naming the option as typed (``--n-scenarios``).

    Examples
    --------
    >>> import argparse
    >>> from numbers import Integral
    >>> args = argparse.Namespace(n_scenarios=0)
    >>> check_options(args, {"n_scenarios": [Interval(Integral, 1, None, closed="left")]})
    Traceback (most recent call last):
    ...
    bsi_sklearn.param_validation.InvalidParameterError: --n-scenarios must be an integer >= 1, \
got 0
    """
    for dest, allowed in constraints.items():
        value = getattr(args, dest, None)
        if value is None or allowed == "no_validation":
            continue
        _check("--" + dest.replace("_", "-"), value, [c for c in allowed if c is not None], None)


def option_type(convert, constraints):
    """An argparse ``type=`` that converts an option's text and checks it against constraints.

    A bad value is an argparse error (usage and exit status 2), named as argparse names it.
    Use it where an option is checked while parsing; :func:`check_options` checks after.

    Parameters
    ----------
    convert : callable
        Text -> value (``int``, ``float``...); a ``ValueError`` it raises reads as argparse's
        usual ``invalid int value``.
    constraints : list
        The constraints the converted value must satisfy one of.

    Returns
    -------
    parse : callable
        ``parse(text) -> value``.

    Examples
    --------
    >>> import argparse
    >>> from numbers import Integral
    >>> parser = argparse.ArgumentParser(prog="demo", exit_on_error=False)
    >>> positive = [Interval(Integral, 1, None, closed="left")]
    >>> _ = parser.add_argument("--sizes", nargs="+", type=option_type(int, positive))
    >>> parser.parse_args(["--sizes", "3", "5"]).sizes
    [3, 5]
    >>> parser.parse_args(["--sizes", "0"])
    Traceback (most recent call last):
    ...
    argparse.ArgumentError: argument --sizes: must be an integer >= 1, got 0
    """
    words = _join(describe(c) for c in constraints)

    def parse(text):
        value = convert(text)
        if not any(is_satisfied(c, value) for c in constraints):
            raise argparse.ArgumentTypeError(f"must be {words}, got {text}")
        return value

    parse.__name__ = getattr(convert, "__name__", "value")
    return parse
