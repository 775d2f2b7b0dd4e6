"""Adaptation: the background a bee's receptors adapt to, for von Kries scaling.

Colour spaces (:mod:`beeoptics.vision.colourspace`) divide each receptor's
catch by its catch from the adapting background (von Kries), so that the
background sits at the centre of every space. The catches compared are
radiance catches (a receptor's catch over its acceptance solid angle), so
that each receptor adapts through its own acceptance. The background is
either the scene itself, the mean radiance catch of the receptors that
have the class, or a named surface, given by the radiance it sends to the
eye.

References
----------
von Kries J (1905) Die Gesichtsempfindungen. In Nagel W (ed) Handbuch der
Physiologie des Menschen 3:109–282. Vieweg, Braunschweig.
"""

import numpy as np

from beeoptics.vision.catches import quantum_catches


def background_catches(seen, sensitivities, wavelengths, background_radiance=None):
    """Catches (3,) of the adapting background.

    Parameters
    ----------
    seen : ndarray (n, classes)
        The catches of every receptor from its mean radiance; NaN where its
        ommatidium lacks the class.
    sensitivities : ndarray (n_wavelengths, 3)
    wavelengths : ndarray
        nm.
    background_radiance : ndarray (n_wavelengths,), optional
        The radiance of a named background surface; without it, the scene
        is the background and its catch the mean of ``seen`` over the
        receptors that have the class.

    Returns
    -------
    ndarray (classes,)
        In the units of ``seen``; radiance catches, so that the acceptance
        solid angle cancels in every ratio.
    """
    if background_radiance is None:
        return np.nanmean(seen, axis=0)
    return quantum_catches(np.asarray(background_radiance)[None], sensitivities, wavelengths)[0]
