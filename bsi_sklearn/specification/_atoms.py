"""How Spot and flloat / LTLf2DFA read an atom: the rules both LTLf writers share.

:mod:`~bsi_sklearn.specification.ltlf_export` (a specification's text) and
:mod:`~bsi_sklearn.specification.templates` (an instance's text) write atoms by them; kept
apart so that neither imports the other.
"""

import re

__all__ = ["ltlf_atom_problem", "spot_atom"]

# Spot's scanner (spot/parsetl/scantl.ll) reads an unquoted atomic proposition as
# [a-zA-EH-WYZ_.][a-zA-Z0-9_.]* (or F, G, X followed by a digit): a word starting with F, G or
# X is an operator applied to the rest. Before that rule it reads 1, 0 and true / false in any
# case as constants and the words U, R, V, W, M, xor, first_match as operators. Anything else is
# written in double quotes, where a backslash escapes the next character.
_SPOT_PLAIN = re.compile(r"[a-zA-EH-WYZ_][a-zA-Z0-9_]*\Z")
_SPOT_WORDS = {"U", "R", "V", "W", "M", "xor", "first_match"}
# flloat's and LTLf2DFA's lexers (flloat/parser/ltlf.lark) read [a-z][a-z0-9_]* as an atom but
# try the keywords first, case-insensitively, on any prefix: "lastly" is LAST then "ly".
_LTLF_ATOM = re.compile(r"[a-z][a-z0-9_]*\Z")
_LTLF_PREFIXES = ("true", "false", "last", "end")
_LTLF_WORDS = {"tt", "ff"}


def spot_atom(name):
    r"""``name`` as a Spot atomic proposition: plain when Spot reads it so, else quoted.

    Examples
    --------
    >>> print(spot_atom("safe"), spot_atom("GPS_ok"), spot_atom("True"), spot_atom("V"))
    safe "GPS_ok" "True" "V"
    >>> print(spot_atom('say "hi"'), spot_atom("a\\b"))
    "say \"hi\"" "a\\b"
    """
    text = str(name)
    if _SPOT_PLAIN.match(text) and text not in _SPOT_WORDS and \
            text.lower() not in ("true", "false"):
        return text
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def ltlf_atom_problem(name):
    """Why flloat / LTLf2DFA cannot read ``name`` as an atom (``None`` when they can)."""
    text = str(name)
    if not _LTLF_ATOM.match(text):
        return "atoms are lowercase letters, digits and underscores, starting with a letter"
    if text in _LTLF_WORDS:
        return f"{text!r} is a constant"
    for word in _LTLF_PREFIXES:
        if text.startswith(word):
            return (f"the parser reads the keyword {word!r} at its start (no atom may start "
                    "with true, false, last or end)")
    return None
