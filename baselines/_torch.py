"""The one import of torch in ``baselines``; a missing torch names the extra to install."""

import importlib

__all__ = ["TORCH_MISSING", "require_torch"]

#: The message of the error raised where a network is requested and torch is not installed.
TORCH_MISSING = (
    "the LSTM baselines need PyTorch, an optional dependency of bsi-sklearn that is not "
    'installed: pip install "bsi-sklearn[baselines]" (the classifier, simulation and '
    "extraction work without it)"
)


def require_torch():
    """The ``torch`` module, or a clear error saying how to install it.

    Returns
    -------
    torch : module
        PyTorch.

    Raises
    ------
    ModuleNotFoundError
        When torch is not installed; the message says ``pip install "bsi-sklearn[baselines]"``.
        An import error inside an installed torch propagates unchanged.
    """
    try:
        return importlib.import_module("torch")
    except ModuleNotFoundError as exc:
        if exc.name != "torch":
            raise
        raise ModuleNotFoundError(TORCH_MISSING, name="torch") from exc
