"""Receptor tables: one row per ommatidium of both eyes, in the head frame.

Columns (``results/eyes/{eye}/receptors.csv``):

``id``
    0 … n−1; the right eye's receptors first.
``side``
    ``right`` or ``left``.
``x, y, z``
    Facet centre in the head frame, mm (+x anterior, +y left, +z dorsal).
``ax, ay, az``
    Unit receptor axis, the interpolated surface normal.
``facet_diameter_um``
    Lens diameter from the facet-diameter map, µm.
``delta_phi_deg``
    Mean angle between this receptor's axis and its neighbours' axes.
``delta_rho_deg``
    Acceptance angle (full width at half maximum of A(θ)).
"""

import numpy as np

from beeoptics.errors import InputError
from beeoptics.headframe import mirror
from beeoptics.table import read_table, write_table

COLUMNS = ("id", "side", "x", "y", "z", "ax", "ay", "az",
           "facet_diameter_um", "delta_phi_deg", "delta_rho_deg")


def delta_phi(axes, edges):
    """Mean angle, in degrees, between each receptor's axis and its neighbours' axes.

    Parameters
    ----------
    axes : ndarray, shape (n, 3)
        Unit axes.
    edges : ndarray, shape (m, 2)
        Neighbour pairs.
    """
    cos = np.clip((axes[edges[:, 0]] * axes[edges[:, 1]]).sum(1), -1.0, 1.0)
    angle = np.degrees(np.arccos(cos))
    n = len(axes)
    count = np.bincount(edges.ravel(), minlength=n)
    total = np.bincount(edges[:, 0], angle, n) + np.bincount(edges[:, 1], angle, n)
    return total / np.maximum(count, 1)


def to_head(eye, points, axes):
    """Right-eye local points and axes, in the head frame."""
    r = eye["rotation"]
    return points @ r + eye["origin"], axes @ r


def receptor_table(eye, points, axes, facet_diameter_um, dphi, drho):
    """Columns of the receptor table for both eyes, from the right eye's local lattice."""
    right_p, right_a = to_head(eye, points, axes)
    n = len(points)
    p = np.vstack([right_p, mirror(right_p)])
    a = np.vstack([right_a, mirror(right_a)])
    return {
        "id": np.arange(2 * n),
        "side": np.repeat(np.array(["right", "left"]), n),
        "x": p[:, 0], "y": p[:, 1], "z": p[:, 2],
        "ax": a[:, 0], "ay": a[:, 1], "az": a[:, 2],
        "facet_diameter_um": np.tile(facet_diameter_um, 2),
        "delta_phi_deg": np.tile(dphi, 2),
        "delta_rho_deg": np.tile(drho, 2),
    }


def write_receptors(path, table):
    write_table(path, {k: table[k] for k in COLUMNS})


def read_receptors(path):
    """Read a receptor table, checking its columns; positions (n,3), axes (n,3) and the rest."""
    t = read_table(path, numeric=[c for c in COLUMNS if c != "side"], text=["side"])
    drho = np.asarray(t["delta_rho_deg"], float)
    if not (np.isfinite(drho) & (drho > 0)).all():
        raise InputError(path, "delta_rho_deg", "acceptance angles must be positive")
    t["position"] = np.column_stack([t["x"], t["y"], t["z"]])
    t["axis"] = np.column_stack([t["ax"], t["ay"], t["az"]])
    return t
