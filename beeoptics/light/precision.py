"""The precision of traced means: standard errors from independent replicates.

A receptor's samples are scrambled quasi-random points, correlated by
design, so the sample variance of its samples over their count misstates
its error (it overstates it where the points stratify well). Its
:data:`~beeoptics.light.batching.REPLICATES` replicates are independent
randomisations of one point set (:mod:`beeoptics.light.sampler`), each an
unbiased estimate of its own; their mean is the receptor's estimate and
their sample deviation over √K its standard error (Owen 1997; L'Ecuyer &
Lemieux 2002, §3).

References
----------
Owen AB (1997) Monte Carlo variance of scrambled net quadrature. SIAM J
Numer Anal 34:1884–1910.
L'Ecuyer P, Lemieux C (2002) Recent advances in randomized quasi-Monte Carlo
methods. In: Dror M et al. (eds) Modeling Uncertainty. Kluwer, pp 419–474.
"""

import numpy as np

from beeoptics.light.batching import REPLICATES

#: The 97.5th percentile of Student's t with REPLICATES − 1 = 7 degrees of freedom (Abramowitz & Stegun 1964,
#: table 26.10): a mean ± T95 standard errors of 8 replicates is its 95 % interval, where ± 1.96 covers only
#: 91 %, the standard error being itself an estimate of 7 degrees of freedom.
T95 = 2.3646


def standard_error(replicates, axis=1):
    """The standard error of the mean of independent replicate estimates along ``axis``.

    sd(ddof = 1)/√K of the K replicates: NaN where K = 1, which gives no
    spread to estimate it from.
    """
    replicates = np.asarray(replicates, float)
    k = replicates.shape[axis]
    if k < 2:
        return np.full(np.delete(replicates.shape, axis), np.nan)
    return replicates.std(axis=axis, ddof=1) / np.sqrt(k)
