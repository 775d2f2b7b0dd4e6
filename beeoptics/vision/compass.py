"""The sky compass: the dorsal rim's polarisation-opponent units, and the solar azimuth read from them.

Each ommatidium of the dorsal rim area holds UV receptors with microvilli in
two orthogonal sets (Schinz 1975; Labhart & Meyer 1999). A polarisation-
opponent unit (POL unit; Labhart 1988, crickets; Labhart & Meyer 2002)
compares the two: here, as in the compass model of Gkanias et al. (2019),
by their normalised difference

    r_POL = (R_∥ − R_⊥) / (R_∥ + R_⊥),

R_∥ and R_⊥ the catches of the two sets (:mod:`beeoptics.vision.polarisation`),
which for ideal analysers is p cos 2(φ − ψ), independent of brightness.

Read-out: the bee holds a map of the sky's pattern of electric vectors
(Rossel & Wehner 1982), and knows the sun's elevation from the time of
day. Here that map is Rayleigh's pattern: for each candidate solar azimuth
(every :data:`STEP_DEG` degrees about the head's vertical, at the sun's
elevation in the head frame) the POL units' responses expected of ideal
analysers, r_i(A) = p_i cos 2(φ_i − ψ_i), are correlated with the
responses measured; the best-matching azimuth, refined by a parabola
through its neighbours, is the estimate, and the correlation its
confidence. Nothing is fitted to the scene: the error is the estimate less
the true solar azimuth, heading by heading. (Gkanias et al.'s 2019 linear
read-out of the units, a first Fourier component over their azimuths,
was tried on the worker's dorsal rim, whose units lie in two arcs along
the eyes' dorsal margins: it confused the sun with the anti-sun at most
headings, since the units' responses are almost symmetric under a half
turn; the template uses the sky's asymmetry in degree, which that sum
nearly cancels.)

References
----------
Labhart T (1988) Polarization-opponent interneurons in the insect visual
system. Nature 331:435–437.
Labhart T, Meyer EP (2002) Neural mechanisms in insect navigation:
polarization compass and odometer. Curr Opin Neurobiol 12:707–714.
Labhart T, Meyer EP (1999) Microsc Res Tech 47:368–379.
Schinz RH (1975) Cell Tissue Res 162:23–34.
Gkanias E, Risse B, Mangan M, Webb B (2019) From skylight input to
behavioural output: a computational model of the insect polarised light
compass. PLoS Comput Biol 15:e1007123.
Rossel S, Wehner R (1982) The bee's map of the e-vector pattern in the
sky. Proc Natl Acad Sci USA 79:4451–4455.
"""

import numpy as np

from beeoptics.headframe import microvillar_angle
from beeoptics.vision.polarisation import receptor_catch

#: The read-out's grid of candidate solar azimuths, degrees.
STEP_DEG = 1.0


def pol_responses(stokes_uv, microvilli_deg, ps):
    """POL units' responses (n, ...) from the dorsal rim's UV Stokes catches (n, ..., 3), head frame."""
    microvilli = np.asarray(microvilli_deg, float).reshape((-1,) + (1,) * (np.ndim(stokes_uv) - 2))
    along = receptor_catch(stokes_uv, microvilli, ps)
    across = receptor_catch(stokes_uv, microvilli + 90.0, ps)
    return (along - across) / (along + across)


def candidate_suns(sun_elevation_deg):
    """Unit vectors (candidates, 3) towards the sun at its elevation for each candidate azimuth, head frame,
    and those azimuths (candidates,), degrees."""
    azimuth = np.arange(0.0, 360.0, STEP_DEG)
    h, a = np.radians(sun_elevation_deg), np.radians(azimuth)
    return np.column_stack([np.cos(h) * np.cos(a), np.cos(h) * np.sin(a), np.full(len(a), np.sin(h))]), azimuth


def expected_responses(degree, e_vectors, axes_head, microvilli_deg):
    """The POL units' responses (candidates, n) as ideal analysers, under skies of each candidate sun.

    ``degree`` (candidates, n) and ``e_vectors`` (candidates, n, 3): the
    sky's polarisation along the units' axes ``axes_head`` (n, 3, head
    frame) for each candidate (Rayleigh's, for the read-out's template);
    ``microvilli_deg`` (n,).
    """
    k, n = np.shape(degree)
    angle = microvillar_angle(np.tile(axes_head, (k, 1)), np.reshape(e_vectors, (k * n, 3))).reshape(k, n)
    return degree * np.cos(2.0 * np.radians(microvilli_deg - angle))


def read_out(pol, expected, azimuth_deg):
    """The solar azimuth (degrees) whose ``expected`` responses (candidates, n) best match ``pol`` (n,), and the
    correlation there."""
    measured = pol - pol.mean()
    template = expected - expected.mean(axis=1, keepdims=True)
    score = template @ measured / np.maximum(np.linalg.norm(template, axis=1) * np.linalg.norm(measured), 1e-300)
    k = int(np.argmax(score))
    before, here, after = score[k - 1], score[k], score[(k + 1) % len(score)]
    curvature = before - 2.0 * here + after
    shift = 0.5 * (before - after) / curvature if curvature < 0.0 else 0.0
    return float(wrap_deg(azimuth_deg[k] + shift * STEP_DEG)), float(here)


def wrap_deg(angle_deg):
    """Angles in degrees wrapped into [−180, 180)."""
    return (np.asarray(angle_deg) + 180.0) % 360.0 - 180.0
