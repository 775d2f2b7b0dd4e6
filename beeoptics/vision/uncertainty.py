"""Standard errors of colour quantities from a trace's replicate catches.

The tracer estimates each receptor's catches q from K independent
randomisations of its quasi-random samples (randomised QMC; Owen 1997,
L'Ecuyer & Lemieux 2002): K replicate estimates q_k whose mean q̄ is the
catch and whose spread gives its standard error, sd(q_k)/√K with the
sample deviation of n − 1 = K − 1 degrees of freedom. A colour quantity
f(q) (a hexagon coordinate, a COC coordinate, ΔS, a contrast) is then
reported as f(q̄), and its standard error is taken from the replicates:

- the replicate estimate (:func:`replicate_se`): f applied to each replicate's
  catches, sd(f(q_k))/√K. It is the error of f(q̄), not an estimate of
  f: for a nonlinear f the mean of the f(q_k) is not f(q̄), and f(q̄) stays
  the estimate (its bias, ½ tr(H Σ/K) with H the Hessian of f, is second
  order in the catches' error). To first order f(q_k) − f(q) ≈ J(q_k − q),
  J the Jacobian of f at q, so Var f(q_k) ≈ J Σ Jᵀ with Σ one replicate's
  covariance, and Var f(q̄) ≈ J (Σ/K) Jᵀ: the replicates' spread of f over
  √K is the delta method's error (Oehlert 1992), with J taken where each
  replicate lies rather than at one point;
- the delta method itself (:func:`delta_se`): a central-difference Jacobian
  of f at q̄ times the replicates' covariance of the catches over K.

The two agree where the errors are small against the scale on which f
bends (tests/test_uncertainty.py shows it, and both against a brute-force
spread of f(q̄) over many independent replicate sets). Every function is
vectorised over receptors: replicates come as (n, K, classes).

A distance between two independent estimates (two receptors, each traced
from its own random numbers) has the two errors in quadrature
(:func:`quadrature`); against an adapting background the background's own
error is left out where it is a mean over the scene's receptors, whose
error is smaller than one receptor's by about the square root of their
number (:func:`mean_se`).

References
----------
L'Ecuyer P, Lemieux C (2002) Recent advances in randomized quasi-Monte Carlo
methods. In Dror M et al. (eds) Modeling Uncertainty, pp 419–474. Kluwer.
Oehlert GW (1992) A note on the delta method. Am Stat 46:27–29.
Owen AB (1997) Scrambled net variance for integrals of smooth functions.
Ann Stat 25:1541–1562.
"""

import numpy as np

from beeoptics.replicates import standard_error
from beeoptics.vision.colourspace import colour_coordinates, hexagon_polar, rnl_metric

#: The share of a just-noticeable difference (JND) that ``target: auto`` allows a catch's error in each of
#: the receptor-noise-limited (RNL) distances, chromatic and achromatic (Vorobyev & Osorio 1998): an
#: error of standard deviation σ (in JND) adds σ² to a distance's expected square, so a quarter of a JND
#: adds a sixteenth of a JND² at most, and a ΔS of 1, the threshold, reads √(1 + 1/16) = 1.03 on average.
NOISE_FRACTION = 0.25
#: The relative step of :func:`delta_se`'s central differences: the cube root of float64's epsilon, the
#: step that balances truncation against rounding for a central difference (Press et al. 2007, §5.7).
RELATIVE_STEP = np.finfo(float).eps ** (1.0 / 3.0)


def replicate_se(f, replicates):
    """The standard error of f(q̄) from f applied to each replicate's catches.

    Parameters
    ----------
    f : callable
        Maps catches (..., classes) to a quantity (...) or (..., m), element-wise over the leading axes;
        any fixed input (an adapting background) bound the same for every replicate.
    replicates : array_like, shape (n, K, classes)
        Each receptor's K replicate catches.

    Returns
    -------
    ndarray, shape (n,) or (n, m)
        In the units of f.
    """
    with np.errstate(divide="ignore", invalid="ignore"):  # a replicate that caught nothing: spread_se's inf
        return spread_se(f(np.asarray(replicates, float)))


def spread_se(values):
    """The standard error of a quantity from its K replicate values, (n, K, ...) → (n, ...).

    Where some replicates have no finite value and others do (a logarithm
    of a replicate that caught nothing: the noise reaches the quantity's
    edge), the error is unbounded, inf, not unknown; NaN where none has one
    (a receptor without the class).
    """
    values = np.asarray(values, float)
    finite = np.isfinite(values)
    with np.errstate(invalid="ignore"):
        se = standard_error(values, axis=1)
    return np.where(finite.any(axis=1) & ~finite.all(axis=1), np.inf, se)


def delta_se(f, replicates):
    """The standard error of f(q̄) by the delta method: √(J (Σ/K) Jᵀ), J by central differences at q̄.

    Parameters
    ----------
    f, replicates
        As :func:`replicate_se`.

    Returns
    -------
    ndarray, shape (n,) or (n, m)
        In the units of f.
    """
    q = np.asarray(replicates, float)
    n, k, c = q.shape
    mean = q.mean(axis=1)
    deviation = q - mean[:, None]
    covariance = np.einsum("nki,nkj->nij", deviation, deviation) / (k - 1) / k
    step = RELATIVE_STEP * np.maximum(np.abs(mean), np.finfo(float).tiny)
    shift = step[:, :, None] * np.eye(c)  # (n, classes perturbed, classes)
    ahead, behind = f(mean[:, None] + shift), f(mean[:, None] - shift)
    jacobian = (ahead - behind) / (2.0 * step.reshape((n, c) + (1,) * (np.ndim(ahead) - 2)))
    # J has the perturbed class on axis 1: Var = Σ_ij J_i Σ_ij J_j for each output.
    return np.sqrt(np.einsum("ni...,nij,nj...->n...", jacobian, covariance, jacobian))


def quadrature(*errors):
    """The standard error of a difference or distance of independent estimates: √(Σ SE²)."""
    return np.sqrt(sum(np.square(np.asarray(e, float)) for e in errors))


def mean_se(replicates):
    """The standard error of the mean over receptors of their catches, (K, classes) → (classes,).

    Parameters
    ----------
    replicates : array_like, shape (n, K, classes)
        NaN where a receptor lacks a class; each receptor's replicates independent of the others'.
    """
    return standard_error(np.nanmean(np.asarray(replicates, float), axis=0), axis=0)


def colour_columns(seen, background_q, receptor_set, replicates=None):
    """:func:`beeoptics.vision.colourspace.colour_coordinates`, each quantity with its standard error beside it.

    The coordinates are those of ``seen``, the catches' estimate; each
    ``se_<column>`` is the replicate estimate (:func:`replicate_se`) with the
    one adapting background ``background_q`` for every replicate. A
    coordinate against that background (``hex_r``, ``rnl_dS``: distances from
    the centre) carries the receptor's error alone: where the background is
    the scene's mean, its own error is :func:`mean_se`'s, some √n times a
    receptor's smaller. The hue's error is taken on the circle (each
    replicate's hue within ±180° of the hue of their mean point), so that
    hues either side of 0° count as close.

    Parameters
    ----------
    seen : ndarray (n, classes)
        The radiance catches' estimates; NaN where a receptor lacks the class.
    background_q : ndarray (classes,)
        The adapting background's catches, in the units of ``seen``.
    receptor_set : ReceptorSet
    replicates : ndarray (n, K, classes), optional
        Each receptor's K replicate radiance catches. Without them, the
        coordinates alone.

    Returns
    -------
    dict of ndarray (n,)
        The coordinates' columns, each but ``lit`` followed by its ``se_<column>``, in its units.
    """
    coordinates = colour_coordinates(seen, background_q, receptor_set)
    if replicates is None:
        return coordinates
    n, k, c = replicates.shape
    lacking = np.isnan(np.asarray(seen, float))[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):  # a replicate that caught nothing: spread_se's inf
        flat = colour_coordinates(np.where(lacking, np.nan, replicates).reshape(n * k, c), background_q, receptor_set)
    spread = {name: values.reshape(n, k) for name, values in flat.items()}
    if "hex_hue_deg" in spread:
        centre, _ = hexagon_polar(np.stack([spread["hex_x"].mean(1), spread["hex_y"].mean(1)], -1))
        spread["hex_hue_deg"] = (spread["hex_hue_deg"] - centre[:, None] + 180.0) % 360.0 - 180.0
    out = {}
    for name, values in coordinates.items():
        out[name] = values
        if name != "lit":
            out[f"se_{name}"] = spread_se(spread[name])
    return out


def noise_forms(receptor_set):
    """The forms (:class:`beeoptics.light.precision.Precision`) that hold a catch's error to
    :data:`NOISE_FRACTION` of a JND in the chromatic and in the achromatic receptor-noise-limited
    distance of ``receptor_set`` (``target: auto``), or None where the set gives no receptor noise (its
    Weber fractions): (2, classes, classes), or (1, …) where the achromatic class is not a colour class.

    A catch's estimate has log error ε (ε_c = δq_c/q_c, covariance C over
    the replicates), and the RNL distances it moves are those of Δf = ε
    (Vorobyev & Osorio 1998): the chromatic ΔS² = εᵀ M ε, M = W − w wᵀ/Σw
    over the colour classes (:func:`~beeoptics.vision.colourspace.rnl_metric`),
    of expectation tr(M C), and the achromatic (ε_a/ω_a)², of expectation
    C_aa/ω_a², a the achromatic class. Each is held to NOISE_FRACTION²: two
    forms, M/NOISE_FRACTION² and e_a e_aᵀ/(ω_a NOISE_FRACTION)² (the latter
    only where the achromatic class is a colour class, whose ω is given).

    The tracer's error is nearly common to a receptor's classes (a cone's
    samples meeting more or less of a sunlit blade scale its catches
    together: in the generated meadow the replicates' errors of UV, B and G
    correlate by 0.95 to 0.99, median over the worker's receptors), and a
    common error moves no colour: the chromatic distance ignores it, so the
    achromatic class's ω_a/4 decides where a quarter of every class's ω
    would hold the blue receptor (ω 0.06) to 1.5 % for an error no colour
    distance sees (measured, 1,024 samples of the worker pair in the meadow:
    458 samples a receptor on average under this rule with each receptor's
    error known, 1,995 under ω/4 for every class).
    """
    if receptor_set.weber is None:
        return None
    k, colour = len(receptor_set.classes), receptor_set.chromatic
    forms = np.zeros((2, k, k))
    forms[0][np.ix_(colour, colour)] = rnl_metric(receptor_set.weber)
    where = np.flatnonzero(colour == receptor_set.achromatic)
    if where.size:
        forms[1][receptor_set.achromatic, receptor_set.achromatic] = 1.0 / receptor_set.weber[where[0]] ** 2
    return forms[: 1 + bool(where.size)] / NOISE_FRACTION ** 2
