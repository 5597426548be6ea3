"""Torch's global settings while a network trains or predicts, restored afterwards.

Deterministic algorithms (:func:`deterministic_torch`), the intra-op thread count
(:func:`torch_threads`), and both with forked random generators for one fit
(:func:`isolated_torch`): the estimator changes none of torch's global state for good. The one
``torch`` module object of the package's torch-backed modules is this module's.
"""

from __future__ import annotations

import contextlib

from baselines._torch import require_torch

torch = require_torch()  # with a message naming the [baselines] extra when torch is absent

__all__ = ["deterministic_torch", "isolated_torch", "torch", "torch_threads"]


@contextlib.contextmanager
def deterministic_torch():
    """Run the block with torch's deterministic algorithms on, then restore the setting.

    The CPU kernels these networks use are deterministic already; the flag makes torch raise
    rather than silently pick a nondeterministic kernel (on GPUs, for example). Its companion
    ``torch.utils.deterministic.fill_uninitialized_memory`` (NaN-fill every new tensor, a
    guard against kernels that read memory they did not write) is switched off inside the
    block: it cost about a tenth of a fit (tens of thousands of fills per fit) and changes no
    result of kernels that write their outputs, which every kernel used here does (the fitted
    weights are bit-identical with and without it).
    """
    previous = torch.are_deterministic_algorithms_enabled()
    fill = torch.utils.deterministic.fill_uninitialized_memory
    torch.use_deterministic_algorithms(True)
    torch.utils.deterministic.fill_uninitialized_memory = False
    try:
        yield
    finally:
        torch.use_deterministic_algorithms(previous)
        torch.utils.deterministic.fill_uninitialized_memory = fill


@contextlib.contextmanager
def torch_threads(n_threads):
    """Use ``n_threads`` torch intra-op threads inside the block, then restore the setting."""
    if n_threads is None:
        yield
        return
    previous = torch.get_num_threads()
    torch.set_num_threads(int(n_threads))
    try:
        yield
    finally:
        torch.set_num_threads(previous)


@contextlib.contextmanager
def isolated_torch(device):
    """Run the block in a fork of torch's random generators, with deterministic algorithms.

    The CPU generator is forked, and ``device``'s on a GPU; both settings are restored when the
    block ends, so seeding inside it leaves the global random state untouched.
    :func:`torch.random.fork_rng` is not thread-safe: fit models in separate processes.
    """
    fork_devices = [device.index or 0] if device.type == "cuda" else []
    with torch.random.fork_rng(devices=fork_devices), deterministic_torch():
        yield
