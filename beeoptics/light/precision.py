"""The precision of traced means: standard errors from independent replicates, and sampling to a precision.

A receptor's samples are scrambled quasi-random points, correlated by
design, so the sample variance of its samples over their count misstates
its error (it overstates it where the points stratify well). Its
:data:`REPLICATES` replicates are independent randomisations of one point
set (:mod:`beeoptics.light.sampler`), each an unbiased estimate of its own
(a weighted mean, over weights sin θ/θ that differ by under 10⁻³ in a cone
of a few degrees, so its ratio's bias is negligible); their mean is the receptor's estimate and
their sample deviation over √K its standard error (Owen 1997; L'Ecuyer &
Lemieux 2002).

Adaptive sampling (``trace.precision``) is Stein's two-stage procedure
(Stein 1945): a pilot of K replicates of m₀ samples estimates each
receptor's relative standard error r₀, which fixes its samples per
replicate, m = m₀ (r₀/target)², clipped to the bounds asked; then K fresh
replicates of m samples each (replicates K … 2K − 1, whose random numbers
none of the pilot's share) give the estimate and its error, and the pilot
is set aside. Because m is fixed before any of the estimate's samples are
drawn, each replicate is an unbiased estimate whatever m is, and so is
their mean. A sequential rule, adding samples until the error looks small
enough and keeping them all, is biased: an estimate that happens to read
low often also reads precise (a rare bright patch not yet met), and stops
there, low.

References
----------
Stein C (1945) A two-sample test for a linear hypothesis whose power is
independent of the variance. Ann Math Stat 16:243–258.
Vorobyev M, Osorio D (1998) Receptor noise as a determinant of colour
thresholds. Proc R Soc Lond B 265:351–358.
Owen AB (1997) Monte Carlo variance of scrambled net quadrature. SIAM J
Numer Anal 34:1884–1910.
L'Ecuyer P, Lemieux C (2002) Recent advances in randomized quasi-Monte Carlo
methods. In: Dror M et al. (eds) Modeling Uncertainty. Kluwer, pp 419–474.
"""

import logging
from typing import NamedTuple

import numpy as np

from beeoptics.replicates import REPLICATES, standard_error

log = logging.getLogger("beeoptics")

#: A catch's relative standard error asked by ``target: auto``, as a share of its class's Weber fraction ω:
#: the log of an estimated catch has variance about rse², and the receptor-noise-limited distance weighs each
#: class's log contrast by 1/ω² (Vorobyev & Osorio 1998), so rse ≤ ω/4 adds at most ω²/16 to a variance of
#: ω², a sixteenth, to every class's term and so to ΔS²'s expected value.
NOISE_FRACTION = 0.25

class Precision(NamedTuple):
    """What adaptive sampling asks (``trace.precision``): the relative standard error of each class's catch
    (a number, or one per class), the floor (a fraction of a white surface's catch), and the samples' bounds."""

    target: float | np.ndarray
    floor: float
    min_samples: int
    max_samples: int


def replicate_samples(samples):
    """The replicates of a bundle of ``samples`` samples, and each one's samples: (K, m).

    K is :data:`REPLICATES`, or ``samples`` where fewer; m = ⌊samples/K⌋, so
    that the K·m samples traced may fall short of ``samples`` by up to K − 1.
    One replicate gives no standard error.
    """
    replicates = max(1, min(REPLICATES, int(samples)))
    return replicates, int(samples) // replicates


def class_targets(target, weber):
    """The relative standard error asked of each class's catch, or None for fixed sampling.

    ``target``: a number, ``"auto"`` (:data:`NOISE_FRACTION` of each class's
    Weber fraction ``weber``) or None. ``auto`` for a receptor set without
    Weber fractions traces fixed samples, and says so.
    """
    if target != "auto":
        return target
    if weber is None:
        log.warning("trace.precision.target auto: the receptor set gives no receptor noise (Weber fractions) to "
                    "derive a precision from; tracing the fixed samples_per_receptor")
        return None
    return NOISE_FRACTION * np.asarray(weber, float)


def adaptive_samples(pilot, white, precision):
    """Each receptor's samples per replicate from its pilot: m₀ (r₀/target)², within the bounds asked.

    Parameters
    ----------
    pilot : ndarray, shape (n, K, k)
        Each pilot replicate's catches of k classes (of m₀ = ``precision.min_samples``/K samples each).
    white : ndarray, shape (n, k)
        Each receptor's catches of a white Lambertian surface under the scene's light: a catch below
        ``precision.floor`` times it is held to the target times that, not times itself.
    precision : Precision

    Returns
    -------
    ndarray of int, shape (n,)
    """
    k = pilot.shape[1]
    m0 = precision.min_samples // k
    target = np.asarray(precision.target, float)
    # A target per class of a set whose classes these are not (a flat-sensitivity catch): the strictest.
    target = target if target.size in (1, pilot.shape[2]) else target.min()
    scale = target * np.maximum(pilot.mean(axis=1), precision.floor * white)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(scale > 0.0, standard_error(pilot) / scale, 0.0)
    m = np.ceil(m0 * np.nan_to_num(ratio).max(axis=1) ** 2)
    return np.clip(m, m0, precision.max_samples // k).astype(np.int64)
