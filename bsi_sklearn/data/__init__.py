"""The data layer: demonstrations in, validated traces and proposition roles out (DESIGN §1, §4).

``traces`` (every accepted input to one :class:`Traces`, or an error naming the
demonstration, step and proposition), ``roles`` (which propositions are global candidates,
subtasks and conditions), ``inferred_roles`` (the roles rule: roles read from the data) and
``preprocessing`` (:class:`NegationAugmenter`). The public names are imported on first use,
as the top-level package's are.
"""

from bsi_sklearn._lazy import lazy_names

__all__ = ["Traces", "check_traces", "Roles", "resolve_roles", "infer_roles",
           "NegationAugmenter"]

_MODULES = {"Traces": "bsi_sklearn.data.traces", "check_traces": "bsi_sklearn.data.traces",
            "Roles": "bsi_sklearn.data.roles", "resolve_roles": "bsi_sklearn.data.roles",
            "infer_roles": "bsi_sklearn.data.inferred_roles",
            "NegationAugmenter": "bsi_sklearn.data.preprocessing"}

__getattr__, __dir__ = lazy_names("bsi_sklearn.data", _MODULES, globals())
