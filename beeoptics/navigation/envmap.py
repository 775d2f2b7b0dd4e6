"""Environment maps: the spectral radiance over the whole sphere at a place, traced once, and any eye at any
heading, pitch and roll there resampled from it.

Turning an eye about its head changes only which directions its receptors
look in, so a place needs one trace, not one per heading. The map is traced
by the receptors' own tracer (:func:`beeoptics.tracing.trace_cones`:
its sampling, light, replicates and standard errors) as a synthetic eye whose
receptors look along the directions of a grid on the sphere, each with a
small Gaussian acceptance of its own. A receptor's catch is then the
acceptance-weighted mean of the map over its cone: a sparse matrix per eye
and pose (:func:`resampling_matrix`), its rows the receptors, its columns
the map's directions.

What a map keeps. The receptors' catches are linear in the radiance, so a
map keeps, of each direction's traced spectrum, only its catches in each
distinct receptor set of the eyes it was traced for (:class:`SetCatches`,
by the set's name; their standard errors from the trace's replicates),
taken before the spectrum is dropped: a few numbers a direction, not one a
wavelength (the worker's map 22 MB, not 190 MB, at 5 nm). The spectrum is
kept only on request, for eyes of other sets or curves later.

The grid is one of rings of constant elevation, h apart, each holding a
whole multiple of 360/(heading step) directions evenly in azimuth, as many
as keep them at most h apart along the ring, with each direction's solid
angle (its ring's band, 2π Δsin(elevation), shared among them) weighting
it. Turning the head by a whole heading step about the vertical then maps
the grid onto itself, ring by ring, so that every heading of an eye is one
matrix, built once for its pitch and roll, applied to the map's directions
taken in a turned order (:func:`turn_order`): an rIDF's 360 headings cost
one neighbour search, not 360. An equal-area grid without that symmetry
(a Fibonacci lattice, González 2010; HEALPix, a dependency besides) needs
the search at every heading, some seconds for the worker on this machine;
the rings oversample the poles instead (directions closer than h along a
ring where a ring's count is rounded up): for the worker 250,920 directions
at h = 0.48°, 40 % more than the 4π/h² of an equal-area grid (González
2010, for the Fibonacci lattice), traced once. A cube map's texels span solid angles differing by
3√3 = 5.2 between a face's corner and its centre, and has the symmetry only
for quarter turns.

The rule. A map for an eye has s ≤ Δρ₂/:data:`SPACINGS_PER_DELTA_RHO`,
Δρ₂ the eye's acceptance angles (full width at half maximum) at percentile
:data:`DELTA_RHO_PERCENTILE` (the 2nd), s being the rings' spacing h; each map
direction accepts a Gaussian of Δρ_map = :data:`MAP_DELTA_RHO_SPACINGS` × s.
Not the smallest Δρ: the bumblebees' (Δρ = Δφ receptor by receptor, Taylor
et al. 2019's assumption) reach 0.18–0.27° at a few dozen facets of each
eye, against medians of 1.48–1.57°, and by the smallest a map would be 9–21
million directions. Those are the facet angles' artefacts at the lattice's
edge, where a facet's neighbours lie on one side and the cornea's normals
flatten: of each shipped Bombus eye's receptors below its 2nd percentile,
92–98 % lie on the edge (their 12 nearest facets' centroid off them by over a
quarter of their spacing, as 8–10 % of all facets are), 69 % for the
smallest bee (BT_77973), against 0–1 % of the worker's, whose Δρ (Snyder's
model) spans 1.90–2.57°. The receptors below 4 s (:func:`clamped`) are
resampled as receptors of Δρ = 4 s, the narrowest the map resolves
(:func:`resolved_delta_rho`): their catches are of a wider cone than their
own, counted where the views are written (``catchment.csv``'s ``clamped``)
and measured against directly traced ones in the README ("Views for
navigation").

The map is thus the radiance blurred by Δρ_map, and a receptor resampled
from it with its own Gaussian would see a Gaussian of √(Δρ² + Δρ_map²)
(variances of Gaussians add): for s = Δρ₂/4 up to 12 % wider than its own
(√(1 + ¼) = 1.118), which takes 20 % off the catch contrast of a target
smaller than Δρ (a Gaussian's peak falls as 1/Δρ²) and widens every edge by
12 %. The resampling kernel is therefore narrowed to
Δρ_k = √(Δρ² − Δρ_map²), so that the map's blur and the kernel's make the
receptor's own acceptance exactly. What remains is (i) the kernel's sum over
grid points, each weighted by its solid angle, standing for its integral:
the kernel is at least √(16 − 4)/2.355 = 1.47 spacings wide (σ), and the
weights are normalised, so a uniform map is returned exactly; a horizon seen by
Δρ = 4 s, 5 s and 6 s comes back as the exact Gaussian edge to within
1.3 × 10⁻⁴ of the step (tests/test_navigation.py, which allows 10⁻³; the
kernel of Δρ itself is 0.027 off); (ii) the kernel cut at
:data:`KERNEL_CUT_SIGMAS` σ, beyond which a Gaussian in two dimensions holds
exp(−4²/2) = 3.4 × 10⁻⁴ of its weight; (iii) the tangent plane's Gaussians
taken on the sphere, a relative error of order σ², 10⁻³ at Δρ = 3°.

The head's centre. A map is traced from one point, the place c, and a
receptor's facet lies a millimetre or so from it (the worker's within
1.6 mm): a receptor at o (from c) with axis d sees the point p = o + t d, t
its distance along d to the first surface, which from c lies in the
direction u = (p − c)/|p − c|. That parallax, at most 1.6 mm/t, is 0.9° at
10 cm, half the worker's smallest Δρ, and shows above the noise near the head
(below). It is kept: the map holds, beside the radiance, each direction's
nearness ν = 1/(distance to the first surface from c), 0 where the sky is
met (one ray a direction), and each receptor's kernel is turned from d to u.
Since p lies 1/ν(u) from c, u − d = ν(u) o⊥ exactly in the part
perpendicular to d (o⊥ the facet's offset across d; the sine of the turn):
u is a fixed point of u = d + ν(u) o⊥. It is taken at ν(d), the map's
nearness under the receptor's kernel about d: the depth from c along d
stands for the depth from o along d. One step of the fixed point more,
ν(d + ν(d) o⊥), did not pay: with it the test below came out further from
the direct trace (rms 1.37 against 1.24 of the errors at one pose), as did
kernels rebuilt about the exactly turned axis again and again (1.32 and
1.30 after one and two steps). The kernel's turn is taken to first order,
K(d + ν o⊥) ≈ K(d) + ν ∂K/∂(ν o⊥) (:func:`parallax_matrix`: a second
sparse matrix of the same entries, fixed as the first for every heading),
so that every heading still costs sums over fixed matrices; it came near
kernels rebuilt about the turned axes (rms 1.26 against 1.24, 2.07 against
1.88, 1.83 against 1.52 at the test's three poses, a map of 32 samples),
which would cost a neighbour search at every heading (1.7 s for the worker). Neglected: the
second order, (ν|o⊥|/σ_k)²/2 of the view's curvature across the kernel,
which grows as the turn passes the kernel's σ_k (for the worker's narrowest,
0.70°, nearer than 13 cm), and the one nearness a receptor takes for its
whole cone, so that a cone across a near edge and the far ground behind it
turns as a whole by their mean. The test (tests/test_navigation.py: the
test eye 2.5 cm from a ball) finds the differences from the direct trace
of the receptors that see the ball within 1.49 of their errors (rms), and
3.12 without the parallax. For the worker at the meadow's own place (35 cm
up, a map of 8 samples against 256 traced directly; README, "Views for
navigation") the differences over their errors have an rms of 1.94 over all
receptors with the parallax kept, 2.69 from the head's centre alone; 7.03
and 9.80 for the 320 whose facet's axis meets grass within 10 cm, 1.0–1.4
against 1.2–2.7 in bands of distance beyond. Kernels rebuilt about the
exactly turned axes gave 1.84 and 5.90: what remains near the head is
mostly the one nearness a cone takes, and what a facet sees past a blade's
edge that the centre does not.

References
----------
González Á (2010) Measurement of areas on a sphere using Fibonacci and
latitude–longitude lattices. Math Geosci 42:49–64 (the equal-area lattice
the rings are weighed against).
Snyder AW (1977) Acuity of compound eyes: physical limitations and design.
J Comp Physiol 116:161–182 (the Gaussian acceptance, :mod:`beeoptics.eye.optics`).
"""

import os
from functools import lru_cache
from typing import NamedTuple

import numpy as np
from scipy.sparse import csr_matrix, diags
from scipy.spatial import cKDTree

from beeoptics.eye.optics import acceptance_solid_angle
from beeoptics.headframe import head_rotation
from beeoptics.io.atomic import atomic_path
from beeoptics.io.errors import InputError
from beeoptics.io.validation import CONFIG_SCHEMA, validate_config
from beeoptics.light.batching import TraceSettings
from beeoptics.light.sampler import STREAMS
from beeoptics.light.sensors import cone_sigma
from beeoptics.raycasting import first_hits
from beeoptics.replicates import standard_error
from beeoptics.tracing import cone_catches, trace_cones
from beeoptics.vision.catches import quantum_catches
from beeoptics.vision.receptorset import DEFAULT_CURVES, curves

#: The grid's spacing is at most the eye's Δρ at :data:`DELTA_RHO_PERCENTILE` over this (the rule above).
SPACINGS_PER_DELTA_RHO = 4
#: The percentile of an eye's Δρ that sets its map's spacing: the receptors below it are nearly all on the
#: lattice's edge (the module's "rule"), and are resampled with their acceptance widened to the narrowest the
#: map resolves, :data:`SPACINGS_PER_DELTA_RHO` spacings (:func:`resolved_delta_rho`).
DELTA_RHO_PERCENTILE = 2.0
#: Each map direction's acceptance angle (FWHM) in grid spacings: wide enough that the map is sampled well
#: (its Gaussian's spectrum at the grid's frequency 1/s is exp(−(2π·2/2.355)²/2) < 10⁻⁶), narrow enough that
#: the resampling kernel keeps √(1 − (2/4)²) = 87 % of the smallest receptor's width.
MAP_DELTA_RHO_SPACINGS = 2.0
#: The resampling kernel's cut, in its σ: the Gaussian's weight beyond it, exp(−c²/2), is 3.4 × 10⁻⁴.
KERNEL_CUT_SIGMAS = 4.0
#: Map directions traced at once: bounds the replicates' memory (directions × 8 × wavelengths × 8 bytes,
#: some 170 MB at 81 wavelengths) without changing a number (every direction draws its own stream).
CHUNK = 1 << 15
#: The arrays a map file holds, beside its scalars and each receptor set's :data:`SET_ARRAYS`.
ARRAYS = ("position_m", "wavelengths_nm", "nearness")
#: A receptor set's arrays in a map file, each ``{array}.{set}`` for every set named in its ``sets``.
SET_ARRAYS = ("q", "q_se", "curves")
#: Its scalars.
SCALARS = ("spacing_deg", "heading_step_deg", "samples", "depth", "seed")


#: The heading step, degrees, whose whole multiples turn a map's grid onto itself by default: the rIDF's 1°.
HEADING_STEP_DEG = 1.0


class Grid(NamedTuple):
    """A map's directions: rings of constant elevation, each a whole multiple of the heading steps in a turn.

    Attributes
    ----------
    directions : ndarray (n, 3)
        Unit vectors in the scene's frame, ring after ring from the nadir, each ring from its first azimuth on.
    solid_angle_sr : ndarray (n,)
        The solid angle each stands for: its ring's band over the ring's directions (summing to 4π).
    counts : ndarray of int (rings,)
        The directions of each ring.
    """

    directions: np.ndarray
    solid_angle_sr: np.ndarray
    counts: np.ndarray


class SetCatches(NamedTuple):
    """A map's radiance catches in one receptor set's classes (:attr:`EnvironmentMap.catches`).

    Attributes
    ----------
    q, q_se : ndarray (n, k)
        The radiance catches of the map's directions in the set's k classes
        (photons m⁻² s⁻¹ sr⁻¹: :func:`beeoptics.vision.catches.quantum_catches`
        of the radiance) and their standard errors over the trace's replicates.
    curves : ndarray (w, k)
        The receptor curves they were taken with, each of area 1 nm.
    """

    q: np.ndarray
    q_se: np.ndarray
    curves: np.ndarray


class EnvironmentMap(NamedTuple):
    """The spectral radiance over the sphere at a place, on a grid of rings (:func:`ring_grid`).

    Attributes
    ----------
    position_m : ndarray (3,)
        The place, m in the scene's frame (its height included).
    spacing_deg : float
        The rings' spacing h, degrees.
    heading_step_deg : float
        The turn, degrees, whose whole multiples map the grid onto itself.
    wavelengths_nm : ndarray (w,)
    radiance : ndarray (n, w) or None
        Each direction's mean spectral radiance over its acceptance of
        Δρ_map = :data:`MAP_DELTA_RHO_SPACINGS` h, W m⁻² sr⁻¹ nm⁻¹, where it
        was asked for (:func:`environment_map`'s ``radiance``: some 190 MB a
        map for the worker at 5 nm); None by default.
    catches : dict of str to SetCatches
        Its radiance catches in each receptor set it was traced for, by the
        set's name, taken from the traced radiance before it is dropped (a
        few classes each: some 6 MB a set for the worker's map).
    nearness : ndarray (n,)
        1/m: the reciprocal of each direction's distance from the place to
        the first surface, 0 where none is met (the sky): the parallax of a
        facet off the place (the module's "head's centre").
    samples, depth, seed : int
        The samples of each direction, the paths' scattering events and the seed it was traced with.
    source : str
        Its file, or "environment_map" for one traced in memory (named by errors).
    """

    position_m: np.ndarray
    spacing_deg: float
    heading_step_deg: float
    wavelengths_nm: np.ndarray
    radiance: np.ndarray
    catches: dict
    nearness: np.ndarray
    samples: int
    depth: int
    seed: int
    source: str = "environment_map"

    @property
    def grid(self):
        """Its directions and their solid angles (:func:`ring_grid`)."""
        return ring_grid(self.spacing_deg, self.heading_step_deg)

    @property
    def delta_rho_deg(self):
        """Each map direction's acceptance angle, FWHM, degrees."""
        return MAP_DELTA_RHO_SPACINGS * self.spacing_deg

    @property
    def resolved_deg(self):
        """The narrowest acceptance angle, FWHM, degrees, the map resolves: :data:`SPACINGS_PER_DELTA_RHO`
        spacings (the module's "rule"), less a rounding's worth, so that a receptor of exactly that width counts
        as resolved."""
        return SPACINGS_PER_DELTA_RHO * self.spacing_deg * (1.0 - 1e-9)


@lru_cache(maxsize=4)
def ring_grid(spacing_deg, heading_step_deg=HEADING_STEP_DEG):
    """The grid of rings: 180/h rings at elevations h apart from pole to pole, each holding the least whole
    multiple of 360/``heading_step_deg`` directions that keeps them at most h apart along it.

    Parameters
    ----------
    spacing_deg : float
        h, degrees; 180/h a whole number.
    heading_step_deg : float
        Degrees; 360 over it a whole number.

    Returns
    -------
    Grid
    """
    elevation, counts = ring_counts(spacing_deg, heading_step_deg)
    h = np.radians(spacing_deg)
    ring = np.repeat(np.arange(len(counts)), counts)
    j = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    # Odd rings half a step round, so that neighbouring rings' directions interleave.
    azimuth = 2.0 * np.pi * (j + 0.5 * (ring % 2)) / counts[ring]
    e = elevation[ring]
    band = 2.0 * np.pi * (np.sin(elevation + h / 2) - np.sin(elevation - h / 2))
    grid = Grid(np.column_stack([np.cos(e) * np.cos(azimuth), np.cos(e) * np.sin(azimuth), np.sin(e)]),
                (band / counts)[ring], counts)
    # Kept (a map's every look asks for it): read-only, so that no caller changes another's grid.
    for array in grid:
        array.flags.writeable = False
    return grid


def ring_counts(spacing_deg, heading_step_deg=HEADING_STEP_DEG):
    """The rings' elevations, radians, and their directions' counts (:func:`ring_grid`'s), (rings,) each."""
    rings, turn = round(180.0 / spacing_deg), round(360.0 / heading_step_deg)
    h = np.radians(spacing_deg)
    elevation = -np.pi / 2 + (np.arange(rings) + 0.5) * h
    return elevation, turn * np.ceil(np.cos(elevation) * 2.0 * np.pi / (turn * h) - 1e-9).astype(np.int64)


def map_spacing_deg(delta_rho_deg):
    """The rule's spacing, degrees, for receptors of acceptance angles ``delta_rho_deg`` (FWHM, degrees): at
    most their value at percentile :data:`DELTA_RHO_PERCENTILE` over :data:`SPACINGS_PER_DELTA_RHO`, and 180°
    over it a whole number."""
    return 180.0 / np.ceil(180.0 * SPACINGS_PER_DELTA_RHO / rule_delta_rho_deg(delta_rho_deg))


def rule_delta_rho_deg(delta_rho_deg):
    """The Δρ, degrees, that sets the rule's spacing for receptors of ``delta_rho_deg``: their
    value at percentile :data:`DELTA_RHO_PERCENTILE` (linearly interpolated)."""
    return float(np.percentile(delta_rho_deg, DELTA_RHO_PERCENTILE))


def resolved_delta_rho(env, delta_rho_deg):
    """The acceptance angles, FWHM, degrees, that receptors of ``delta_rho_deg`` are resampled with: their own,
    or the narrowest the map resolves, :data:`SPACINGS_PER_DELTA_RHO` spacings, where theirs is narrower (the
    module's "rule": the receptors :func:`clamped`)."""
    return np.maximum(np.asarray(delta_rho_deg, float), SPACINGS_PER_DELTA_RHO * env.spacing_deg)


def clamped(env, delta_rho_deg):
    """Which receptors of ``delta_rho_deg`` (FWHM, degrees) are narrower than the map resolves, and so resampled
    wider than their own acceptance (:func:`resolved_delta_rho`): a boolean array of their shape."""
    return np.asarray(delta_rho_deg, float) < env.resolved_deg


def turn_order(grid, heading_deg):
    """The map's directions in the order that turns it by ``heading_deg`` (a whole multiple of its heading
    step), (n,): ``W @ q[turn_order(grid, ψ)]`` is what ``W``'s receptors see turned by ψ about the vertical."""
    starts = np.cumsum(grid.counts) - grid.counts
    ring = np.repeat(np.arange(len(grid.counts)), grid.counts)
    # A turn by ψ moves every ring by ψ/360 of its count, a whole number of its directions.
    shift = np.rint(heading_deg / 360.0 * grid.counts).astype(np.int64)
    j = np.arange(len(ring)) - starts[ring]
    return starts[ring] + (j + shift[ring]) % grid.counts[ring]


def environment_map(scene, position_m, eyes, *, spacing_deg=None, heading_step_deg=HEADING_STEP_DEG, samples=8,
                    depth=None, seed=None, sensitivities=DEFAULT_CURVES, radiance=False, threads=None):
    """Trace the spectral radiance over the whole sphere at a place, once, for resampling to an eye at any pose.

    Parameters
    ----------
    scene : beeoptics.Scene
        A loaded scene (:func:`beeoptics.load_scene`).
    position_m : array_like (3,)
        The place, m (the head's centre).
    eyes : beeoptics.Eye or sequence of beeoptics.Eye
        The eyes it is for: the finest of their Δρ's 2nd percentiles sets the
        spacing by the rule (:func:`map_spacing_deg`), and the map keeps its catches and their
        standard errors in each of their distinct receptor sets.
    spacing_deg : float, optional
        A finer spacing than the rule's, degrees, made finer still where
        180° over it is not a whole number.
    heading_step_deg : float
        The turn, degrees, whose whole multiples are resampled without a
        search of their own (360 over it a whole number).
    samples : int
        Samples of each map direction (as eight replicates where eight or
        more). A receptor resampled from ~4πσ_k²/h² directions (27 for the
        worker's smallest Δρ, 47 at its median; more near the poles) has the
        precision of some that many times more samples traced directly.
    depth, seed : int, optional
        Scattering events per path and the seed: the configuration's by default.
    sensitivities : str
        The receptor curves (:func:`beeoptics.vision.receptorset.curves`).
    radiance : bool
        Keep the spectral radiance too (an eye of another receptor set, or
        other curves, can then be resampled from the map; with the errors a
        gap).
    threads : int, optional
        Threads tracing; all cores by default. The map is the same for any.

    Returns
    -------
    EnvironmentMap
    """
    eyes = [eyes] if hasattr(eyes, "receptor_set") else list(eyes)
    rule = min(map_spacing_deg(e.table.delta_rho_deg) for e in eyes)
    if spacing_deg is not None and not 0.0 < spacing_deg <= rule:
        raise InputError("environment_map", "spacing_deg", f"{spacing_deg!r} is not above 0 and at most the "
                         f"rule's {rule:.4g}° (the eyes' Δρ at percentile {DELTA_RHO_PERCENTILE:g} over "
                         f"{SPACINGS_PER_DELTA_RHO})")
    spacing = rule if spacing_deg is None else 180.0 / np.ceil(180.0 / spacing_deg)
    turn = 360.0 / heading_step_deg if heading_step_deg > 0.0 else 0.0
    if turn < 1.0 or abs(turn - round(turn)) > 1e-9:
        raise InputError("environment_map", "heading_step_deg", f"{heading_step_deg!r}: 360° over it must be a "
                         "whole number")
    try:
        position = np.asarray(position_m, float)
    except (TypeError, ValueError):
        position = np.full(0, np.nan)
    if position.shape != (3,) or not np.isfinite(position).all():
        raise InputError("environment_map", "position_m", f"{position_m!r} is not three finite numbers (m)")
    given = {k: v for k, v in (("samples_per_receptor", samples), ("depth", depth), ("seed", seed)) if v is not None}
    trace = validate_config({"trace": given}, CONFIG_SCHEMA, source="environment_map", folders=False)["trace"]
    settings = TraceSettings.from_config(trace, threads or os.cpu_count())
    wl = scene.wavelengths_nm
    # Each distinct receptor set once, by name: its curves side by side with the others', traced in one pass.
    sets = {e.receptor_set.name: curves(e.receptor_set, wl, sensitivities) for e in eyes}
    sens = np.hstack(list(sets.values()))
    # Each direction draws a random stream of its own, so that a map is the same for any chunking: at most the
    # tracer's streams (a spacing under 0.05°: the finest bumblebee receptors' Δρ over four).
    n = int(ring_counts(spacing, heading_step_deg)[1].sum())
    if n > STREAMS:
        raise InputError("environment_map", "spacing_deg", f"{spacing:.3g}° apart makes {n:,} directions, more than "
                         f"the tracer's {STREAMS:,} random streams (one each): the eyes' Δρ is too fine for one map")
    axes = ring_grid(spacing, heading_step_deg).directions
    origins = np.broadcast_to(position, (n, 3))
    delta_rho = np.full(n, MAP_DELTA_RHO_SPACINGS * spacing)
    streams = np.arange(n, dtype=np.int64)
    spectra, q, q_se = [], [], []
    for first in range(0, n, CHUNK):
        last = min(first + CHUNK, n)
        errors = {}
        # The replicates kept as traced: of their errors the map keeps the catches' alone, not the radiance's.
        chunk = trace_cones(scene.scene, origins, axes, delta_rho, streams, first, last, settings, len(wl),
                            rs=scene.raycasting, sensitivities=(wl, sens), errors=errors, deferred=True)[0]
        # The catches from the chunk's radiance before it goes (unless asked for): a few classes, not w wavelengths.
        q.append(quantum_catches(chunk, sens, wl))
        spectra += [chunk] if radiance else []
        # The replicates' catches are over the direction's acceptance solid angle: per steradian here.
        omega = acceptance_solid_angle(delta_rho[first:last])
        q_se.append(standard_error(cone_catches(errors["replicates"], omega, (wl, sens))) / omega[:, None])
    # One ray a direction from the place: the distance to the first surface, whose reciprocal turns a facet's
    # kernel (sky: none, no parallax).
    distance = first_hits(scene.raycasting, np.column_stack([origins, axes]).astype(np.float32))["t_hit"]
    nearness = np.where(np.isfinite(distance), 1.0 / np.maximum(distance, 1e-9), 0.0)
    split = np.cumsum([c.shape[1] for c in sets.values()])[:-1]
    catches = {name: SetCatches(a, e, c) for name, a, e, c in zip(sets, np.split(np.concatenate(q), split, axis=1),
                                                                   np.split(np.concatenate(q_se), split, axis=1),
                                                                   sets.values())}
    return EnvironmentMap(position, spacing, float(heading_step_deg), wl, np.concatenate(spectra) if radiance else None,
                          catches, nearness, settings.samples, settings.depth, settings.seed)


def resampling_matrix(env, axes, delta_rho_deg):
    """The weights of the map's directions in each receptor's acceptance: a sparse matrix (receptors, n).

    Row i holds the Gaussian kernel of Δρ_k = √(Δρ_i² − Δρ_map²) about
    axis i times each direction's solid angle, at every map direction within
    :data:`KERNEL_CUT_SIGMAS` of its σ, normalised to sum to one, so that the
    map's blur and the kernel make the receptor's acceptance of Δρ_i (the
    module's rule).

    Parameters
    ----------
    env : EnvironmentMap
    axes : ndarray (receptors, 3)
        Unit receptor axes in the scene's frame.
    delta_rho_deg : ndarray (receptors,)
        Their acceptance angles, FWHM, degrees.

    Returns
    -------
    scipy.sparse.csr_matrix
    """
    delta_rho = np.broadcast_to(np.asarray(delta_rho_deg, float), (len(axes),))
    rule = rule_delta_rho_deg(delta_rho) if len(delta_rho) else np.inf
    if rule < env.resolved_deg:
        raise InputError(env.source, "spacing_deg", f"{env.spacing_deg:.3g}° is too coarse for receptors of Δρ "
                         f"{rule:.3g}° at percentile {DELTA_RHO_PERCENTILE:g}: trace the map at most "
                         f"Δρ/{SPACINGS_PER_DELTA_RHO} apart")
    grid = env.grid
    tree = cKDTree(env.grid.directions)
    sigma = kernel_sigma(env, delta_rho)
    # Chords of the cut's angles: the tree measures straight lines between unit vectors.
    cut = 2.0 * np.sin(KERNEL_CUT_SIGMAS * sigma / 2.0)
    # The nearest k of every axis at once (one dense query, where a list per receptor took seconds for an eye):
    # k a third above the directions a cap of the widest cut holds on average, and the receptors that have
    # all k within their cut (the rings crowd towards the poles) asked again for twice as many, until none has.
    grid_n = len(grid.directions)
    k = int(4.0 / 3.0 * grid_n * (1.0 - np.cos(KERNEL_CUT_SIGMAS * sigma.max(initial=0.0))) / 2.0) + 16
    rows, data, cols, asked = [], [], [], np.arange(len(axes))
    while len(asked):
        k = min(k, grid_n)
        chord, columns = tree.query(axes[asked], k=k, distance_upper_bound=cut[asked].max(), workers=-1)
        inside = chord <= cut[asked, None]
        done = ~inside[:, -1] | (k == grid_n)
        inside, columns, chord = inside[done], np.where(inside, columns, 0)[done], chord[done]
        theta = 2.0 * np.arcsin(np.minimum(np.where(inside, chord, 0.0) / 2.0, 1.0))
        weights = np.where(inside, np.exp(-0.5 * (theta / sigma[asked[done], None]) ** 2)
                           * grid.solid_angle_sr[columns], 0.0)
        rows.append(np.repeat(asked[done], k))
        data.append((weights / weights.sum(axis=1, keepdims=True)).ravel())
        cols.append(columns.ravel())
        asked, k = asked[~done], 2 * k
    # Entries beyond the cut are zero, and dropped.
    matrix = csr_matrix((np.concatenate(data), (np.concatenate(rows), np.concatenate(cols))),
                        shape=(len(axes), grid_n))
    matrix.eliminate_zeros()
    return matrix


def kernel_sigma(env, delta_rho_deg):
    """The resampling kernel's σ, radians, for receptors of ``delta_rho_deg`` (FWHM, degrees): narrowed by the
    map's own blur, those narrower than the map resolves widened to it first (the module's rule)."""
    return np.sqrt(cone_sigma(resolved_delta_rho(env, delta_rho_deg)) ** 2 - cone_sigma(env.delta_rho_deg) ** 2)


def parallax_matrix(env, kernel, axes, delta_rho_deg, offsets_m):
    """The kernels' change as their centres turn towards their facets' offsets: G of ``kernel``'s entries, with
    the kernel about d + ε o⊥ equal to ``kernel`` + ε G to first order in ε (1/m).

    The normalised Gaussian weight w_j = K_j Ω_j / Σ K Ω of direction x_j
    changes by w_j (a_j − Σ_l w_l a_l)/σ_k² as its centre moves by ε o⊥,
    a_j = x_j · o⊥ (m, o⊥ ⟂ d) in the tangent plane: a uniform map does not
    change (each row sums to zero).

    Parameters
    ----------
    env : EnvironmentMap
    kernel : scipy.sparse.csr_matrix (receptors, n)
        :func:`resampling_matrix` of ``axes`` and ``delta_rho_deg``.
    axes : ndarray (receptors, 3)
        Unit receptor axes in the scene's frame.
    delta_rho_deg : ndarray (receptors,)
        Their acceptance angles, FWHM, degrees.
    offsets_m : ndarray (receptors, 3)
        Their facets' places from the map's place (the head's centre), m, in the scene's frame.

    Returns
    -------
    scipy.sparse.csr_matrix
        Of ``kernel``'s indices, m (times a nearness, 1/m: a change of weight).
    """
    rows = np.repeat(np.arange(kernel.shape[0]), np.diff(kernel.indptr))
    across = offsets_m - np.sum(offsets_m * axes, axis=1)[:, None] * axes
    a = np.einsum("ij,ij->i", env.grid.directions[kernel.indices], across[rows])
    mean = np.bincount(rows, kernel.data * a, minlength=kernel.shape[0])
    sigma = np.broadcast_to(kernel_sigma(env, np.asarray(delta_rho_deg, float)), (kernel.shape[0],))
    return csr_matrix((kernel.data * (a - mean[rows]) / sigma[rows] ** 2, kernel.indices, kernel.indptr),
                      shape=kernel.shape)


class Weights(NamedTuple):
    """An eye's resampling at a map's place in a pose (:func:`eye_weights`).

    Attributes
    ----------
    kernel : scipy.sparse.csr_matrix (receptors, n)
        Each receptor's kernel about its axis (:func:`resampling_matrix`).
    parallax : scipy.sparse.csr_matrix (receptors, n)
        Its change as the kernel turns towards the facet's offset (:func:`parallax_matrix`), m.
    """

    kernel: csr_matrix
    parallax: csr_matrix


def eye_weights(env, eye, *, pitch_deg=0.0, roll_deg=0.0, heading_deg=0.0):
    """The eye's resampling matrices (:class:`Weights`) at the map's place in a pose: built once, they serve
    every heading a whole number of the map's heading steps from ``heading_deg`` (:func:`resampled_catches`)."""
    # As a scene turns and places a head's receptors (beeoptics.light.scene.receptors_in_world), from the place.
    rotation = head_rotation(heading_deg, pitch_deg, roll_deg)
    axes, offsets = eye.table.axis @ rotation.T, 1e-3 * eye.table.position @ rotation.T
    kernel = resampling_matrix(env, axes, eye.table.delta_rho_deg)
    return Weights(kernel, parallax_matrix(env, kernel, axes, eye.table.delta_rho_deg, offsets))


def parallax_corrected(sums, turns):
    """Catches with the facets' offsets kept: the kernels' sums turned by the nearness along their axes.

    Parameters
    ----------
    sums : ndarray (..., k + 1)
        :class:`Weights`' ``kernel`` times the map's radiance catches in k
        classes and its nearness (last), receptor by receptor.
    turns : ndarray (..., k)
        Its ``parallax`` times the catches.

    Returns
    -------
    ndarray (..., k)
        The catches of kernels turned from d by ν o⊥, ν the map's nearness
        under the kernel about d (the module's "head's centre").
    """
    return sums[..., :-1] + sums[..., -1:] * turns


def resampled_catches(env, eye, *, heading_deg=0.0, pitch_deg=0.0, roll_deg=0.0, weights=None, q=None):
    """The eye's catches at the map's place in a pose, resampled from the map: as :func:`beeoptics.look` gives them,
    each receptor looking from its own facet (the module's "head's centre").

    Parameters
    ----------
    env : EnvironmentMap
    eye : beeoptics.Eye
    heading_deg, pitch_deg, roll_deg : float
        The head's heading (from +x towards +y), pitch (nose up) and roll, degrees.
    weights : Weights, optional
        :func:`eye_weights` of the eye at this pitch and roll (heading 0),
        once for every heading that is a whole number of the map's heading
        steps; a heading between steps gets a matrix of its own.
    q : (ndarray, ndarray), optional
        The map's radiance catches and their standard errors in the eye's
        classes, (n, k) each, from :func:`map_catches`, once for many poses.

    Returns
    -------
    catches : ndarray (receptors, k)
        Each class's quantum catch, photons m⁻² s⁻¹ (``responses.csv``'s:
        the radiance catch times the receptor's acceptance solid angle).
    se : ndarray (receptors, k)
        Its standard error: √(Σ_j w_ij² se_j²), the map's directions being
        traced independently; NaN where the map's curves are not the eye's.
    """
    steps = heading_deg / env.heading_step_deg
    whole = np.floor(steps + 1e-9)
    if weights is None or steps - whole > 1e-9:
        # Between steps: the matrix of this heading's remainder, the whole steps turned as the grid.
        weights = eye_weights(env, eye, pitch_deg=pitch_deg, roll_deg=roll_deg,
                              heading_deg=(steps - whole) * env.heading_step_deg)
    order = turn_order(env.grid, whole * env.heading_step_deg)
    q, q_se = map_catches(env, eye) if q is None else q
    sums = weights.kernel @ np.column_stack([q[order], env.nearness[order]])
    catches = parallax_corrected(sums, weights.parallax @ q[order])
    # The turned kernel's own weights, w + ν G, for the errors.
    turned = weights.kernel + diags(sums[:, -1]) @ weights.parallax
    omega = acceptance_solid_angle(eye.table.delta_rho_deg)[:, None]
    return omega * catches, omega * np.sqrt(turned.multiply(turned) @ (q_se[order] ** 2))


def map_catches(env, eye, sensitivities=DEFAULT_CURVES):
    """The map's radiance catches in the eye's classes and their standard errors, (n, k) each.

    They are the map's own of the eye's receptor set (by its name) where the
    map was traced for it with the same curves; else they follow from the
    map's spectral radiance, where it was kept, with NaN errors (a gap: the
    trace's replicates were reduced to the map's sets); else the map is
    refused in one line.
    """
    name = eye.receptor_set.name
    sens = curves(eye.receptor_set, env.wavelengths_nm, sensitivities)
    own = env.catches.get(name)
    if own is not None and own.curves.shape == sens.shape and np.array_equal(own.curves, sens):
        return own.q, own.q_se
    if env.radiance is None:
        raise InputError(env.source, "sets", f"the map holds the catches of {', '.join(env.catches)} only, not of "
                         f"the eye's set {name} with curves {sensitivities} (it was traced without its spectral "
                         "radiance): trace it again for this eye")
    return quantum_catches(env.radiance, sens, env.wavelengths_nm), np.full((len(env.radiance), sens.shape[1]), np.nan)


def write_map(path, env):
    """Write a map to an NPZ file (whole or not at all): its arrays, the names of its receptor sets (``sets``)
    and each one's catches, their errors and curves (``q.{set}``, ``q_se.{set}``, ``curves.{set}``), its
    grid's directions and their solid angles (``directions``, ``solid_angle_sr``, as :func:`ring_grid` makes
    them again from the spacing and heading step), its samples, depth and seed; and its spectral radiance where
    it holds it (the worker's map at 5 nm is some 20 MB without it, 190 MB with it)."""
    grid = env.grid
    spectrum = {"radiance": env.radiance} if env.radiance is not None else {}
    per_set = {f"{k}.{name}": getattr(c, k) for name, c in env.catches.items() for k in SET_ARRAYS}
    with atomic_path(path) as tmp:
        np.savez(tmp, **{k: getattr(env, k) for k in ARRAYS}, sets=np.array(list(env.catches), dtype=str),
                 **per_set, **spectrum, directions=grid.directions, solid_angle_sr=grid.solid_angle_sr,
                 **{k: np.asarray(getattr(env, k)) for k in SCALARS})


def read_map(path):
    """Read a map written by :func:`write_map`; bad input is one :class:`InputError` naming the file and field."""
    try:
        with np.load(path, allow_pickle=False) as f:
            data = {k: f[k] for k in f.files}
    except (OSError, ValueError, EOFError) as e:
        raise InputError(path, "", f"not an environment map's NPZ file ({e})") from None
    if "sets" not in data:
        raise InputError(path, "sets", "missing: the map was written before maps held their catches per receptor "
                         "set; trace it again")
    names = data["sets"]
    if names.dtype.kind != "U" or names.ndim != 1 or len(names) == 0 or len(set(names)) != len(names):
        raise InputError(path, "sets", "must name the map's receptor sets, one or more, each once")
    per_set = [f"{k}.{name}" for name in names for k in SET_ARRAYS]
    for key in (*ARRAYS, *SCALARS, *per_set, *(("radiance",) if "radiance" in data else ())):
        if key not in data:
            raise InputError(path, key, "missing")
        if not np.issubdtype(data[key].dtype, np.number) or not np.isfinite(data[key]).all():
            raise InputError(path, key, "must hold finite numbers")
    n, w = len(data["nearness"]), len(data["wavelengths_nm"])
    shapes = {"position_m": (3,), "wavelengths_nm": (w,), "nearness": (n,),
              **({"radiance": (n, w)} if "radiance" in data else {})}
    for name in names:
        k = data[f"curves.{name}"].shape[-1] if data[f"curves.{name}"].ndim == 2 else 0
        shapes |= {f"q.{name}": (n, k), f"q_se.{name}": (n, k), f"curves.{name}": (w, k)}
    for key, shape in shapes.items():
        if n == 0 or w == 0 or 0 in data[key].shape or data[key].shape != shape:
            raise InputError(path, key, f"shape {data[key].shape}, where the map's nearness {data['nearness'].shape} "
                             f"and wavelengths {data['wavelengths_nm'].shape} ask for {shape}")
    spacing, step = float(data["spacing_deg"]), float(data["heading_step_deg"])
    for key, value, most in (("spacing_deg", spacing, 180.0), ("heading_step_deg", step, 360.0)):
        if not 0.0 < value <= most or abs(most / value - round(most / value)) > 1e-9:
            raise InputError(path, key, f"{value}: {most:g}° over it must be a whole number")
    if len(ring_grid(spacing, step).directions) != n:
        raise InputError(path, "nearness", f"{n} directions, where the grid of spacing_deg {spacing} and "
                         f"heading_step_deg {step} has {len(ring_grid(spacing, step).directions)}")
    catches = {str(name): SetCatches(*(data[f"{k}.{name}"] for k in SET_ARRAYS)) for name in names}
    return EnvironmentMap(data["position_m"], spacing, step, data["wavelengths_nm"], data.get("radiance"), catches,
                          data["nearness"], int(data["samples"]), int(data["depth"]), int(data["seed"]), str(path))
