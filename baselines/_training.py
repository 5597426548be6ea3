"""The training loop of the LSTM baselines: Adam, early stopping, or a fixed number of epochs."""

from __future__ import annotations

import math
from dataclasses import dataclass

from baselines._runtime import torch

nn = torch.nn

__all__ = ["Training", "train"]


@dataclass(frozen=True)
class Training:
    """The hyperparameters of a training run (the estimator's parameters of the same names)."""

    lr: float
    weight_decay: float
    batch_size: int
    clip_grad_norm: float | None
    max_epochs: int
    patience: int
    verbose: int = 0


def train(module, batches, train_idx, valid_idx, order_rng, objective_mask, settings,
          epochs=None):
    """Train ``module`` with early stopping, or for exactly ``epochs`` epochs (a refit).

    Parameters
    ----------
    module : RecurrentNet
        The network, trained in place; it is left in eval mode with the weights kept.
    batches : Batches
        The fit's sequences, targets and weights.
    train_idx, valid_idx : ndarray of int
        Training and validation sequences (``valid_idx`` may be empty: the training loss is
        then monitored).
    order_rng : numpy.random.Generator
        Shuffles the training sequences at every epoch.
    objective_mask : torch.Tensor
        1 for an objective with two labels, 0 for a constant one (left out of the loss).
    settings : Training
        Hyperparameters.
    epochs : int or None
        A fixed number of epochs: the weights after the last are kept, nothing is monitored.
        ``None``: early stopping, the best epoch's weights are kept.

    Returns
    -------
    stopping : tuple or None
        With early stopping, ``(history, best_epoch, best_loss)``: one dict per epoch run
        (``epoch``, ``train_loss``, ``valid_loss``), the epoch kept (1-based; 0 when no loss
        was finite) and its monitored loss. ``None`` with ``epochs``.
    """
    params = list(module.parameters())
    # foreach: one kernel per step for all parameters instead of one per parameter (the
    # same arithmetic element by element, so the same weights; about 5 % of a fit)
    optimizer = torch.optim.Adam(
        params, lr=settings.lr, weight_decay=settings.weight_decay, foreach=True
    )

    def batch_loss(indices):
        x, lengths, rev, target, weight, phase_target, mask = batches.batch(indices)
        logits, phase_logits = module(x, lengths, rev)
        bce = nn.functional.binary_cross_entropy_with_logits(
            logits, target, weight=weight, reduction="none",
        )
        loss = (bce.mean(dim=0) * objective_mask).sum()
        if phase_logits is not None:
            loss = loss + nn.functional.cross_entropy(
                phase_logits[mask], phase_target[mask]
            )
        return loss

    has_valid = len(valid_idx) > 0
    best_loss, best_epoch, best_state = math.inf, 0, None
    history = []
    batch_size = int(settings.batch_size)
    for epoch in range(1, int(epochs or settings.max_epochs) + 1):
        module.train()
        order = order_rng.permutation(train_idx)
        total, count = 0.0, 0
        for s in range(0, len(order), batch_size):
            indices = order[s : s + batch_size]
            loss = batch_loss(indices)
            optimizer.zero_grad()
            loss.backward()
            if settings.clip_grad_norm is not None:
                nn.utils.clip_grad_norm_(params, settings.clip_grad_norm, foreach=True)
            optimizer.step()
            total += float(loss.detach()) * len(indices)
            count += len(indices)
        train_loss = total / count
        if epochs is not None:
            continue
        valid_loss = math.nan
        if has_valid:
            module.eval()
            with torch.no_grad():
                valid_loss = float(batch_loss(valid_idx))
        monitored = valid_loss if has_valid else train_loss
        history.append({"epoch": epoch, "train_loss": train_loss, "valid_loss": valid_loss})
        if settings.verbose > 1:
            print(
                f"epoch {epoch:4d}  train_loss {train_loss:.4f}  valid_loss {valid_loss:.4f}"
            )
        if not math.isfinite(monitored):
            break
        if monitored < best_loss:
            best_loss, best_epoch = monitored, epoch
            best_state = {k: v.detach().clone() for k, v in module.state_dict().items()}
        elif epoch - best_epoch >= settings.patience:
            break
    if epochs is not None:
        module.eval()
        return None
    if best_state is not None:
        module.load_state_dict(best_state)
    module.eval()
    return history, best_epoch, best_loss
