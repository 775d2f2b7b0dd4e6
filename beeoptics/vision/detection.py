"""Can the bee see it? Detection of a target by an eye, from the receptors it traced.

The published rule is Giurfa, Vorobyev, Kevan & Menzel's (1996): honey
bees detect a disc (with probability 0.6, choosing at a Y-maze's decision
point) once it subtends 5° if it gives the green receptors contrast as
well as colour contrast, and only from 15° if it gives colour contrast
alone. A species' receptor set states its rule as data (``detection:``,
:mod:`beeoptics.vision.receptorset`): each criterion's smallest visual angle
and the contrast it needs, as a measure and a threshold.

What the eye adds is how the target falls on its receptors. The tracer
records, for each receptor, the share of its acceptance whose samples met
the target first (:func:`beeoptics.light.integrator.trace_paths`,
``target``), leaves in front of it included. The target's local background
is what the receptors around it saw: those the target does not touch whose
axes lie within :data:`RING_DELTA_PHI` interommatidial angles of its edge.
Each touched receptor's catch is the mix c·q_t + (1 − c)·q_b of the target's
catch q_t and the background's q_b, c its share; q_t is the least-squares
solution of these mixes, the receptors weighted by their shares. The
contrasts are then those of the target against its local background, as
the receptors saw both under the scene's light, adapted to that background
(von Kries):

- the green (achromatic-class) contrast, E_t − E_b of the excitations
  E = q/(q + 1) (Giurfa et al.: "excitation difference in the green
  photoreceptors"; E_b = 0.5), and as a Weber contrast in receptor-noise
  units, |ln(q_t/q_b)|/e;
- the colour distances: the hexagon's (Chittka 1992) and the RNL ΔS
  (Vorobyev & Osorio 1998), where the species has them.

Beside the rule, a receptor-level measure: how many of the receptors the
target touches it makes differ from the background by the criterion's
threshold (each receptor's catch as the target's share of it makes it,
c·q_t + (1 − c)·q_b, so that neither the background's texture nor the
trace's noise counts), so that a user can see where the rule, made for
discs at a decision point, and the eye agree.

References
----------
Giurfa M, Vorobyev M, Kevan P, Menzel R (1996) Detection of coloured
stimuli by honeybees: minimum visual angles and receptor specific
contrasts. J Comp Physiol A 178:699–709.
Chittka L (1992) The colour hexagon. J Comp Physiol A 170:533–543.
Vorobyev M, Osorio D (1998) Receptor noise as a determinant of colour
thresholds. Proc R Soc B 265:351–358.
"""

import numpy as np

from beeoptics.vision.colourspace import excitation, hexagon, rnl_distance

#: The local background: receptors untouched by the target whose axes lie within this many of their
#: interommatidial angles of its edge (Δρ/2 beyond its angular radius, where a receptor stops seeing
#: it): two rings of the lattice, enough receptors to average, close enough to be its surround.
RING_DELTA_PHI = 2.0
#: A receptor "covered" by the target: its acceptance at least half filled.
COVERED_SHARE = 0.5
#: The columns of a detection row (see :func:`detect`).
COLUMNS = ("angular_diameter_deg", "receptors_touched", "receptors_covered", "cover_max", "green_contrast",
           "green_dS", "hexagon_distance", "rnl_dS", "achromatic_detectable", "chromatic_detectable",
           "receptors_green_above_threshold", "receptors_colour_above_threshold")


def local_background(axes, cover, target_direction, angular_radius_deg, delta_rho_deg, delta_phi_deg):
    """Which receptors are the target's local background: untouched ones close around it, (n,) bool.

    Parameters
    ----------
    axes : ndarray (n, 3)
        The receptors' axes, unit vectors, in the frame of ``target_direction``.
    cover : ndarray (n,)
        Each receptor's share of its acceptance the target fills.
    target_direction : ndarray (3,) or (n, 3)
        The unit direction to the target's centre, or from each receptor.
    angular_radius_deg : float
        The target's angular radius seen from the eye.
    """
    cosine = (np.asarray(axes, float) * np.asarray(target_direction, float)).sum(-1)
    angle = np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0)))
    edge = angular_radius_deg + 0.5 * np.asarray(delta_rho_deg, float)
    return (cover == 0.0) & (angle <= edge + RING_DELTA_PHI * np.asarray(delta_phi_deg, float))


def unmix(catches, cover, background):
    """The target's own catches from receptors that see it mixed with its background, (classes,).

    Least squares over the touched receptors of q_i = c_i q_t + (1 − c_i) q_b:
    q_t = Σ c_i (q_i − (1 − c_i) q_b) / Σ c_i². NaN if no receptor is touched.
    """
    c = np.asarray(cover, float)
    touched = c > 0.0
    if not touched.any():
        return np.full(np.shape(background), np.nan)
    c, q = c[touched, None], np.asarray(catches, float)[touched]
    return (c * (q - (1.0 - c) * background)).sum(0) / (c**2).sum()


def _measure(measure, q, background, receptor_set):
    """One contrast measure of catches ``q`` (..., classes) against ``background`` (classes,)."""
    adapted = q / background
    colour = receptor_set.chromatic
    if measure == "achromatic_rnl":
        k = receptor_set.achromatic
        where = np.flatnonzero(colour == k)
        if receptor_set.weber is None or not where.size:
            return np.full(adapted.shape[:-1], np.nan)
        return np.abs(np.log(adapted[..., k])) / receptor_set.weber[where[0]]
    if measure == "rnl":
        if receptor_set.weber is None:
            return np.full(adapted.shape[:-1], np.nan)
        return rnl_distance(adapted[..., colour], np.ones(len(colour)), receptor_set.weber)
    if "hexagon" not in receptor_set.spaces:
        return np.full(adapted.shape[:-1], np.nan)
    return np.hypot(*np.moveaxis(hexagon(excitation(adapted[..., colour])), -1, 0))


def detect(catches, cover, background_mask, angular_diameter_deg, receptor_set):
    """Whether, and how, an eye detects a target: one row of :data:`COLUMNS`.

    Parameters
    ----------
    catches : ndarray (n, classes)
        The quantum catches of the receptors near the target, every class of ``receptor_set``.
    cover : ndarray (n,)
        The share of each one's acceptance the target fills (from the trace).
    background_mask : ndarray (n,) of bool
        The target's local background (:func:`local_background`).
    angular_diameter_deg : float
        The target's angular diameter seen from the eye.
    receptor_set : ReceptorSet
        With its ``detection`` rule, or None: the contrasts are given, the verdicts are not (NaN).

    Returns
    -------
    dict
        ``angular_diameter_deg``; ``receptors_touched`` (share > 0),
        ``receptors_covered`` (share ≥ :data:`COVERED_SHARE`), ``cover_max``;
        ``green_contrast`` (E_t − E_b of the achromatic class), ``green_dS``
        (its Weber contrast over its noise), ``hexagon_distance``, ``rnl_dS``;
        ``achromatic_detectable`` and ``chromatic_detectable`` (1 or 0, NaN
        without a rule or a contrast the rule needs); and how many touched
        receptors the target makes reach the achromatic and the chromatic
        criterion's contrast against the background.
    """
    catches, cover = np.asarray(catches, float), np.asarray(cover, float)
    row = {"angular_diameter_deg": float(angular_diameter_deg), "receptors_touched": int((cover > 0).sum()),
           "receptors_covered": int((cover >= COVERED_SHARE).sum()),
           "cover_max": float(cover.max()) if cover.size else 0.0}
    nan = {k: np.nan for k in COLUMNS[4:]}
    if not background_mask.any() or not (cover > 0).any():
        return {**row, **nan}
    background = catches[background_mask].mean(0)
    target = unmix(catches, cover, background)
    if not (background > 0).all() or not (target > 0).all():
        return {**row, **nan}
    k = receptor_set.achromatic
    row["green_contrast"] = float(excitation(target[k] / background[k]) - 0.5)
    row["green_dS"] = float(_measure("achromatic_rnl", target, background, receptor_set))
    row["hexagon_distance"] = float(_measure("hexagon", target, background, receptor_set))
    row["rnl_dS"] = float(_measure("rnl", target, background, receptor_set))
    rule = receptor_set.detection
    verdicts = {"achromatic_detectable": np.nan, "chromatic_detectable": np.nan,
                "receptors_green_above_threshold": np.nan, "receptors_colour_above_threshold": np.nan}
    if rule is not None:
        achromatic, chromatic = rule["achromatic"], rule["chromatic"]
        green = _measure(achromatic["contrast"]["measure"], target, background, receptor_set)
        colour = _measure(chromatic["contrast"]["measure"], target, background, receptor_set)
        green_ok = green >= achromatic["contrast"]["threshold"]
        colour_ok = colour >= chromatic["contrast"]["threshold"]
        alpha = float(angular_diameter_deg)
        # Giurfa et al.'s 5° is for targets with both contrasts; an achromatic one alone was not learnt.
        if np.isfinite(green) and np.isfinite(colour):
            verdicts["achromatic_detectable"] = int(alpha >= achromatic["min_visual_angle_deg"] and green_ok
                                                    and colour_ok)
        if np.isfinite(colour):
            verdicts["chromatic_detectable"] = int(alpha >= chromatic["min_visual_angle_deg"] and colour_ok)
        # Each touched receptor as the flower's share of it makes it, c q_t + (1 − c) q_b: the flower's
        # own effect, without the background's texture or the trace's noise.
        c = cover[cover > 0, None]
        seen = c * target + (1.0 - c) * background
        verdicts["receptors_green_above_threshold"] = int(np.sum(
            _measure(achromatic["contrast"]["measure"], seen, background, receptor_set)
            >= achromatic["contrast"]["threshold"]))
        verdicts["receptors_colour_above_threshold"] = int(np.sum(
            _measure(chromatic["contrast"]["measure"], seen, background, receptor_set)
            >= chromatic["contrast"]["threshold"]))
    return {**row, **verdicts}
