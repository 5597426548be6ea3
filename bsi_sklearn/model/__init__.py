"""The model: what a specification is made of, and how probable it is (DESIGN §2–§4, §12).

- ``clauses``: the clause layout and the clause truth, computed once per fit;
- ``patterns``: the pattern library (templates beyond the paper's: Declare, Dwyer, user
  LTLf), its truth on demonstrations (``_pattern_kernels``, ``_ltlf_program``);
- ``priors``: Priors 1–3, every fact about them, the tables the kernels read;
- ``likelihood``: the CB, CI and calibrated likelihoods and the label noise's prior;
- ``bundle``: :class:`Model` and :func:`make_model`, the one argument the kernels take.

Change the prior in ``priors``, the likelihood in ``likelihood``, the templates in
``patterns``. The names below are imported on first use.
"""

from bsi_sklearn._lazy import lazy_names

__all__ = ["Model", "make_model"]

_MODULES = {"Model": "bsi_sklearn.model.bundle", "make_model": "bsi_sklearn.model.bundle"}

__getattr__, __dir__ = lazy_names("bsi_sklearn.model", _MODULES, globals())
