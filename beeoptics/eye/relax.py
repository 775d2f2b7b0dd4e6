"""Relaxing the facet lattice as a spring–mass particle system (Collins §4.1, step 3).

Any two particles closer than their rest length are joined by a spring. A
spring's rest length is a fixed multiple (``SQUEEZE``, above one) of the
mean facet diameter the map asks for at its two ends, and it pushes with a
force proportional to its strain when compressed and not at all when
slack. With the squeeze at 1.08 only nearest neighbours interact (the next
ring of a hexagonal lattice lies √3 spacings away), the force varies
continuously as particles move, and the lattice is held under a uniform
pressure: it fills the eye to its rim, as the cornea's facets do, and every
spring is compressed by the same fraction, so that neighbour spacing
follows the facet-diameter map everywhere. A lattice pulled by springs
would instead shrink away from the rim.

Particles move as masses under FIRE (Bitzek et al. 2006), damped dynamics
whose velocity is steered towards the force and zeroed whenever it runs
against it, and after every step are put back on the mesh at the closest
point, so they never leave it. Spring lengths are measured as chords while
the lattice forms. Once it is still, the springs are measured again as
exact geodesics over the mesh (libigl), and the system is run to rest on
those lengths, until no particle moves by more than the tolerance in a
step; the Delaunay neighbours of the final lattice are measured the same way.

References
----------
Collins S. Reconstructing the visual field of compound eyes. §4.1.
Bitzek E, Koskinen P, Gähler F, Moseler M, Gumbsch P (2006) Structural
relaxation made simple. Phys Rev Lett 97:170201.
Guénolé J, Nöhring WG, Vaid A, Houllé F, Xie Z, Prakash A, Bitzek E (2020)
Assessment and optimization of the fast inertial relaxation engine (FIRE)
for energy minimization in atomistic simulations. Comput Mater Sci 175:109584.
"""

from typing import NamedTuple

import numpy as np
from scipy.spatial import cKDTree

from beeoptics.eye.geodesic import pair_distances
from beeoptics.eye.lattice import MAX_EDGE, neighbour_edges

#: Rest length over filling spacing. Above one keeps every spring compressed.
SQUEEZE = 1.08
#: Pairs are listed out to this many rest lengths, and the list is rebuilt
#: once a particle has moved half the difference (a Verlet list).
SKIN = 1.5
# FIRE's parameters as recommended by Bitzek et al. (2006), but for the longest
# step, halved: a shorter step makes for fewer avalanches in the compressed
# lattice. The shortest step is FIRE 2.0's (Guénolé et al. 2020).
FIRE_MIX, FIRE_MIX_DECAY, FIRE_CALM, FIRE_GROW, FIRE_SHRINK = 0.1, 0.99, 5, 1.1, 0.5
FIRE_DT_MAX, FIRE_DT_MIN = 1.0, 0.02


class Relaxation(NamedTuple):
    """A relaxed facet lattice.

    ``points`` (n, 3) on the mesh and ``faces`` (n,) holding them;
    ``edges`` (m, 2), the Delaunay neighbour pairs, and ``geodesic`` (m,),
    their exact geodesic lengths; ``boundary`` (n,), the particles on the rim
    of the triangulation; ``iterations``; ``snapshots``, a list of
    (iteration, points) from the initial grid to rest; ``fill_factor``.
    """

    points: np.ndarray
    faces: np.ndarray
    edges: np.ndarray
    boundary: np.ndarray
    geodesic: np.ndarray
    iterations: int
    fill_factor: float
    snapshots: list


def _spring_forces(points, edges, rest, delta, chord, lengths):
    strain = np.clip((rest - lengths) / rest, 0.0, None)
    push = delta * (strain / chord)[:, None]
    n = len(points)
    force = np.empty_like(points)
    for k in range(3):
        force[:, k] = np.bincount(edges[:, 1], push[:, k], n) - np.bincount(edges[:, 0], push[:, k], n)
    return force


def fill_factor(query, diameters):
    """Spacing that fills the mesh with these facets, over the spacing the map asks for.

    A hexagonal facet of diameter D covers √3/2·D². One means the mesh
    area and the facet count agree with the map; the rest lengths are
    scaled by this factor, so that a mesh a little too large or too small
    is still filled under the same compression, and the mismatch shows as
    a uniform error in spacing rather than as gaps.
    """
    return float(np.sqrt(query.area / (np.sqrt(3.0) / 2.0 * (diameters**2).sum())))


def _lengths(points, pairs):
    return np.linalg.norm(points[pairs[:, 1]] - points[pairs[:, 0]], axis=1)


def _geodesic_ratio(query, points, faces, pairs, known=None):
    """Geodesic over straight length of each pair, measured exactly on the mesh.

    ``known`` holds the sorted pair keys and ratios of an earlier call; only
    pairs not among them are measured. A pair's ratio (1 + κ²L²/24 on a
    surface of curvature κ) hardly changes as its ends move by a fraction
    of a facet, so a rebuilt pair list needs only its new springs measured.
    Returns the ratios and the updated ``known``.
    """
    keys = pairs[:, 0] * (len(points) + 1) + pairs[:, 1]
    old_keys, old_ratio = known if known is not None else (np.empty(0, np.int64), np.empty(0))
    at = np.minimum(np.searchsorted(old_keys, keys), max(len(old_keys) - 1, 0))
    seen = old_keys[at] == keys if len(old_keys) else np.zeros(len(keys), bool)
    ratio = np.empty(len(pairs))
    ratio[seen] = old_ratio[at[seen]]
    new = pairs[~seen]
    ratio[~seen] = pair_distances(query.vertices, query.faces, points, faces, new) / _lengths(points, new)
    all_keys = np.concatenate([old_keys, keys[~seen]])
    order = np.argsort(all_keys)
    return ratio, (all_keys[order], np.concatenate([old_ratio, ratio[~seen]])[order])


def _near_pairs(points, target):
    pairs = cKDTree(points).query_pairs(SKIN * SQUEEZE * target.max(), output_type="ndarray")
    rest = SQUEEZE * 0.5 * (target[pairs[:, 0]] + target[pairs[:, 1]])
    keep = _lengths(points, pairs) < SKIN * rest
    return pairs[keep], rest[keep]


def relax(
    query,
    uv,
    diameters,
    points,
    faces,
    tolerance,
    *,
    step=0.5,
    max_iterations=5000,
    snapshot_at=(0, 25, 100),
    progress=None,
):
    """Relax particles on a mesh into a hexagonal lattice that follows a facet-diameter map.

    Parameters
    ----------
    query : MeshQuery
        The remeshed eye.
    uv : ndarray, shape (n_vertices, 2)
        Conformal flattening of the mesh, for the neighbour triangulation.
    diameters : ndarray, shape (n_vertices,)
        Target facet diameter at each mesh vertex, in mesh units (mm).
    points, faces : ndarray
        Initial particles on the mesh and the faces holding them.
    tolerance : float
        Stop when no particle is further than this from rest: when none
        would move further in a unit step from rest (mm).
    step : float
        Displacement per unit strain in one unit time step, in target spacings.
    max_iterations : int
    snapshot_at : sequence of int
        Iterations whose particle positions are kept, beside the final one.
    progress : callable, optional
        Called with (iteration, largest displacement) after each step.

    Returns
    -------
    Relaxation

    Raises
    ------
    RuntimeError
        If the lattice is not still after ``max_iterations``.
    """
    points = np.array(points, float)
    faces = np.array(faces)
    fill = fill_factor(query, query.interpolate(diameters, points, faces))
    velocity = np.zeros_like(points)
    dt, mix, calm = 1.0, FIRE_MIX, 0
    snapshots = []
    ratio = None
    previous_force = np.zeros_like(points)
    own_step = np.ones(len(points))
    drift, rest_min = np.inf, 0.0
    for iteration in range(max_iterations):
        if iteration in snapshot_at:
            snapshots.append((iteration, points.copy()))
        # Rebuild the pair list before any particle can have crossed its skin;
        # once springs are measured along the surface, measure the new ones too.
        if drift > 0.5 * (SKIN - 1.0) * rest_min:
            target = query.interpolate(diameters, points, faces)
            springs, rest = _near_pairs(points, fill * target)
            rest_min = SQUEEZE * fill * target.min()
            built_at, drift = points.copy(), 0.0
            if ratio is not None:
                ratio, known = _geodesic_ratio(query, points, faces, springs, known)
        delta = points[springs[:, 1]] - points[springs[:, 0]]
        chord = np.sqrt((delta**2).sum(1))
        lengths = chord if ratio is None else chord * ratio
        force = _spring_forces(points, springs, rest, delta, chord, lengths) * (step * target)[:, None]
        normal = query.face_normals[faces]
        force -= (force * normal).sum(1, keepdims=True) * normal
        # The rim holds back what pushes a particle off the eye: near it, the
        # force becomes the step it can actually make, projected onto the mesh.
        on_rim = query.on_rim_face(faces)
        rim = np.flatnonzero(on_rim)
        force[rim] = query.project(points[rim] + force[rim])[0] - points[rim]
        # A particle in a rim face whose force keeps turning round is caught in
        # a corner of the rim, where the force never vanishes: it gets its own
        # step, halved at each reversal so that it settles into the corner, and
        # is left out of FIRE's bookkeeping so that it cannot stall the rest.
        caught = ((force * previous_force).sum(1) < 0.0) & on_rim
        own_step = np.where(caught, 0.5 * own_step, np.minimum(1.0, 2.0 * own_step))
        velocity[caught] = 0.0
        previous_force = force
        # FIRE: steer the velocity towards the force while going downhill,
        # lengthen the step after a calm run, stop dead when going uphill.
        power = (force * velocity).sum()
        if power >= 0.0:
            velocity = (1.0 - mix) * velocity + mix * force * (
                np.linalg.norm(velocity) / max(np.linalg.norm(force), 1e-300)
            )
            calm += 1
            if calm > FIRE_CALM:
                dt, mix = min(dt * FIRE_GROW, FIRE_DT_MAX), mix * FIRE_MIX_DECAY
        else:
            velocity[:] = 0.0
            dt, mix, calm = max(dt * FIRE_SHRINK, FIRE_DT_MIN), FIRE_MIX, 0
        velocity += force * dt
        moved_to, faces = query.slide(points + velocity * (dt * own_step[:, None]), faces)
        moved = moved_to - points
        velocity = moved / dt
        points = moved_to
        drift = np.sqrt(((points - built_at) ** 2).sum(1).max())
        # How far the lattice is from rest: the step each particle would make
        # from rest, its force, whatever FIRE's own step; a particle caught in
        # a corner is as far from rest as its last move.
        largest = np.sqrt(np.where(caught | (own_step < 1.0), (moved**2).sum(1), (force**2).sum(1)).max())
        if progress is not None:
            progress(iteration, largest)
        if largest < tolerance:
            if ratio is not None:
                break
            # Still under chords: from here on springs are measured along the surface.
            ratio, known = _geodesic_ratio(query, points, faces, springs)
            velocity[:] = 0.0
            dt, mix, calm = 1.0, FIRE_MIX, 0
    else:
        raise RuntimeError(
            f"facet lattice still moving after {max_iterations} iterations: a facet moved "
            f"{largest * 1e3:.3g} µm in the last step, over the tolerance of {tolerance * 1e3:.3g} µm; "
            "a tolerance below about 0.05 µm can chase rearrangements of the lattice for long"
        )
    # A spacing per particle: the lattice's mean (fill × target), or its own nearest neighbour where
    # that is further, so that a particle at a sparse defect keeps its neighbours.
    spacing = np.maximum(fill * target, cKDTree(points).query(points, k=2)[0][:, 1])
    edges, boundary = neighbour_edges(query.interpolate(uv, points, faces), points, MAX_EDGE * spacing)
    # The neighbours are springs, whose ratios are known: only the few edges that are not get measured.
    geodesic = _geodesic_ratio(query, points, faces, edges, known)[0] * _lengths(points, edges)
    snapshots.append((iteration + 1, points.copy()))
    return Relaxation(points=points, faces=faces, edges=edges, boundary=boundary, geodesic=geodesic,
                      iterations=iteration + 1, fill_factor=fill, snapshots=snapshots)
