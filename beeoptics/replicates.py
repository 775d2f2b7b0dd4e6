"""Independent replicates: how many a traced mean is made of, its standard error, and its 95 % interval.

A receptor's samples are scrambled quasi-random points, correlated by
design, so their own sample variance misstates the error of their mean.
Independent randomisations of one point set (randomised quasi-Monte Carlo)
give K independent, unbiased replicate estimates, whose sample deviation
over √K is an unbiased error (Owen 1997; L'Ecuyer & Lemieux 2002). The
tracer makes them (:mod:`beeoptics.light.precision`); colour vision carries
them into every quantity derived from the catches
(:mod:`beeoptics.vision.uncertainty`).

References
----------
Owen AB (1997) Monte Carlo variance of scrambled net quadrature. SIAM J
Numer Anal 34:1884–1910.
L'Ecuyer P, Lemieux C (2002) Recent advances in randomized quasi-Monte Carlo
methods. In: Dror M et al. (eds) Modeling Uncertainty. Kluwer, pp 419–474.
Abramowitz M, Stegun IA (1964) Handbook of mathematical functions. National
Bureau of Standards, Washington.
"""

import numpy as np
from scipy.special import stdtrit

#: Independent replicates of each bundle, whose spread gives its standard error. Eight keeps each
#: replicate's share of the default 256 samples at 32, where the quasi-random points still stratify, while
#: the relative standard error of the standard error itself, about 1/√(2(K − 1)), is 27 %.
REPLICATES = 8
#: The 97.5th percentile of Student's t with REPLICATES − 1 = 7 degrees of freedom, 2.3646 (Abramowitz & Stegun
#: 1964, table 26.10; computed from REPLICATES, so that the two stay together): a mean ± T95 standard errors of
#: 8 replicates is its 95 % interval, where ± 1.96 covers only 91 %, the standard error being itself an
#: estimate of 7 degrees of freedom.
T95 = float(stdtrit(REPLICATES - 1, 0.975))


def standard_error(replicates, axis=1):
    """The standard error of the mean of independent replicate estimates along ``axis``.

    Parameters
    ----------
    replicates : array_like
        K independent replicate estimates along ``axis``, in any units.

    Returns
    -------
    ndarray
        sd(ddof = 1)/√K, in the units of ``replicates``: NaN where K = 1,
        which gives no spread to estimate it from, or where a replicate is NaN.
    """
    replicates = np.asarray(replicates, float)
    k = replicates.shape[axis]
    if k < 2:
        return np.full(np.delete(replicates.shape, axis), np.nan)
    return replicates.std(axis=axis, ddof=1) / np.sqrt(k)


def mean_covariance(replicates):
    """The covariance of the mean of independent replicate estimates of several quantities.

    Parameters
    ----------
    replicates : array_like, shape (n, K, k)
        K independent replicate estimates of k quantities, n times.

    Returns
    -------
    ndarray, shape (n, k, k)
        Their sample covariance (K − 1 in the denominator) over K, in the units of ``replicates`` squared;
        its diagonal is :func:`standard_error`'s square.
    """
    replicates = np.asarray(replicates, float)
    k = replicates.shape[1]
    deviation = replicates - replicates.mean(axis=1, keepdims=True)
    return np.einsum("nka,nkb->nab", deviation, deviation) / ((k - 1) * k)
