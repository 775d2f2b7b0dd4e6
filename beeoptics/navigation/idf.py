"""Image-difference functions: how a view differs from a remembered one, over headings (rIDF) and places (tIDF).

A view here is what an eye's own receptors catch, class by class, not a
camera's pixels. Its difference from a reference view is the root mean
square over receptors of the two views' difference (Zeil, Hofmann & Chahl
2003, who took the r.m.s. pixel difference of panoramic images; Stürzl &
Zeil 2007; Philippides et al. 2011; Baddeley et al. 2012), in each of
these signals:

- each receptor class (UV, B, G for a bee), the catch over the view's own
  mean catch of that class over its receptors (a von Kries adaptation of
  the whole view, as ``responses.csv``'s ``scene`` background adapts): a
  light uniformly brighter or dimmer leaves it unchanged, as Stürzl & Zeil
  (2007) found normalised images keep the IDF robust to changing light;
- ``achromatic``: von Helversen's brightness (the set's overall sensitivity,
  :func:`beeoptics.vision.receptorset.brightness_weights`), so normalised;
- ``UV-G``: the UV–green contrast (UV − G)/(UV + G) of the normalised catches,
  which separates terrestrial objects from the sky by one fixed threshold
  in any daylight (Möller 2002), where the set has both classes.

The rIDF is the difference at every heading from a reference view, whose
minimum points back to the reference heading; the tIDF the difference at
every place of a grid at one heading, whose basin about the reference place
is the snapshot's catchment area (Zeil et al. 2003). Both are computed from
environment maps (:mod:`beeoptics.navigation.envmap`), one a place.

References
----------
Zeil J, Hofmann MI, Chahl JS (2003) Catchment areas of panoramic snapshots
in outdoor scenes. J Opt Soc Am A 20:450–469.
Stürzl W, Zeil J (2007) Depth, contrast and view-based homing in outdoor
scenes. Biol Cybern 96:519–531.
Philippides A, Baddeley B, Cheng K, Graham P (2011) How might ants use
panoramic views for route navigation? J Exp Biol 214:445–451.
Baddeley B, Graham P, Husbands P, Philippides A (2012) A model of ant route
navigation driven by scene familiarity. PLoS Comput Biol 8:e1002336.
Möller R (2002) Insects could exploit UV–green contrast for landmark
navigation. J Theor Biol 214:619–631.
"""

import numpy as np

from beeoptics.navigation.envmap import eye_weights, map_catches, resampled_catches
from beeoptics.vision.receptorset import brightness_weights

#: The opponent signal's classes, by the receptor set's names: Möller's (2002) UV–green contrast.
OPPONENT = ("UV", "G")
#: The achromatic signal's name.
ACHROMATIC = "achromatic"


def signals(catches, eye, wavelengths_nm, curves):
    """A view's signals, each normalised as the module says: {name: (receptors,)}.

    Parameters
    ----------
    catches : ndarray (receptors, k)
        The catches of the eye's classes (photons m⁻² s⁻¹), as :func:`~beeoptics.navigation.envmap.resampled_catches`
        or :func:`beeoptics.look` give them.
    eye : beeoptics.Eye
    wavelengths_nm, curves : ndarray
        The spectral grid (nm) and the classes' curves on it, (w, k), for the brightness's weights.
    """
    classes = list(eye.receptor_set.classes)
    # The view's own mean over its receptors, class by class: its von Kries adaptation to itself.
    normalised = catches / np.nanmean(catches, axis=0)
    out = {c: normalised[:, k] for k, c in enumerate(classes)}
    weights = brightness_weights(eye.receptor_set, wavelengths_nm, curves)
    if weights is not None:
        brightness = catches @ weights
        out[ACHROMATIC] = brightness / np.nanmean(brightness)
    if set(OPPONENT) <= set(classes):
        uv, g = (normalised[:, classes.index(c)] for c in OPPONENT)
        out["-".join(OPPONENT)] = (uv - g) / (uv + g)
    return out


def image_difference(view, reference):
    """The root mean square over receptors of two views' difference, per signal: {name: float}.

    ``view`` and ``reference`` are :func:`signals` of the same eye; receptors
    that caught nothing in either (NaN) are left out.
    """
    return {name: float(np.sqrt(np.nanmean((view[name] - reference[name]) ** 2))) for name in reference}


def ridf(env, eye, reference, headings_deg=np.arange(360.0), *, pitch_deg=0.0, roll_deg=0.0, weights=None):
    """The rotational image-difference function at a map's place: {signal: (headings,)}.

    Parameters
    ----------
    env : EnvironmentMap
    eye : beeoptics.Eye
    reference : dict
        The reference view's :func:`signals`.
    headings_deg : ndarray
        Headings, degrees: 1° steps by default, each a whole number of the
        map's heading steps (one resampling matrix for all).
    pitch_deg, roll_deg : float
        The head's pitch and roll, degrees.
    weights : scipy.sparse matrix, optional
        :func:`~beeoptics.navigation.envmap.eye_weights` at this pitch and
        roll: it depends on the grid alone, not on the place, so one serves
        every map of the same spacing and heading step.
    """
    weights = eye_weights(env, eye, pitch_deg=pitch_deg, roll_deg=roll_deg) if weights is None else weights
    q = map_catches(env, eye)
    return _stacked(_difference(env, eye, reference, (h, pitch_deg, roll_deg), weights, q) for h in headings_deg)


def tidf(envs, eye, reference, heading_deg=0.0, *, pitch_deg=0.0, roll_deg=0.0, weights=None):
    """The translational image-difference function over places: {signal: (places,)}.

    Parameters
    ----------
    envs : sequence of EnvironmentMap
        A map at each place, all of the same spacing and heading step (one resampling matrix serves all).
    eye : beeoptics.Eye
    reference : dict
        The reference view's :func:`signals`.
    heading_deg, pitch_deg, roll_deg : float
        The head's pose at every place, degrees.
    weights : scipy.sparse matrix, optional
        :func:`~beeoptics.navigation.envmap.eye_weights` at this pitch and roll.
    """
    weights = eye_weights(envs[0], eye, pitch_deg=pitch_deg, roll_deg=roll_deg) if weights is None else weights
    return _stacked(_difference(env, eye, reference, (heading_deg, pitch_deg, roll_deg), weights) for env in envs)


def _difference(env, eye, reference, pose, weights, q=None):
    """The view's difference from the reference at a map's place in a pose (heading, pitch, roll; degrees)."""
    catches, _ = resampled_catches(env, eye, heading_deg=pose[0], pitch_deg=pose[1], roll_deg=pose[2],
                                   weights=weights, q=q)
    return image_difference(signals(catches, eye, env.wavelengths_nm, env.curves), reference)


def _stacked(differences):
    """Differences, one {signal: float} a view, as {signal: (views,)}."""
    differences = list(differences)
    return {name: np.array([d[name] for d in differences]) for name in differences[0]}


def ridf_minimum(headings_deg, differences):
    """The heading of an rIDF's minimum (degrees), its depth and its width.

    The depth is the median of the rIDF over the headings less its minimum,
    over that median (0: no dip, 1: the minimum is zero); the width the
    angle, degrees, about the minimum over which the rIDF stays below half
    way from its minimum to its median (its full width at half depth).
    Our own summaries of the dip's shape, which the cited papers show
    rather than number.
    """
    headings_deg, differences = np.asarray(headings_deg, float), np.asarray(differences, float)
    best = int(np.argmin(differences))
    median = float(np.median(differences))
    half = (differences[best] + median) / 2.0
    below = differences < half
    # Out from the minimum both ways, round the circle, while below half depth.
    n = len(differences)
    ahead = np.argmin(np.roll(below, -best)[1:]) if not below.all() else n
    behind = np.argmin(np.roll(below, -best)[::-1][:-1]) if not below.all() else n
    depth = (median - differences[best]) / median if median > 0.0 else 0.0
    return float(headings_deg[best]), float(depth), float(min((ahead + behind + 1) * 360.0 / n, 360.0))
