"""Receptors' polarisation sensitivity: what a receptor of given microvilli catches of polarised light.

A receptor whose microvilli lie at angle φ absorbs light polarised along
them PS times as strongly as light polarised across them. Of light with
intensity catch I, degree p and angle ψ it catches

    R = I (1 + d p cos 2(φ − ψ)),   d = (PS − 1)/(PS + 1),

which, with Q = I p cos 2ψ and U = I p sin 2ψ, is R = I + d (Q cos 2φ + U sin 2φ):
linear in the Stokes catches, so each class's catch of Q and U is its
sensitivity integrated against the traced spectral Q and U, like I
(:mod:`beeoptics.vision.catches`). An ideal analyser (PS = ∞, d = 1)
follows Malus's law, R = 2 I cos²(φ − ψ) for fully polarised light.

Polarisation sensitivity by eye region (``PS``), as modelled by default:

- the main retina: PS = 1. Its rhabdoms twist through 180° along their
  length (Collins §2.1; Wehner et al. 1975), "so that their polarization
  sensitivity is almost abolished" (Labhart 1980, in the words of Horváth et
  al. 2002); the short ninth cell, which keeps some, is not modelled.
- the dorsal rim area's UV receptors: PS = 6.6 (:data:`DORSAL_RIM_PS`),
  Labhart's (1980) measurement as quoted with that source in
  public analysis code of skylight polarisation vision ("polarization
  sensitivity as defined in Labhart, 1980 is 6.6 for honeybees"); the paper
  itself was not readable here, so the figure is second-hand and should be
  checked against its text. The config's ``polarisation.dorsal_rim_ps``
  takes another value, or ``ideal`` analysers (PS = ∞), as in the compass
  model of Gkanias et al. (2019). The compass read-out
  (:mod:`beeoptics.vision.compass`) does not depend on it.

Angles are those of :mod:`beeoptics.eye.dorsalrim`: about a receptor's
axis, from the projection of the head's dorsal direction towards its
anterior one, degrees in [0, 180).

References
----------
Labhart T (1980) Specialized photoreceptors at the dorsal rim of the
honeybee's compound eye: polarizational and angular sensitivity. J Comp
Physiol 141:19–30.
Horváth G, Gál J, Labhart T, Wehner R (2002) Does reflection polarization
by plants influence colour perception in insects? J Exp Biol 205:3281–3298
(the quotation above).
Wehner R, Bernard GD, Geiger E (1975) Twisted and non-twisted rhabdoms and
their significance for polarization detection in the bee. J Comp Physiol
104:225–245.
Gkanias E, Risse B, Mangan M, Webb B (2019) PLoS Comput Biol 15:e1007123.
"""

import numpy as np

from beeoptics.io.validation import config_default

#: The dorsal rim's UV receptors' polarisation sensitivity (Labhart 1980, as quoted: see above): the
#: config schema's ``polarisation.dorsal_rim_ps``.
DORSAL_RIM_PS = config_default("polarisation.dorsal_rim_ps")


def analyser_ps(setting):
    """A polarisation sensitivity from a config: a number, or ``"ideal"`` (infinite)."""
    return np.inf if setting == "ideal" else float(setting)


def analyser_efficiency(ps):
    """d = (PS − 1)/(PS + 1) of a receptor's polarisation sensitivity PS (``inf``: an ideal analyser, d = 1)."""
    ps = np.asarray(ps, float)
    finite = np.isfinite(ps)
    return np.where(finite, (np.where(finite, ps, 1.0) - 1.0) / (np.where(finite, ps, 1.0) + 1.0), 1.0)


def receptor_catch(stokes, microvilli_deg, ps):
    """What receptors of microvilli at ``microvilli_deg`` and sensitivity ``ps`` catch of Stokes catches (..., 3)."""
    phi = 2.0 * np.radians(microvilli_deg)
    d = analyser_efficiency(ps)
    return stokes[..., 0] + d * (stokes[..., 1] * np.cos(phi) + stokes[..., 2] * np.sin(phi))


def degree_and_angle(stokes):
    """The degree of linear polarisation and its angle (degrees in [0, 180)) of Stokes vectors (..., 3)."""
    stokes = np.asarray(stokes, float)
    with np.errstate(invalid="ignore", divide="ignore"):
        degree = np.hypot(stokes[..., 1], stokes[..., 2]) / stokes[..., 0]
    return degree, np.degrees(0.5 * np.arctan2(stokes[..., 2], stokes[..., 1])) % 180.0


def head_frame_stokes(stokes, axes_head):
    """Stokes vectors (n, ..., 3) from the tracer's frame about each receptor's axis into the eye's.

    The tracer measures angles from the projection of the head's dorsal
    direction towards d × dorsal (:mod:`beeoptics.light.mueller`); the eye
    from the same direction towards the projection of the anterior one. The
    two agree or are mirror images, by receptor: where they are mirrored, U
    changes sign.
    """
    axes_head = np.asarray(axes_head, float)
    dorsal = np.array([0.0, 0.0, 1.0]) - axes_head[:, 2:3] * axes_head
    # d × dorsal is perpendicular to the axis and to the dorsal direction, so along
    # the projection of the anterior direction, or against it.
    mirrored = np.cross(axes_head, dorsal)[:, 0] < 0.0
    out = np.array(stokes, float, copy=True)
    out[mirrored, ..., 2] *= -1.0
    return out
