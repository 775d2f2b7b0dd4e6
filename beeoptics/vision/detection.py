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

Where the species' rule gives its angles by eye region, the angle applied
is the region's the target's centre falls in, by its elevation in the head
frame: for the honey bee Giurfa, Zaccardi & Vorobyev's (1999) frontal
4.0 ± 0.5°, ventral 7.1 ± 0.5° and dorsal 8.2 ± 0.6° for targets with both
contrasts (the bands and how their gaps are bridged are the receptor set's
data).

Every number comes with its error: each contrast its standard error from
the trace's replicate catches (:mod:`beeoptics.vision.uncertainty`), each
verdict a flag that noise could flip it, where a condition it needs lies
within the 95 % half-widths, in quadrature, of the contrast's error and the
threshold's own (:func:`could_flip`).

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
Giurfa M, Zaccardi G, Vorobyev M (1999) How bees detect coloured targets
using different regions of their compound eyes. J Comp Physiol A 185:591–600.
Chittka L (1992) The colour hexagon. J Comp Physiol A 170:533–543.
Vorobyev M, Osorio D (1998) Receptor noise as a determinant of colour
thresholds. Proc R Soc B 265:351–358.
"""

import numpy as np

from beeoptics.replicates import T95
from beeoptics.vision.colourspace import excitation, hexagon, rnl_distance
from beeoptics.vision.uncertainty import quadrature, spread_se

#: The z of a two-sided 95 % interval of a normal error, the normal's 97.5th percentile (Abramowitz & Stegun
#: 1964, table 26.1): a published threshold's ± (a standard error of many trials) spans ± Z95 of it.
Z95 = 1.959963984540054

#: The local background: receptors untouched by the target whose axes lie within this many of their
#: interommatidial angles of its edge (Δρ/2 beyond its angular radius, where a receptor stops seeing
#: it): two rings of the lattice, enough receptors to average, close enough to be its surround.
RING_DELTA_PHI = 2.0
#: A receptor "covered" by the target: its acceptance at least half filled.
COVERED_SHARE = 0.5
#: The columns of a detection row (see :func:`detect`): the target's geometry and the rule's angles where it
#: falls, then its contrasts with their standard errors, the verdicts with their flags and the receptor-level
#: counts.
GEOMETRY = ("angular_diameter_deg", "target_elevation_deg", "achromatic_min_angle_deg",
            "se_achromatic_min_angle_deg", "chromatic_min_angle_deg", "se_chromatic_min_angle_deg",
            "receptors_touched", "receptors_covered", "cover_max")
CONTRASTS = ("green_contrast", "green_dS", "hexagon_distance", "rnl_dS")
VERDICTS = ("achromatic_detectable", "achromatic_uncertain", "chromatic_detectable", "chromatic_uncertain",
            "receptors_green_above_threshold", "receptors_colour_above_threshold")
COLUMNS = (*GEOMETRY, *(c for name in CONTRASTS for c in (name, f"se_{name}")), *VERDICTS)
#: The column of each contrast measure a rule can name.
MEASURE_COLUMN = {"achromatic_rnl": "green_dS", "rnl": "rnl_dS", "hexagon": "hexagon_distance"}


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
    """The target's own catches from receptors that see it mixed with its background, (..., classes).

    Least squares over the touched receptors of q_i = c_i q_t + (1 − c_i) q_b:
    q_t = Σ c_i (q_i − (1 − c_i) q_b) / Σ c_i². ``catches`` (n, ..., classes)
    may hold replicates along further axes, ``background`` (..., classes)
    one for each. NaN if no receptor is touched.
    """
    c = np.asarray(cover, float)
    touched = c > 0.0
    if not touched.any():
        return np.full(np.shape(background), np.nan)
    q = np.asarray(catches, float)[touched]
    c = c[touched].reshape((-1,) + (1,) * (q.ndim - 1))
    return (c * (q - (1.0 - c) * background)).sum(0) / (c**2).sum()


def min_visual_angle(regions, elevation_deg):
    """The smallest visual angle a criterion needs where the target falls, and its standard error, degrees.

    Parameters
    ----------
    regions : Regions
        The criterion's region table (:class:`beeoptics.vision.receptorset.Regions`).
    elevation_deg : float
        The target centre's elevation in the head frame, from the horizontal plane, positive dorsal.
    """
    k = min(int(np.searchsorted(regions.upper_deg, elevation_deg)), len(regions.upper_deg) - 1)
    return float(regions.angle_deg[k]), float(regions.se_deg[k])


def could_flip(value, threshold, se_value, se_threshold):
    """Whether noise could flip ``value ≥ threshold``: they lie within their 95 % half-widths in quadrature.

    The value's half-width is T95 of its standard error (an error from the
    trace's eight replicates, of seven degrees of freedom: Student's t,
    :mod:`beeoptics.replicates`), the threshold's Z95 of its published ± (a
    normal error). An error not known (NaN, a contrast traced without
    replicates) counts as none, so that only the known errors flag; an
    unbounded one (inf) always flags.
    """
    se_value, se_threshold = (np.nan_to_num(se, posinf=np.inf) for se in (se_value, se_threshold))
    spread = quadrature(T95 * se_value, Z95 * se_threshold)
    return bool(abs(value - threshold) <= spread)


def _measure(measure, q, background, receptor_set):
    """One contrast measure of catches ``q`` (..., classes) against ``background`` (..., classes)."""
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


def contrasts(catches, cover, background_mask, receptor_set):
    """The target's contrasts against its local background, from the catches of the receptors round it.

    Parameters
    ----------
    catches : ndarray (n, ..., classes)
        The receptors' catches; replicates of them along further axes give a contrast for each.
    cover, background_mask : ndarray (n,)
        As :func:`detect`.

    Returns
    -------
    values : dict of ndarray (...)
        Each of :data:`CONTRASTS`.
    target, background : ndarray (..., classes)
        The target's unmixed catches and its local background's.
    """
    background = catches[background_mask].mean(0)
    target = unmix(catches, cover, background)
    k = receptor_set.achromatic
    values = {"green_contrast": excitation(target[..., k] / background[..., k]) - 0.5,
              **{column: _measure(m, target, background, receptor_set) for m, column in MEASURE_COLUMN.items()}}
    return values, target, background


def _verdict(conditions):
    """A verdict that needs every one of ``conditions`` (value, threshold, SE of each) to hold, 1 or 0, and
    whether noise could flip it, 1 or 0: whether it differs once each condition noise could flip is made
    to hold and once made to fail (:func:`could_flip`)."""
    holds = [value >= threshold for value, threshold, _, _ in conditions]
    flips = [could_flip(*c) for c in conditions]
    hopeful = all(h or f for h, f in zip(holds, flips))
    doubtful = all(h and not f for h, f in zip(holds, flips))
    return int(all(holds)), int(hopeful != doubtful)


def detect(catches, cover, background_mask, angular_diameter_deg, direction, receptor_set, replicate_catches=None):
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
        The target's angular diameter seen from the eye, from the geometry: exact, no error of its own.
    direction : array_like (3,)
        From the head to the target's centre, in the head frame, any length: which region of the
        rule's (:func:`min_visual_angle`) it falls in.
    receptor_set : ReceptorSet
        With its ``detection`` rule, or None: the contrasts are given, the verdicts are not (NaN).
    replicate_catches : ndarray (n, K, classes), optional
        The trace's K independent replicate estimates of ``catches``: with them, each contrast's
        standard error, the spread of the contrast over the replicates over √K (its local background
        and unmixing redone in each, for both come from the same noisy receptors).

    Returns
    -------
    dict
        ``angular_diameter_deg``; ``target_elevation_deg`` (head frame); the rule's smallest visual
        angle of each criterion where the target falls and its standard error
        (``achromatic_min_angle_deg``, ``se_achromatic_min_angle_deg``, ``chromatic_…``);
        ``receptors_touched`` (share > 0), ``receptors_covered`` (share ≥ :data:`COVERED_SHARE`),
        ``cover_max``; ``green_contrast`` (E_t − E_b of the achromatic class), ``green_dS`` (its Weber
        contrast over its noise), ``hexagon_distance``, ``rnl_dS``, each with its ``se_`` (NaN without
        replicates); ``achromatic_detectable`` and ``chromatic_detectable`` (1 or 0, NaN without a rule
        or a contrast the rule needs), each with ``_uncertain`` (1 where noise could flip it:
        :func:`_verdict`); and how many touched receptors the target makes reach the achromatic and
        the chromatic criterion's contrast against the background.
    """
    catches, cover = np.asarray(catches, float), np.asarray(cover, float)
    rule = receptor_set.detection
    alpha = float(angular_diameter_deg)
    row = dict.fromkeys(GEOMETRY, np.nan)
    row.update(angular_diameter_deg=alpha, receptors_touched=int((cover > 0).sum()),
               receptors_covered=int((cover >= COVERED_SHARE).sum()),
               cover_max=float(cover.max()) if cover.size else 0.0)
    d = np.asarray(direction, float)
    row["target_elevation_deg"] = float(np.degrees(np.arcsin(np.clip(d[2] / np.linalg.norm(d), -1.0, 1.0))))
    if rule is not None:
        for criterion in ("achromatic", "chromatic"):
            row[f"{criterion}_min_angle_deg"], row[f"se_{criterion}_min_angle_deg"] = min_visual_angle(
                rule[criterion]["regions"], row["target_elevation_deg"])
    nan = dict.fromkeys(COLUMNS[len(GEOMETRY):], np.nan)
    if not background_mask.any() or not (cover > 0).any():
        return {**row, **nan}
    values, target, background = contrasts(catches, cover, background_mask, receptor_set)
    if not (background > 0).all() or not (target > 0).all():
        return {**row, **nan}
    spread = None
    if replicate_catches is not None:
        # A replicate whose unmixed target catch is not positive has no logarithmic contrast (NaN): the noise
        # reaches the catch itself, so the error is unbounded (inf, spread_se's rule, which flags every verdict
        # that needs it), not unknown (NaN, which would count as none and call a verdict noise could flip certain).
        with np.errstate(invalid="ignore", divide="ignore"):
            spread = contrasts(np.asarray(replicate_catches, float), cover, background_mask, receptor_set)[0]
    for name in CONTRASTS:
        row[name] = float(values[name])
        row[f"se_{name}"] = np.nan if spread is None else float(spread_se(spread[name][None])[0])
    verdicts = dict.fromkeys(VERDICTS, np.nan)
    if rule is not None:
        achromatic, chromatic = rule["achromatic"], rule["chromatic"]
        green, colour = (MEASURE_COLUMN[c["contrast"]["measure"]] for c in (achromatic, chromatic))
        # The contrasts' thresholds come without published errors.
        green_ok = (row[green], achromatic["contrast"]["threshold"], row[f"se_{green}"], 0.0)
        colour_ok = (row[colour], chromatic["contrast"]["threshold"], row[f"se_{colour}"], 0.0)
        # Giurfa et al.'s angles for both contrasts are for targets with both; an achromatic one alone was not learnt.
        if np.isfinite(row[green]) and np.isfinite(row[colour]):
            verdicts["achromatic_detectable"], verdicts["achromatic_uncertain"] = _verdict([
                (alpha, row["achromatic_min_angle_deg"], 0.0, row["se_achromatic_min_angle_deg"]), green_ok,
                colour_ok])
        if np.isfinite(row[colour]):
            verdicts["chromatic_detectable"], verdicts["chromatic_uncertain"] = _verdict([
                (alpha, row["chromatic_min_angle_deg"], 0.0, row["se_chromatic_min_angle_deg"]), colour_ok])
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
