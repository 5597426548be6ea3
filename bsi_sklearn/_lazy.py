"""Public names of a package imported on first use (PEP 562 module ``__getattr__``).

``import bsi_sklearn`` and the command lines' ``--help`` stay fast: scikit-learn, pandas and
numba load with the module that needs them, on the first access to one of its names.
"""

import importlib

__all__ = ["lazy_names"]


def lazy_names(package, modules, namespace):
    """Module-level ``__getattr__`` and ``__dir__`` loading ``modules[name]`` on first use.

    Parameters
    ----------
    package : str
        The package's name, for the error message.
    modules : dict
        Public name -> the module that defines it.
    namespace : dict
        The package's ``globals()``: a loaded name is stored there, so it loads once.

    Examples
    --------
    >>> ns = {}
    >>> getattr_, dir_ = lazy_names("pkg", {"sqrt": "math"}, ns)
    >>> getattr_("sqrt")(4.0), "sqrt" in ns
    (2.0, True)
    """
    def __getattr__(name):
        if name in modules:
            value = getattr(importlib.import_module(modules[name]), name)
            namespace[name] = value
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__():
        return sorted(set(namespace) | set(modules))

    return __getattr__, __dir__
