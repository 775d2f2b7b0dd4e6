"""Standard errors of colour quantities from replicate catches (beeoptics.vision.uncertainty)."""

import numpy as np
import pytest

from beeoptics.vision.colourspace import coc, excitation, hexagon, rnl_distance
from beeoptics.vision.receptorset import load_receptor_set
from beeoptics.replicates import standard_error
from beeoptics.vision.uncertainty import colour_columns, delta_se, mean_se, quadrature, replicate_se

BEE = load_receptor_set("apis_mellifera")
#: Replicates per receptor, as the tracer draws them.
K = 8


def colour(q):
    """Hexagon x, y, COC A, B and RNL ΔS from the background (catches adapted to 1), (..., 5)."""
    e = excitation(q)
    return np.concatenate([hexagon(e), coc(e), rnl_distance(q, np.ones(3), BEE.weber)[..., None]], -1)


def replicates_of(true, relative, k, rng):
    """K replicate catches of each receptor: the true catches times independent lognormal noise."""
    return true[:, None] * rng.lognormal(0.0, relative, (len(true), k, true.shape[-1]))


@pytest.fixture(scope="module")
def true_catches():
    # Receptors away from the background (ΔS > 1), where ΔS is smooth in the catches.
    q = np.exp(np.random.default_rng(3).uniform(-1.0, 1.0, (300, 3)))
    return q[rnl_distance(q, np.ones(3), BEE.weber) > 1.0][:200]


def test_the_replicates_spread_and_the_delta_method_agree_where_errors_are_small(true_catches):
    # 3 % per replicate: about 1 % on the mean of eight, the tracer's median.
    reps = replicates_of(true_catches, 0.03, K, np.random.default_rng(5))
    by_replicates, by_delta = replicate_se(colour, reps), delta_se(colour, reps)
    ratio = by_replicates / by_delta
    assert np.median(np.abs(ratio - 1.0)) < 0.01 and np.percentile(np.abs(ratio - 1.0), 99) < 0.05


def test_both_estimates_match_a_brute_force_spread_over_many_replicate_sets(true_catches):
    rng = np.random.default_rng(11)
    sets = 1000
    reps = replicates_of(np.repeat(true_catches, sets, 0), 0.03, K, rng).reshape(len(true_catches), sets, K, 3)
    # The estimate is f of the mean catches; its true error is its spread over independent sets.
    truth = colour(reps.mean(2)).std(1, ddof=1)
    flat = reps.reshape(-1, K, 3)
    for estimate in (replicate_se, delta_se):
        rms = np.sqrt((estimate(colour, flat) ** 2).reshape(len(true_catches), sets, -1).mean(1))
        # A thousand sets: the spread's own sampling error is 2.2 % (1/√(2·999)), the estimates' rms's 0.8 %.
        deviation = np.abs(rms / truth - 1.0)
        assert np.median(deviation) < 0.03 and deviation.max() < 0.12, estimate.__name__


def test_both_estimates_by_hand_for_two_replicates():
    # f = q², replicates 1 and 3: the spread of f (1 and 9) over √2; the delta method f'(q̄) = 2·2 times q's.
    reps = np.array([[[1.0], [3.0]]])
    assert replicate_se(np.square, reps)[0, 0] == pytest.approx(np.std([1.0, 9.0], ddof=1) / np.sqrt(2))
    assert delta_se(np.square, reps)[0, 0] == pytest.approx(2 * 2.0 * np.std([1.0, 3.0], ddof=1) / np.sqrt(2))


def test_a_replicate_that_caught_nothing_makes_a_log_quantitys_error_unbounded_not_unknown():
    # One receptor's G catch is 0 in one replicate of eight, 2 in the rest: its mean is positive and its ΔS
    # finite, but that replicate's log contrast is not: the error is inf (the noise reaches the catch), where
    # a receptor without the class (all NaN) keeps NaN, and the hexagon, finite at 0, its plain spread.
    reps = np.ones((3, K, 3))
    reps[0, :, 2], reps[0, 0, 2] = 2.0, 0.0
    reps[2] = np.nan
    se = replicate_se(colour, reps)
    assert se[0, 4] == np.inf and np.isfinite(se[0, :4]).all() and np.isfinite(se[1]).all()
    assert np.isnan(se[2]).all()
    seen = np.array([[1.0, 1.0, 1.75], [1.0, 1.0, 1.0], [np.nan] * 3])
    columns = colour_columns(seen, np.ones(3), BEE, reps)
    assert columns["se_rnl_dS"][0] == np.inf and np.isfinite(columns["rnl_dS"][0])
    assert np.isfinite(columns["se_hex_x"][0]) and np.isnan(columns["se_rnl_dS"][2])


def test_independent_errors_add_in_quadrature_and_a_mean_over_receptors_shrinks_them():
    assert quadrature(3.0, 4.0) == pytest.approx(5.0)
    rng = np.random.default_rng(2)
    reps = replicates_of(np.ones((10000, 3)), 0.05, K, rng)
    one = standard_error(reps, axis=1).mean(0)
    np.testing.assert_allclose(mean_se(reps), one / np.sqrt(10000), rtol=0.3)
