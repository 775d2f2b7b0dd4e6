"""Image-difference functions: how a view differs from a remembered one, over headings (rIDF) and places (tIDF).

Zeil, Hofmann & Chahl (2003) took panoramic snapshots on grids of places
and measured each image's root-mean-square pixel difference from a
reference image: over the places it falls smoothly to a sharp minimum at
the reference (the translational IDF, whose basin is the snapshot's
catchment area); the same difference over the turns of one image (the
rotational IDF) has a similar shape with a higher plateau and changes
little with distance from the reference. Stürzl & Zeil (2007) found the
IDFs and catchment areas wider the farther the objects, and made them
robust against changes of illumination by normalising the images' contrast.

Here an image is one eye's receptors, and a pixel one receptor's signal
(:func:`image_difference`). A class's signal is its receptors' excitation
E = q/(q + 1), q each catch over the reference view's mean catch of the
class (adapted to the reference view as to a background, von Kries; the
hyperbolic transform of Chittka's 1992 colour hexagon,
:func:`beeoptics.vision.colourspace.excitation`): the classes compare on one
scale, 0.5 at the reference's mean, and the sun's disc, some thousand times
the mean catch, saturates near 1 as a camera's pixels do rather than making
the whole difference (with catches over their mean a turn of 1° in the
meadow differed by 13 mean catches, 10 cm of travel by 0.09). The
achromatic signal is the receptor set's achromatic class so taken (green
for the bee); the
opponent signal is the natural log of the shortest-wavelength class's catch
over the achromatic class's, receptor by receptor (for the bee log(UV/G)):
the UV–green contrast that separates the sky from the objects below the
skyline by a fixed threshold under any illumination (Möller 2002), which a
common change of the light's intensity leaves unchanged, and on which
Kollmeier et al. (2007), Stone et al. (2014) and Differt & Möller (2015,
2016) built their skyline-based navigation. A receptor with a catch of
zero in either class has no opponent signal and is left out of the mean.

The rIDF's valley (:func:`valley`): the heading of its minimum; its depth,
1 − minimum/median (0 for a flat function, 1 for a perfect match: the
median standing for the plateau Zeil et al. 2003 describe); its width, the
half-width of the valley at half its depth (the mean of the turns either
side of the minimum at which the rIDF first reaches halfway between the
minimum and the median, linearly between headings). These are this module's definitions: the
abstracts of Zeil et al. (2003) and Stürzl & Zeil (2007) name the
functions' depth and width but the papers' formulas could not be read here.

References
----------
Chittka L (1992) The colour hexagon: a chromaticity diagram based on
photoreceptor excitations as a generalized representation of colour
opponency. J Comp Physiol A 170:533–543.
Zeil J, Hofmann MI, Chahl JS (2003) Catchment areas of panoramic snapshots
in outdoor scenes. J Opt Soc Am A 20:450–469.
Stürzl W, Zeil J (2007) Depth, contrast and view-based homing in outdoor
scenes. Biol Cybern 96:519–531.
Möller R (2002) Insects could exploit UV–green contrast for landmark
navigation. J Theor Biol 214:619–631.
Kollmeier T, Röben F, Schenck W, Möller R (2007) Spectral contrasts for
landmark navigation. J Opt Soc Am A 24:1–10.
Stone T, Mangan M, Ardin P, Webb B (2014) Sky segmentation with ultraviolet
images can be used for navigation. Robotics: Science and Systems X.
Differt D, Möller R (2015) Insect models of illumination-invariant skyline
extraction from UV and green channels. J Theor Biol 380:444–462.
Differt D, Möller R (2016) Spectral skyline separation: extended landmark
databases and panoramic imaging. Sensors 16:1614.
"""

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from beeoptics.eye.optics import acceptance_solid_angle
from beeoptics.io.errors import InputError
from beeoptics.jit import kernel
from beeoptics.navigation.envmap import eye_weights, map_catches, parallax_corrected
from beeoptics.vision.colourspace import excitation


@kernel
def _turned_sums(indptr, start, kernel, parallax, table, length, near, rows):
    """Receptors ``rows``' weighted sums of the map at every turn by the two matrices of one sparsity,
    ``kernel`` and ``parallax`` (their entries' weights), (2, rows, ``length``): entry p adds its weight times
    ``table[start[p]:start[p] + length]``, the map's values at its direction turned through every heading (laid
    out so by :func:`turned_catches`), read once for both. Each receptor's sum runs in the same order always:
    the same bits for any split of the receptors among threads. A receptor not ``near`` (its kernel meets no
    surface at any turn) has no parallax to sum: its sums are left zero, as the nearness under its kernel,
    zero, would count them."""
    out = np.zeros((2, len(rows), length))
    for n in range(len(rows)):
        i = rows[n]
        sums, turns = out[0, n], out[1, n]
        for p in range(indptr[i], indptr[i + 1]):
            seen = table[start[p]:start[p] + length]
            w = kernel[p]
            if near[i]:
                v = parallax[p]
                for j in range(length):
                    sums[j] += w * seen[j]
                    turns[j] += v * seen[j]
            else:
                for j in range(length):
                    sums[j] += w * seen[j]
    return out


def turned_catches(env, eye, *, heading_step_deg=1.0, pitch_deg=0.0, roll_deg=0.0, weights=None, q=None,
                   threads=None):
    """The eye's catches at the map's place at every heading a whole turn round, resampled from the map.

    A turn by a whole number of the map's heading steps moves each of its
    rings by a whole number of directions
    (:func:`beeoptics.navigation.envmap.turn_order`): here each ring's
    directions are laid out as (turn, the ring's count over the turn's
    steps), so that turning is a shift along the first axis, and every
    heading's view is the one resampling matrix applied to shifted slices,
    all headings in one compiled pass rather than 360 sparse products: the
    kernel's and its parallax's sums of the map's catches and nearness
    (:func:`beeoptics.navigation.envmap.parallax_corrected`), 8 × 10⁹
    multiply-adds for the worker's 360 headings.

    Parameters
    ----------
    env : EnvironmentMap
    eye : beeoptics.Eye
    heading_step_deg : float
        Degrees between headings, a whole multiple of the map's heading step; the headings are 0, it, 2 it, …
    pitch_deg, roll_deg : float
        The head's pitch and roll, degrees.
    weights : Weights, optional
        :func:`beeoptics.navigation.envmap.eye_weights` at this pitch and
        roll, heading 0 (the same for every map of one grid: built once).
    q : (ndarray, ndarray), optional
        :func:`beeoptics.navigation.envmap.map_catches` of the map.
    threads : int, optional
        Threads summing; all cores by default. The catches are the same for any.

    Returns
    -------
    ndarray (headings, receptors, k)
        Each class's quantum catch, photons m⁻² s⁻¹, as
        :func:`beeoptics.navigation.envmap.resampled_catches` gives it at each heading.
    """
    steps = heading_step_deg / env.heading_step_deg
    turn = round(360.0 / env.heading_step_deg)
    if heading_step_deg <= 0.0 or abs(steps - round(steps)) > 1e-9 or turn % round(steps):
        raise InputError(env.source, "heading_step_deg", f"{heading_step_deg!r}° is not a whole multiple of the "
                         f"map's heading step {env.heading_step_deg}° dividing 360°")
    grid = env.grid
    weights = eye_weights(env, eye, pitch_deg=pitch_deg, roll_deg=roll_deg) if weights is None else weights
    # The nearness beside the catches: both turn alike.
    q = np.column_stack([(map_catches(env, eye) if q is None else q)[0], env.nearness])
    step, k = round(steps), q.shape[1]
    turns = turn // step
    # Ring r's direction j is (u, v) = (j // m_r, j % m_r), m_r its count over the turn: a turn by t map steps
    # takes u to u + t. Column v of ring r is column first_r + v of the table, and u = a step + b its residue b
    # and place a: the table holds, for every column and residue, the map at places 0, 1, … twice round, so that
    # a direction's values at all the headings are one contiguous run from its own place.
    per = grid.counts // turn
    starts, first = np.cumsum(grid.counts) - grid.counts, np.cumsum(per) - per
    ring = np.repeat(np.arange(len(per)), per)
    v = np.arange(per.sum()) - first[ring]
    table = q[starts[ring] + np.arange(turn)[:, None] * per[ring] + v]
    table = table.reshape(turns, step, len(v), k).transpose(2, 1, 0, 3)
    table = np.ascontiguousarray(np.concatenate([table, table], axis=2)).ravel()
    rings = np.repeat(np.arange(len(per)), grid.counts)
    r = rings[weights.kernel.indices]
    j = weights.kernel.indices - starts[r]
    u, column = j // per[r], first[r] + j % per[r]
    start = (((column * step + u % step) * 2 * turns) + u // step) * k
    # The receptors whose kernels meet a surface at some turn (the nearness, last of a direction's k values at
    # each of its turns, above zero somewhere): only theirs have a parallax to sum.
    seen = table.reshape(-1, 2 * turns, k)[:, :turns, -1].any(axis=1)[start // (2 * turns * k)]
    counted = np.concatenate([[0], np.cumsum(seen)])
    indptr = weights.kernel.indptr
    near = counted[indptr[1:]] > counted[indptr[:-1]]
    # The kernel holds no GIL: the receptors split among threads, each its own rows.
    parts = np.array_split(np.arange(weights.kernel.shape[0]), threads or os.cpu_count())
    with ThreadPoolExecutor(len(parts)) as pool:
        sums = list(pool.map(lambda rows: _turned_sums(indptr, start, weights.kernel.data, weights.parallax.data,
                                                       table, turns * k, near, rows), parts))
    sums = np.concatenate(sums, axis=1).reshape(2, -1, turns, k)
    catches = parallax_corrected(sums[0], sums[1][..., :-1])
    return (acceptance_solid_angle(eye.table.delta_rho_deg)[:, None, None] * catches).transpose(1, 0, 2)


def signal_names(receptor_set):
    """The signals of :func:`signals` for a receptor set: its classes, ``achromatic`` and the opponent
    ``<shortest>-<achromatic>`` (``UV-G`` for the bee)."""
    classes = receptor_set.classes
    return (*classes, "achromatic",
            f"{classes[int(np.argmin(receptor_set.lambda_max_nm))]}-{classes[receptor_set.achromatic]}")


def signals(catches, receptor_set, reference):
    """A view's signals, receptor by receptor, for image differences (the module's normalisation).

    Parameters
    ----------
    catches : ndarray (..., receptors, k)
        Quantum catches in the set's classes (any leading axes: headings, places).
    receptor_set : ReceptorSet
    reference : ndarray (receptors, k)
        The reference view's catches: each class is taken over their mean.

    Returns
    -------
    dict of str to ndarray (..., receptors)
        By :func:`signal_names`: each class's and the achromatic one's
        excitation, its catch over the reference's mean catch of the class
        through q/(q + 1) (dimensionless, 0 to 1), and the opponent's log
        ratio (NaN where either catch is not above zero).
    """
    catches = np.asarray(catches, float)
    scaled = excitation(catches / np.mean(reference, axis=0))
    names = signal_names(receptor_set)
    short, achromatic = int(np.argmin(receptor_set.lambda_max_nm)), receptor_set.achromatic
    positive = (catches[..., short] > 0.0) & (catches[..., achromatic] > 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        opponent = np.where(positive, np.log(catches[..., short] / catches[..., achromatic]), np.nan)
    return {**{k: scaled[..., i] for i, k in enumerate(receptor_set.classes)},
            names[-2]: scaled[..., achromatic], names[-1]: opponent}


def image_difference(views, reference):
    """The root-mean-square difference over receptors between views and a reference (Zeil et al. 2003).

    Parameters
    ----------
    views : ndarray (..., receptors)
        One signal of views (:func:`signals`): a heading's (rIDF), a place's (tIDF), or any stack.
    reference : ndarray (receptors,)
        The reference view's same signal.

    Returns
    -------
    ndarray (...)
        √(mean over receptors of (view − reference)²), in the signal's units;
        receptors where either is NaN left out.
    """
    return np.sqrt(np.nanmean((np.asarray(views) - reference) ** 2, axis=-1))


def ridf(views, reference, receptor_set):
    """The rotational image-difference function in every signal (Zeil et al. 2003): each view's difference
    from the reference view.

    Parameters
    ----------
    views : ndarray (headings, receptors, k)
        An eye's catches at one place at every heading (:func:`turned_catches`), or any stack of views.
    reference : ndarray (receptors, k)
        The remembered view's catches (a snapshot: a place's view at one heading).
    receptor_set : ReceptorSet
        The eye's (its classes and achromatic class).

    Returns
    -------
    dict of str to ndarray (headings,)
        By :func:`signal_names`: :func:`image_difference` of the views'
        :func:`signals` against the reference's, in the signal's units;
        its minimum's heading points home.
    """
    seen, remembered = signals(views, receptor_set, reference), signals(reference, receptor_set, reference)
    return {name: image_difference(seen[name], remembered[name]) for name in seen}


def valley(ridf, heading_step_deg=1.0):
    """The rIDF's minimum: its heading, depth and width (the module's definitions).

    Parameters
    ----------
    ridf : ndarray (..., headings)
        rIDFs over a whole turn, heading 0 first, ``heading_step_deg`` apart.
    heading_step_deg : float

    Returns
    -------
    heading_deg, depth, width_deg : ndarray (...)
        The heading of the minimum (degrees), 1 − minimum/median, and the
        half-width at half depth (degrees).
    """
    ridf = np.asarray(ridf, float)
    n = ridf.shape[-1]
    low = np.argmin(ridf, axis=-1)
    least, median = np.min(ridf, axis=-1), np.median(ridf, axis=-1)
    half = (0.5 * (least + median))[..., None]
    # The rIDF turned so that its minimum is first: the first turn either way at which it reaches half depth.
    turned = np.take_along_axis(ridf, (low[..., None] + np.arange(n)) % n, axis=-1)
    reach = [_crossing(side, half) for side in (turned, np.roll(turned[..., ::-1], 1, axis=-1))]
    with np.errstate(divide="ignore", invalid="ignore"):
        depth = np.where(median > 0.0, 1.0 - least / median, 0.0)
    return low * heading_step_deg, depth, 0.5 * (reach[0] + reach[1]) * heading_step_deg


def _crossing(turned, level):
    """Steps from the first element to where ``turned`` first reaches ``level`` (…, 1), linearly between the
    steps either side; 0 where the first reaches it (a flat function)."""
    k = np.argmax(turned >= level, axis=-1)[..., None]
    above = np.take_along_axis(turned, k, axis=-1)
    below = np.take_along_axis(turned, np.maximum(k - 1, 0), axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        share = np.where(above > below, (level - below) / (above - below), 1.0)
    return np.where(k > 0, k - 1 + share, 0.0)[..., 0]
