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

A step's loops over springs and particles are compiled (numba) and serial,
so that every sum runs in one order and the lattice comes out the same to
the bit on every run, whatever the number of threads; libigl still puts
the particles back on the mesh, and scipy's KD-tree lists the pairs.

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
from beeoptics.jit import kernel

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


@kernel
def _spring_forces(points, springs, rest, ratio, scale, face_normals, faces):
    """The push of the compressed springs on each particle, times ``scale``, in the plane of its face.

    A spring's length is its chord times its ``ratio``. The sums run over
    the springs in order, so that they come out the same on every run.
    """
    force = np.zeros_like(points)
    for k in range(len(springs)):
        i, j = springs[k, 0], springs[k, 1]
        d0, d1, d2 = points[j, 0] - points[i, 0], points[j, 1] - points[i, 1], points[j, 2] - points[i, 2]
        chord = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        strain = (rest[k] - chord * ratio[k]) / rest[k]
        if strain > 0.0:
            push = strain / chord
            force[j, 0] += push * d0
            force[j, 1] += push * d1
            force[j, 2] += push * d2
            force[i, 0] -= push * d0
            force[i, 1] -= push * d1
            force[i, 2] -= push * d2
    for i in range(len(points)):
        n = face_normals[faces[i]]
        f0, f1, f2 = force[i, 0] * scale[i], force[i, 1] * scale[i], force[i, 2] * scale[i]
        up = f0 * n[0] + f1 * n[1] + f2 * n[2]
        force[i, 0], force[i, 1], force[i, 2] = f0 - up * n[0], f1 - up * n[1], f2 - up * n[2]
    return force


@kernel
def _fire_step(points, force, previous_force, velocity, own_step, on_rim, dt, mix, calm):
    """One step of FIRE, with the particles caught in a corner of the rim on their own step.

    Updates ``velocity`` and ``own_step`` in place. Returns where the
    particles go (before they are put back on the mesh), which are caught,
    and FIRE's new ``dt``, ``mix`` and ``calm``.
    """
    n = len(points)
    # A particle in a rim face whose force keeps turning round is caught in
    # a corner of the rim, where the force never vanishes: it gets its own
    # step, halved at each reversal so that it settles into the corner, and
    # is left out of FIRE's bookkeeping so that it cannot stall the rest.
    caught = np.zeros(n, np.bool_)
    for i in range(n):
        turn = (force[i, 0] * previous_force[i, 0] + force[i, 1] * previous_force[i, 1]
                + force[i, 2] * previous_force[i, 2])
        caught[i] = on_rim[i] and turn < 0.0
        if caught[i]:
            own_step[i] *= 0.5
            velocity[i] = 0.0
        else:
            own_step[i] = min(1.0, 2.0 * own_step[i])
    power, speed2, force2 = 0.0, 0.0, 0.0
    for i in range(n):
        for c in range(3):
            power += force[i, c] * velocity[i, c]
            speed2 += velocity[i, c] * velocity[i, c]
            force2 += force[i, c] * force[i, c]
    # Steer the velocity towards the force while going downhill, lengthen the
    # step after a calm run, stop dead when going uphill.
    if power >= 0.0:
        steer = mix * np.sqrt(speed2) / max(np.sqrt(force2), 1e-300)
        for i in range(n):
            for c in range(3):
                velocity[i, c] = (1.0 - mix) * velocity[i, c] + steer * force[i, c]
        calm += 1
        if calm > FIRE_CALM:
            dt, mix = min(dt * FIRE_GROW, FIRE_DT_MAX), mix * FIRE_MIX_DECAY
    else:
        velocity[:] = 0.0
        dt, mix, calm = max(dt * FIRE_SHRINK, FIRE_DT_MIN), FIRE_MIX, 0
    proposed = np.empty_like(points)
    for i in range(n):
        for c in range(3):
            velocity[i, c] += force[i, c] * dt
            proposed[i, c] = points[i, c] + velocity[i, c] * (dt * own_step[i])
    return proposed, caught, dt, mix, calm


@kernel
def _settle(points, moved_to, built_at, half_skin, force, caught, own_step, velocity, dt):
    """Take the moves the mesh allowed as the velocity (in place).

    Returns the furthest any particle is from where the pair list was built,
    in its ``half_skin``, and how far the lattice is from rest: the step each
    particle would make from rest, its force, whatever FIRE's own step; a
    particle caught in a corner is as far from rest as its last move.
    """
    drift, largest2 = 0.0, 0.0
    for i in range(len(points)):
        moved2, away2, force2 = 0.0, 0.0, 0.0
        for c in range(3):
            moved = moved_to[i, c] - points[i, c]
            velocity[i, c] = moved / dt
            moved2 += moved * moved
            away2 += (moved_to[i, c] - built_at[i, c]) ** 2
            force2 += force[i, c] * force[i, c]
        drift = max(drift, np.sqrt(away2) / half_skin[i])
        largest2 = max(largest2, moved2 if caught[i] or own_step[i] < 1.0 else force2)
    return drift, np.sqrt(largest2)


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
    keep, rest = _within_skin(points, pairs, target)
    return pairs[keep], rest[keep]


@kernel
def _within_skin(points, pairs, target):
    """Whether each pair is closer than ``SKIN`` rest lengths, and its rest length.

    Compiled: where facet sizes vary, the KD-tree's single radius lists
    several times more pairs than are kept.
    """
    keep = np.empty(len(pairs), np.bool_)
    rest = np.empty(len(pairs))
    for k in range(len(pairs)):
        i, j = pairs[k, 0], pairs[k, 1]
        rest[k] = SQUEEZE * 0.5 * (target[i] + target[j])
        chord2 = ((points[j, 0] - points[i, 0]) ** 2 + (points[j, 1] - points[i, 1]) ** 2
                  + (points[j, 2] - points[i, 2]) ** 2)
        keep[k] = chord2 < (SKIN * rest[k]) ** 2
    return keep, rest


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
    faces = np.array(faces, np.int64)
    fill = fill_factor(query, query.interpolate(diameters, points, faces))
    velocity = np.zeros_like(points)
    dt, mix, calm = 1.0, FIRE_MIX, 0
    snapshots = []
    known = None
    previous_force = np.zeros_like(points)
    own_step = np.ones(len(points))
    drift = np.inf
    for iteration in range(max_iterations):
        if iteration in snapshot_at:
            snapshots.append((iteration, points.copy()))
        # Rebuild the pair list before a pair it left out can have come within
        # its rest length: a pair's skin is (SKIN − 1) rest lengths, the mean
        # of its ends', so it holds while each particle has moved less than
        # half of that at its own target. Once springs are measured along the
        # surface, measure the new ones too.
        if drift > 1.0:
            target = query.interpolate(diameters, points, faces)
            springs, rest = _near_pairs(points, fill * target)
            half_skin = 0.5 * (SKIN - 1.0) * SQUEEZE * fill * target
            built_at, drift = points.copy(), 0.0
            if known is None:
                ratio = np.ones(len(springs))
            else:
                ratio, known = _geodesic_ratio(query, points, faces, springs, known)
        force = _spring_forces(points, springs, rest, ratio, step * target, query.face_normals, faces)
        # The rim holds back what pushes a particle off the eye: near it, the
        # force becomes the step it can actually make, projected onto the mesh.
        on_rim = query.on_rim_face(faces)
        rim = np.flatnonzero(on_rim)
        force[rim] = query.project(points[rim] + force[rim])[0] - points[rim]
        proposed, caught, dt, mix, calm = _fire_step(points, force, previous_force, velocity, own_step, on_rim,
                                                     dt, mix, calm)
        previous_force = force
        moved_to, faces = query.slide(proposed, faces)
        drift, largest = _settle(points, moved_to, built_at, half_skin, force, caught, own_step, velocity, dt)
        points = moved_to
        if progress is not None:
            progress(iteration, largest)
        if largest < tolerance:
            if known is not None:
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
