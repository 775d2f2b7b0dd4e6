"""Catchment areas: the places from which descending the image difference leads to the reference place.

Zeil, Hofmann & Chahl (2003) recovered a snapshot's place from elsewhere by
moving so as to make the image difference smaller (gradient descent on the
translational IDF), and called the region from which that succeeds the
snapshot's catchment area; Stürzl & Zeil (2007) found it wider the farther
the objects. Here the descent is walked on the grid of places: from each
place to the neighbour (of its eight) whose tIDF falls the most per metre
below its own, and a place with no lower neighbour stays (a minimum). The
catchment area is the set of places whose walk ends at the reference place
(:func:`catchment`); its area is their number times a grid cell's, and its
shape their extent along and across the reference heading (:func:`extent`).

References
----------
Zeil J, Hofmann MI, Chahl JS (2003) Catchment areas of panoramic snapshots
in outdoor scenes. J Opt Soc Am A 20:450–469.
Stürzl W, Zeil J (2007) Depth, contrast and view-based homing in outdoor
scenes. Biol Cybern 96:519–531.
"""

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import breadth_first_order

#: The eight neighbours of a place on the grid, (row, column) steps.
NEIGHBOURS = np.array([(-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1)])


def descent(field):
    """Each place's next place descending the field: the neighbour of steepest descent, or itself at a minimum.

    Parameters
    ----------
    field : ndarray (rows, columns)
        The tIDF on a square grid (any units); NaN is never descended to.

    Returns
    -------
    ndarray of int (rows, columns)
        The flat index of each place's next place.
    """
    rows, columns = field.shape
    padded = np.pad(np.asarray(field, float), 1, constant_values=np.inf)
    shifted = np.stack([padded[1 + dr:1 + dr + rows, 1 + dc:1 + dc + columns] for dr, dc in NEIGHBOURS])
    slope = (shifted - field) / np.hypot(*NEIGHBOURS.T)[:, None, None]
    slope = np.where(np.isnan(slope), np.inf, slope)
    best = np.argmin(slope, axis=0)
    r, c = np.indices(field.shape)
    down = np.take_along_axis(slope, best[None], axis=0)[0] < 0.0
    return np.where(down, (r + NEIGHBOURS[best, 0]) * columns + c + NEIGHBOURS[best, 1], r * columns + c)


def catchment(field, reference):
    """The places from which descending the field leads to the reference place.

    Parameters
    ----------
    field : ndarray (rows, columns)
    reference : (int, int)
        The reference place's row and column.

    Returns
    -------
    ndarray of bool (rows, columns)
    """
    step = descent(field).ravel()
    n = step.size
    # Edges from each place's next place back to it: the places reached from the reference are those whose
    # walk passes through it, and the reference, the field's minimum there, is where the walk ends.
    back = csr_matrix((np.ones(n), (step, np.arange(n))), shape=(n, n))
    start = int(np.ravel_multi_index(reference, field.shape))
    inside = np.zeros(n, bool)
    if step[start] == start:
        inside[breadth_first_order(back, start, directed=True, return_predecessors=False)] = True
    return inside.reshape(field.shape)


def extent(inside, x_m, y_m, heading_deg, spacing_m):
    """A catchment area's area and its extent along and across a heading.

    Parameters
    ----------
    inside : ndarray of bool (rows, columns)
    x_m, y_m : ndarray (rows, columns)
        The places, m.
    heading_deg : float
        The reference heading, degrees from +x towards +y.
    spacing_m : float
        The grid's spacing, m.

    Returns
    -------
    area_m2, along_m, across_m : float
        The places' number times spacing²; the span of their positions along
        and across the heading, plus one spacing (a place stands for its cell).
    """
    if not inside.any():
        return 0.0, 0.0, 0.0
    h = np.radians(heading_deg)
    along = x_m[inside] * np.cos(h) + y_m[inside] * np.sin(h)
    across = -x_m[inside] * np.sin(h) + y_m[inside] * np.cos(h)
    return (float(inside.sum() * spacing_m ** 2), float(np.ptp(along) + spacing_m),
            float(np.ptp(across) + spacing_m))
