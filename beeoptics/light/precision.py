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
(Stein 1945): a pilot of K replicates of m₀ samples estimates each cone's
errors, the covariance C of its classes' relative errors. What is asked
is a set of quadratic forms F of them, each to stay at most 1: a relative
standard error t of every class (C_cc/t², :func:`class_forms`), or the
receptor-noise-limited distances an error moves, chromatic and
achromatic (``auto``: :func:`beeoptics.vision.uncertainty.noise_forms`).
The mean e² of a form's tr(F C) over the cone's neighbourhood (itself and
its nearest on the eye, :func:`neighbourhoods`), the largest of the forms',
fixes its samples per replicate, m = m₀ e² inflated by a chi-square
quantile (:data:`PROBABILITY`), clipped to the bounds asked;
then K fresh replicates of m samples each (replicates K … 2K − 1, whose
random numbers none of the pilot's share) give the estimate and its
error, and the pilots are set aside. Pooling, as renderers filter their
error estimates over neighbouring pixels before deciding samples, gives e²
(K − 1) degrees of freedom per cone pooled rather than K − 1, and lets a
neighbour's pilot that met a rare bright blade speak for a cone whose own
pilot missed it. Because m is fixed before any of the estimate's samples
are drawn, each replicate is an unbiased estimate whatever m is, and so is
their mean. A sequential rule, adding samples until the error looks small
enough and keeping them all, is biased: an estimate that happens to read
low often also reads precise (a rare bright patch not yet met), and stops
there, low.

References
----------
Stein C (1945) A two-sample test for a linear hypothesis whose power is
independent of the variance. Ann Math Stat 16:243–258.
Greiner B, Ribi WA, Warrant EJ (2004) Retinal and optical adaptations for
nocturnal vision in the halictid bee Megalopta genalis. Cell Tissue Res
316:377–390.
Owen AB (1997) Monte Carlo variance of scrambled net quadrature. SIAM J
Numer Anal 34:1884–1910.
L'Ecuyer P, Lemieux C (2002) Recent advances in randomized quasi-Monte Carlo
methods. In: Dror M et al. (eds) Modeling Uncertainty. Kluwer, pp 419–474.
"""

from typing import NamedTuple

import numpy as np
from scipy.spatial import cKDTree
from scipy.special import chdtri

from beeoptics.replicates import REPLICATES, mean_covariance

#: The cones whose pilots set a cone's samples: itself and its six nearest, an ommatidium and its ring
#: of the hexagonal lattice. Measured for the worker pair in the meadow at a target of 3 % (the pilots of
#: eight seeds, each receptor's true error from 32 further replicates, errors taken to fall as 1/√N as
#: fixed sampling's 99th percentile does): of neighbourhoods of 1, 7, 9, 13 and 19 cones, 7 takes the
#: fewest samples to bring each class's 99th percentile to the target (1,331 a receptor, the pilot's
#: included; 1,806 for a cone's own pilot alone), pooled as the root mean square rather than the largest
#: (1,418) or the upper quartile (1,368).
NEIGHBOURHOOD = 7
#: The probability with which a cone's standard error is to meet the target, were its neighbourhood's
#: errors its own: the pooled r² has ν = (K − 1)·j degrees of freedom (K replicates, j cones), and is
#: inflated by ν/χ²_ν at 1 − this (Stein's 1945 t quantile, for a variance), 1.33 for 7 cones of 8
#: replicates. Measured as above, it brings each class's 99th percentile to 3.5 % (3.5 %, 3.3 %, 3.2 % in
#: UV, B and G; 4.0 %, 3.8 %, 3.7 % uninflated, at 791 samples) at 1,015 samples a receptor, where a cone's
#: own pilot needs 1,500 (819 uninflated reach 5.0 %, 4.6 %, 4.2 %).
PROBABILITY = 0.9
#: The length (m) that weighs as much as a radian of axis in telling cones apart (:func:`neighbourhoods`).
#: Adjacent facets of a worker's eye lie a facet's diameter apart (up to 20 µm, Greiner et al. 2004; 19.8
#: µm in the worker's receptors.csv) and their axes 1.5° to 3° (0.03 to 0.05 rad) apart, so within an eye
#: the axes decide; the worker pair's closest receptors of opposite eyes lie 1.5 mm apart (measured), as
#: far as 1.5 rad of axis, beyond any cone's six nearest.
ORIGIN_SCALE_M = 1.0e-3


class Precision(NamedTuple):
    """What adaptive sampling asks (``trace.precision``): ``forms``, quadratic forms of a catch's relative
    errors each of which is to stay at most 1 (:func:`class_forms`;
    :func:`beeoptics.vision.uncertainty.noise_forms`), the floor (a
    fraction of a white surface's catch), and the samples' bounds."""

    forms: np.ndarray
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


def class_forms(target, classes):
    """The forms asking a relative standard error ``target`` of each of ``classes`` catches: (classes,
    classes, classes), one a class, e_c e_cᵀ / target²."""
    return np.eye(classes)[:, :, None] * np.eye(classes)[:, None, :] / float(target) ** 2


def neighbourhoods(origins, axes):
    """Each cone's neighbourhood: the :data:`NEIGHBOURHOOD` cones nearest it in axis and origin, itself
    among them.

    Cones are near as their unit axes and their origins over
    :data:`ORIGIN_SCALE_M` are (the Euclidean distance of the six numbers):
    within an eye the axes decide, and a cone of the other eye, or of a pose
    of the head a millimetre or more away, is not among a cone's nearest.

    Parameters
    ----------
    origins : ndarray, shape (n, 3)
        The cones' apexes (m).
    axes : ndarray, shape (n, 3)
        Their unit axes.

    Returns
    -------
    ndarray of int, shape (n, min(n, NEIGHBOURHOOD))
        Indices of each cone's neighbourhood, nearest first.
    """
    points = np.hstack([axes, origins / ORIGIN_SCALE_M])
    k = max(1, min(len(points), NEIGHBOURHOOD))
    return cKDTree(points).query(points, k)[1].reshape(len(points), k)


def form_errors(replicates, scale, forms):
    """Each form's measure of the error of the replicates' mean: tr(F C), C the covariance of that mean
    relative to ``scale``.

    Parameters
    ----------
    replicates : ndarray, shape (n, K, k)
        K independent replicate catches of k classes.
    scale : ndarray, shape (n, k)
        What each error is relative to (the catches, or a floor under them); a scale of 0 counts no error.
    forms : ndarray, shape (f, k, k)
        :class:`Precision`'s forms.

    Returns
    -------
    ndarray, shape (n, f)
        Each is at most 1 where the error meets the form.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        inverse = np.where(scale > 0.0, 1.0 / scale, 0.0)
    covariance = np.nan_to_num(mean_covariance(replicates) * inverse[:, :, None] * inverse[:, None, :])
    return np.einsum("fab,nab->nf", forms, covariance)


def adaptive_samples(pilot, white, precision, near):
    """Each receptor's samples per replicate from the pilots of its neighbourhood: m₀ e² ν/χ²_ν, within the
    bounds asked.

    e² is, of the forms asked (:class:`Precision`), the largest of each
    form's mean over the neighbourhood of the pilots' tr(F C), C the
    covariance of a pilot's relative errors (over its K replicates, of its
    mean): the factor by which m₀ samples fall short. Each is a variance
    estimate of ν = (K − 1)·j degrees of freedom for j cones, and χ²_ν its
    quantile at 1 − :data:`PROBABILITY`, so that, were the neighbours'
    errors the receptor's own, its error would meet every form with that
    probability (a chi-square quantile in place of Stein's t).

    Parameters
    ----------
    pilot : ndarray, shape (n, K, k)
        Each pilot replicate's catches of k classes (of m₀ = ``precision.min_samples``/K samples each), of
        every cone in a neighbourhood.
    white : ndarray, shape (n, k)
        Each of those cones' catches of a white Lambertian surface under the scene's light: a catch below
        ``precision.floor`` times it has its error taken relative to that, not to itself.
    precision : Precision
    near : ndarray of int, shape (r, j)
        Each receptor's neighbourhood (:func:`neighbourhoods`), as rows of ``pilot``.

    Returns
    -------
    ndarray of int, shape (r,)
    """
    k = pilot.shape[1]
    m0 = precision.min_samples // k
    shortfall = form_errors(pilot, np.maximum(pilot.mean(axis=1), precision.floor * white), precision.forms)
    dof = (k - 1) * near.shape[1]
    m = np.ceil(m0 * dof / chdtri(dof, PROBABILITY) * shortfall[near].mean(axis=1).max(axis=1))
    return np.clip(m, m0, precision.max_samples // k).astype(np.int64)
