"""Matplotlib figures of a specification report, rendered to PNG bytes (Agg, no pyplot)."""

import io
import textwrap

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Patch

__all__ = [
    "confusion_matrix_png",
    "layered_layout",
    "marginals_png",
    "order_dag_png",
    "satisfaction_png",
    "wrap_label",
]

_MAP_COLOR = "#2166ac"
_OTHER_COLOR = "#b2b2b2"
# Clause states of the satisfaction heatmap: violated, satisfied, vacuous (condition false).
STATE_COLORS = ("#d73027", "#1a9850", "#c7e9c0")
STATE_NAMES = ("violated", "satisfied", "vacuous (condition false)")


def _png(fig, dpi=100):
    # Figure + Agg canvas: no pyplot, no global figure registry, nothing left open.
    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight")
    fig.clear()
    return buf.getvalue()


def marginals_png(labels, values, in_map):
    """Horizontal bar chart of clause inclusion probabilities, MAP clauses highlighted.

    Parameters
    ----------
    labels : list of str
        One label per clause, drawn top to bottom.
    values : array-like of float
        Posterior inclusion probability of every clause.
    in_map : array-like of bool
        Whether each clause belongs to the MAP specification.
    """
    values = np.asarray(values, dtype=float)
    in_map = np.asarray(in_map, dtype=bool)
    n = len(labels)
    fig = Figure(figsize=(7.5, 1.2 + 0.28 * max(n, 1)))
    ax = fig.add_subplot()
    ypos = np.arange(n)[::-1]
    colors = np.where(in_map, _MAP_COLOR, _OTHER_COLOR)
    ax.barh(ypos, values, color=colors, height=0.7)
    for y, v in zip(ypos, values):
        ax.text(min(v, 1.0) + 0.01, y, f"{v:.2f}", va="center", fontsize=8)
    ax.set_yticks(ypos, labels, fontsize=8, family="monospace")
    ax.set_xlim(0, 1.1)
    ax.set_ylim(-0.6, n - 0.4)
    ax.set_xlabel("posterior inclusion probability")
    ax.axvline(0.5, color="k", lw=0.6, ls=":")
    ax.legend(handles=[Patch(color=_MAP_COLOR, label="in the MAP specification"),
                       Patch(color=_OTHER_COLOR, label="not in the MAP specification")],
              loc="lower right", fontsize=8, framealpha=0.9)
    ax.set_title("How certain is each clause?", fontsize=10)
    return _png(fig)


def layered_layout(nodes, edges):
    """Layered (left-to-right) positions of a DAG's nodes.

    A node's layer is the length of the longest path reaching it; within a layer, nodes are
    sorted by the mean position of their predecessors (barycentre heuristic), then by name.

    Parameters
    ----------
    nodes : list of hashable
    edges : list of (a, b)
        Edges of an acyclic graph over ``nodes``.

    Returns
    -------
    positions : dict
        Node -> ``(layer, slot)``; slots of a layer are centred on 0.
    """
    preds = {v: [] for v in nodes}
    for a, b in edges:
        preds[b].append(a)
    layer = {}

    def depth(v):
        if v not in layer:
            layer[v] = 1 + max((depth(p) for p in preds[v]), default=-1)
        return layer[v]

    for v in nodes:
        depth(v)
    positions = {}
    for k in range(max(layer.values(), default=-1) + 1):
        members = [v for v in nodes if layer[v] == k]

        def bary(v):
            ys = [positions[p][1] for p in preds[v]]
            return (float(np.mean(ys)) if ys else 0.0, str(v))

        members.sort(key=bary)
        for i, v in enumerate(members):
            positions[v] = (k, i - (len(members) - 1) / 2)
    return positions


def order_dag_png(nodes, edges, labels, edge_probabilities):
    """The ordering constraints as a layered DAG, edges labelled with their probability.

    Parameters
    ----------
    nodes : list of hashable
        Subtasks that take part in an order.
    edges : list of (a, b)
        Edges of the transitive reduction (``a`` precedes ``b``).
    labels : dict
        Node -> text drawn in its box.
    edge_probabilities : dict
        Edge -> posterior probability that ``a`` precedes ``b``.
    """
    pos = layered_layout(nodes, edges)
    n_layers = 1 + max(p[0] for p in pos.values())
    height = max(sum(1 for p in pos.values() if p[0] == k) for k in range(n_layers))
    fig = Figure(figsize=(2.0 + 2.6 * n_layers, 1.2 + 1.1 * height))
    ax = fig.add_subplot()
    boxes = {}
    for v, (x, y) in pos.items():
        boxes[v] = ax.text(
            x, -y, labels[v], ha="center", va="center", fontsize=9, zorder=3,
            bbox=dict(boxstyle="round,pad=0.4", fc="#eef3fa", ec=_MAP_COLOR, lw=1.2),
        )
    for a, b in edges:
        (xa, ya), (xb, yb) = pos[a], pos[b]
        # Anchored to the boxes themselves (fractions of their extents): from the right edge
        # of the predecessor to the left edge of the successor, whatever the text size.
        ax.annotate(
            "", xy=(0.0, 0.5), xycoords=boxes[b], xytext=(1.0, 0.5), textcoords=boxes[a],
            zorder=2,
            arrowprops=dict(arrowstyle="-|>", color="#333333", lw=1.2, mutation_scale=14,
                            shrinkA=4, shrinkB=4),
        )
        ax.text((xa + xb) / 2, -(ya + yb) / 2 + 0.12, f"{edge_probabilities[(a, b)]:.2f}",
                ha="center", va="bottom", fontsize=8, color="#555555", zorder=4)
    ax.set_xlim(-0.8, n_layers - 0.2)
    ax.set_ylim(-(height / 2 + 0.1), height / 2 + 0.1)
    ax.axis("off")
    ax.set_title("Ordering constraints (A \u2192 B: A happens before B; "
                 "label: posterior probability)", fontsize=9)
    return _png(fig)


def wrap_label(text, width=18):
    """Wrap a node label for a DAG box."""
    return "\n".join(textwrap.wrap(str(text), width=width)) or str(text)


def satisfaction_png(states, row_labels, column_labels, column_colors):
    """Clause-by-demonstration heatmap of satisfied / violated / vacuous clauses.

    Parameters
    ----------
    states : ndarray of shape (n_rows, n_demos), int
        0 violated, 1 satisfied, 2 vacuously satisfied (the clause's condition is false).
    row_labels : list of str
    column_labels : list of str
    column_colors : list of str
        Colour of every column label (predicted-unacceptable demonstrations stand out).
    """
    from matplotlib.colors import ListedColormap

    states = np.asarray(states)
    n_rows, n_cols = states.shape
    width = min(3.5 + 0.42 * n_cols, 40.0)
    fig = Figure(figsize=(width, 1.6 + 0.34 * n_rows))
    ax = fig.add_subplot()
    ax.imshow(states, cmap=ListedColormap(STATE_COLORS), vmin=-0.5, vmax=2.5,
              aspect="auto", interpolation="nearest")
    ax.set_yticks(np.arange(n_rows), row_labels, fontsize=8, family="monospace")
    fontsize = 7 if n_cols <= 40 else 5
    every = max(1, -(-n_cols // 80))  # at most 80 labelled columns
    shown = np.arange(0, n_cols, every)
    ax.set_xticks(shown, [column_labels[j] for j in shown], fontsize=fontsize)
    for tick, j in zip(ax.get_xticklabels(), shown):
        tick.set_color(column_colors[j])
    ax.set_xticks(np.arange(n_cols + 1) - 0.5, minor=True)
    ax.set_yticks(np.arange(n_rows + 1) - 0.5, minor=True)
    if n_cols <= 60:  # cell borders only while cells are wide enough
        ax.grid(which="minor", color="white", lw=1.0)
    ax.tick_params(which="minor", length=0)
    if n_rows > 1:
        ax.axhline(n_rows - 1.5, color="black", lw=1.5)
    ax.set_xlabel("demonstration (red label: predicted unacceptable)")
    ax.legend(handles=[Patch(color=c, label=s) for c, s in zip(STATE_COLORS, STATE_NAMES)],
              loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    ax.set_title("Which clause does each demonstration satisfy?", fontsize=10)
    return _png(fig)


def confusion_matrix_png(matrix, labels):
    """2x2 confusion matrix (rows: true label, columns: prediction) with counts."""
    matrix = np.asarray(matrix)
    fig = Figure(figsize=(3.8, 3.3))
    ax = fig.add_subplot()
    ax.imshow(matrix, cmap="Blues", vmin=0, vmax=max(int(matrix.max()), 1))
    for (i, j), v in np.ndenumerate(matrix):
        dark = v > 0.6 * max(matrix.max(), 1)
        ax.text(j, i, str(int(v)), ha="center", va="center", fontsize=14,
                color="white" if dark else "black")
    ax.set_xticks(range(len(labels)), labels)
    ax.set_yticks(range(len(labels)), labels)
    ax.set_xlabel("MAP specification says")
    ax.set_ylabel("label")
    ax.set_title("Confusion matrix of the MAP specification", fontsize=9)
    return _png(fig)
