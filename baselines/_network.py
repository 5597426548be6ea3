"""The networks of the LSTM baselines and the padded batches they read.

:class:`RecurrentNet` (stacked (Bi-)LSTM, objective head, optional per-step phase head),
:class:`Batches` (one fit's sequences padded once, mini-batches cut from them),
:func:`make_batch` (a batch padded on its own, for prediction), :func:`predict_batches`
(every sequence through a fitted network).
"""

from __future__ import annotations

import math
import zlib

import numpy as np

from baselines._runtime import torch
from baselines._sequences import length_mask, pad_sequences, reverse_index

nn = torch.nn

__all__ = ["Batches", "RecurrentNet", "make_batch", "predict_batches"]


class Batches:
    """The training sequences, targets and weights of one ``fit`` as padded tensors, built once.

    Every mini-batch (and the validation batch) is then rows of these tensors cut to the
    batch's longest sequence: the same values that padding the batch on its own gives
    (:func:`make_batch`), without padding and converting again at every step of every epoch,
    in the early-stopping phase and again in the refit. Memory: ``n_sequences x`` the longest
    length ``x n_features`` floats, the size of one padded batch holding every sequence.
    """

    def __init__(self, data, offsets, y01, weights, phase_data, device):
        n = len(offsets) - 1
        every = np.arange(n)
        padded, lengths = pad_sequences(data, offsets, every)
        self.lengths_np = lengths
        self.x = torch.as_tensor(padded, device=device)
        self.lengths = torch.as_tensor(lengths, device=device)
        self.rev = torch.as_tensor(reverse_index(lengths, padded.shape[1]), device=device)
        self.y = torch.as_tensor(y01, device=device)
        self.weights = torch.as_tensor(weights, device=device)
        self.phases = self.mask = None
        if phase_data is not None:
            phases, _ = pad_sequences(phase_data, offsets, every, fill=0)
            self.phases = torch.as_tensor(phases, device=device)
            self.mask = torch.as_tensor(length_mask(lengths, padded.shape[1]), device=device)

    def batch(self, indices):
        """Inputs, lengths, reversal index, targets, weights, phase targets and step mask."""
        t_max = int(self.lengths_np[indices].max())
        rows = torch.as_tensor(indices, device=self.x.device)
        phases = mask = None
        if self.phases is not None:
            phases = self.phases[rows, :t_max].contiguous()
            mask = self.mask[rows, :t_max].contiguous()
        return (self.x[rows, :t_max].contiguous(), self.lengths[rows],
                self.rev[rows, :t_max].contiguous(), self.y[rows], self.weights[rows],
                phases, mask)


def make_batch(data, offsets, indices, device):
    """Pad the sequences at ``indices``; return inputs, lengths and reversal index."""
    padded, lengths = pad_sequences(data, offsets, indices)
    return (
        torch.as_tensor(padded, device=device),
        torch.as_tensor(lengths, device=device),
        torch.as_tensor(reverse_index(lengths, padded.shape[1]), device=device),
    )


class RecurrentNet(nn.Module):
    """Stacked (Bi-)LSTM with an objective head and an optional per-step phase head.

    Each layer is a forward ``nn.LSTM`` and, when bidirectional, a second one run over each
    sequence reversed inside its length (see :func:`baselines._sequences.reverse_index`), so no
    output at a valid step depends on padding.
    """

    def __init__(self, n_features, hidden_size, num_layers, bidirectional, dropout, n_outputs,
                 n_phases, pooling):
        super().__init__()
        self.bidirectional = bidirectional
        self.pooling = pooling
        self.hidden_size = hidden_size
        width = hidden_size * (2 if bidirectional else 1)
        sizes = [n_features] + [width] * (num_layers - 1)
        self.forward_layers = nn.ModuleList(
            nn.LSTM(size, hidden_size, batch_first=True) for size in sizes
        )
        self.backward_layers = nn.ModuleList(
            nn.LSTM(size, hidden_size, batch_first=True) for size in sizes
        ) if bidirectional else None
        self.drop = nn.Dropout(dropout)
        self.objective_head = nn.Linear(width, n_outputs)
        self.phase_head = nn.Linear(width, n_phases) if n_phases else None

    def forward(self, x, lengths, rev_index):
        """Objective logits ``(B, n_outputs)`` and phase logits ``(B, T, n_phases)`` or None."""
        h = x
        for k, layer in enumerate(self.forward_layers):
            if k > 0:
                h = self.drop(h)
            out, _ = layer(h)
            if self.bidirectional:
                idx = rev_index.unsqueeze(-1)
                reversed_in = h.gather(1, idx.expand(-1, -1, h.shape[-1]))
                back, _ = self.backward_layers[k](reversed_in)
                back = back.gather(1, idx.expand(-1, -1, back.shape[-1]))
                out = torch.cat([out, back], dim=-1)
            h = out
        batch = torch.arange(h.shape[0], device=h.device)
        if self.pooling == "last":
            summary = h[batch, lengths - 1]
            if self.bidirectional:
                # the backward direction's final state sits at the first step
                summary = torch.cat([summary[:, : self.hidden_size],
                                     h[:, 0, self.hidden_size :]], dim=-1)
        else:
            mask = (torch.arange(h.shape[1], device=h.device)[None, :] < lengths[:, None])
            mask = mask.unsqueeze(-1)
            if self.pooling == "mean":
                summary = (h * mask).sum(dim=1) / lengths[:, None].to(h.dtype)
            else:
                summary = h.masked_fill(~mask, -math.inf).amax(dim=1)
        logits = self.objective_head(self.drop(summary))
        phase_logits = self.phase_head(h) if self.phase_head is not None else None
        return logits, phase_logits


def predict_batches(module, data, offsets, lengths, n_outputs, step):
    """Objective probabilities ``(n, n_outputs)`` and per-step phase logits of every sequence.

    The sequences are read shortest first (ties by content), ``step`` at a time, without
    gradients; the phase logits are ``None`` per sequence when the network has no phase head.
    """
    device = next(module.parameters()).device
    # Ties in length are ordered by content, not by position in X: a batch then holds the same
    # rows in the same order whatever the order of X, so the fused kernel's rounding, which
    # can depend on a row's place in its batch (about 1e-7), cannot depend on it.
    content = [zlib.crc32(np.ascontiguousarray(data[offsets[i]:offsets[i + 1]]).tobytes())
               for i in range(len(lengths))]
    order = np.lexsort((np.asarray(content, dtype=np.int64), lengths))
    proba = np.empty((len(lengths), n_outputs))
    phase_logits = [None] * len(lengths)
    module.eval()
    with torch.no_grad():
        for s in range(0, len(order), step):
            indices = order[s : s + step]
            batch = make_batch(data, offsets, indices, device)
            logits, phases = module(*batch)
            proba[indices] = torch.sigmoid(logits).double().cpu().numpy()
            if phases is not None:
                phases = phases.double().cpu().numpy()
                for k, i in enumerate(indices):
                    phase_logits[i] = phases[k, : lengths[i]]
    return proba, phase_logits
