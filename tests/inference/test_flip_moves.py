"""The one-bit Gibbs update over bitsets against the row-by-row one: the same draw, bit for bit."""

import numpy as np
import pytest
from numba import njit

from bsi_sklearn.inference._chain_kernel import fill_viol
from bsi_sklearn.inference._flip_moves import flip_move, flip_move_masked, zero_one_masks
from bsi_sklearn.inference.mcmc import deduplicate_demos
from bsi_sklearn.model import make_model
from bsi_sklearn.model.likelihood import LIKELIHOODS
from bsi_sklearn.model.priors import draw_hypothesis, global_inclusion


@njit
def _both(tau, w1, parent, demos, model, us, beta):
    # Every global bit redrawn in turn both ways from the same state and uniforms.
    n_rows = demos.truth_t.shape[1]
    viol_a = np.zeros(n_rows, dtype=np.int32)
    viol_b = np.zeros(n_rows, dtype=np.int32)
    n_a = fill_viol(viol_a, tau, w1, parent, demos.truth_t, model)
    n_b = fill_viol(viol_b, tau, w1, parent, demos.truth_t, model)
    masks = np.zeros((2, demos.bits.shape[1]), dtype=np.uint64)
    zero_one_masks(viol_b, masks)
    tau_a, tau_b = tau.copy(), tau.copy()
    out = np.empty((model.n_g, 6))
    for j in range(model.n_g):
        lg_in, lg_out = global_inclusion(j, model)
        na, lla, ua = flip_move(j, tau_a[j], lg_in, lg_out, viol_a, n_a, demos, model, us[j],
                                beta)
        nb, llb, ub = flip_move_masked(j, tau_b[j], lg_in, lg_out, viol_b, masks, n_b, demos,
                                       model, us[j], beta)
        n_a += na - tau_a[j]
        n_b += nb - tau_b[j]
        tau_a[j], tau_b[j] = na, nb
        out[j, 0], out[j, 1], out[j, 2] = na, nb, lla
        out[j, 3], out[j, 4], out[j, 5] = llb, ua, ub
    return out, viol_a, viol_b


@pytest.mark.parametrize("likelihood", LIKELIHOODS)
@pytest.mark.parametrize("beta", [1.0, 0.01])
def test_masked_flips_draw_what_the_row_by_row_flips_draw(likelihood, beta):
    rng = np.random.default_rng(3)
    n_g, n = 9, 3
    model = make_model(prior="sets_of_chains", likelihood=likelihood, n_globals=n_g,
                       n_subtasks=n, p_patterns=[0.2, 0.05, 0.1, 0.3])
    for _ in range(5):
        # 200 demonstrations (several words), some rows repeated (weights above 1)
        truth = (rng.random((200, n_g + n + n * n)) < 0.93).astype(np.uint8)
        truth[100:140] = truth[:40]
        demos = deduplicate_demos(truth, (rng.random(200) < 0.6).astype(np.int64))
        tau, w1, parent = draw_hypothesis(model, rng)
        out, viol_a, viol_b = _both(tau.astype(np.int64), w1.astype(np.int64),
                                    parent.astype(np.int64), demos, model,
                                    rng.random(n_g), beta)
        np.testing.assert_array_equal(out[:, 0], out[:, 1])
        np.testing.assert_array_equal(out[:, 2], out[:, 3])  # equal, not close
        np.testing.assert_array_equal(out[:, 4], out[:, 5])
        np.testing.assert_array_equal(viol_a, viol_b)
