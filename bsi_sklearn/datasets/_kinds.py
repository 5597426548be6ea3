"""``negative_kinds`` of the dataset generators: one check for every domain."""

from __future__ import annotations

__all__ = ["check_kinds"]


def check_kinds(kinds, n_negative, choices):
    """The kinds of negative demonstration to generate, as a tuple.

    Parameters
    ----------
    kinds : str or iterable of str
        One kind, or a sequence of kinds, each among ``choices``.
    n_negative : int
        Number of negative demonstrations asked for; with none, ``kinds`` may be empty.
    choices : tuple of str
        The domain's kinds (its ``NEGATIVE_KINDS``).

    Returns
    -------
    kinds : tuple of str

    Raises
    ------
    ValueError
        For a value that is not a sequence, an unknown kind, or no kind while negatives are
        asked for.

    Examples
    --------
    >>> check_kinds("skip", 3, ("threat", "skip"))
    ('skip',)
    >>> check_kinds(["fly"], 3, ("threat", "skip"))
    Traceback (most recent call last):
    ...
    ValueError: negative_kinds has 'fly'; choose among ('threat', 'skip')
    """
    if isinstance(kinds, str):
        kinds = (kinds,)
    try:
        kinds = tuple(kinds)
    except TypeError:
        raise ValueError(f"negative_kinds must be a sequence of kinds, got {kinds!r}") from None
    for k in kinds:
        if k not in choices:
            raise ValueError(f"negative_kinds has {k!r}; choose among {choices}")
    if n_negative and not kinds:
        raise ValueError("negative_kinds is empty but n_negative > 0")
    return kinds
