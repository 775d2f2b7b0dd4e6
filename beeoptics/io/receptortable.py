"""Receptor tables: one row per ommatidium of both eyes, in the head frame.

Columns of ``receptors.csv`` (``results/eyes/{eye}/receptors.csv``):

``id``
    0 … n−1; the right eye's receptors first.
``side``
    ``right`` or ``left`` (:data:`beeoptics.headframe.SIDES`).
``x, y, z``
    Facet centre in the head frame, mm (+x anterior, +y left, +z dorsal).
``ax, ay, az``
    Unit receptor axis.
``facet_diameter_um``
    Lens diameter, µm.
``delta_phi_deg``
    Mean angle between this receptor's axis and its neighbours' axes.
``delta_rho_deg``
    Acceptance angle (full width at half maximum of A(θ)).
"""

from typing import NamedTuple

import numpy as np

from beeoptics.io.errors import InputError
from beeoptics.io.table import read_table, write_table

COLUMNS = ("id", "side", "x", "y", "z", "ax", "ay", "az",
           "facet_diameter_um", "delta_phi_deg", "delta_rho_deg")


class ReceptorTable(NamedTuple):
    """The receptors of an eye pair, one entry per receptor.

    ``position`` (n, 3) is in mm and ``axis`` (n, 3) a unit vector, both in
    the head frame; the other fields are (n,) arrays named as the columns of
    :data:`COLUMNS`. ``focal_offset_mm`` is CompoundRay's focal point offset,
    None for a table that does not come from a ``.eye`` file.
    """

    id: np.ndarray
    side: np.ndarray
    position: np.ndarray
    axis: np.ndarray
    facet_diameter_um: np.ndarray
    delta_phi_deg: np.ndarray
    delta_rho_deg: np.ndarray
    focal_offset_mm: np.ndarray = None

    def columns(self):
        """The table as the named columns of :data:`COLUMNS`."""
        return {"id": self.id, "side": self.side,
                **dict(zip(("x", "y", "z"), self.position.T)), **dict(zip(("ax", "ay", "az"), self.axis.T)),
                "facet_diameter_um": self.facet_diameter_um, "delta_phi_deg": self.delta_phi_deg,
                "delta_rho_deg": self.delta_rho_deg}


def write_receptors(path, table):
    """Write a :class:`ReceptorTable` as ``receptors.csv``, atomically."""
    write_table(path, table.columns())


def read_receptors(path):
    """Read and check a receptor table written by :func:`write_receptors`.

    Raises
    ------
    InputError
        If a column is missing or not numeric, or an acceptance angle is not positive.
    """
    t = read_table(path, numeric=[c for c in COLUMNS if c != "side"], text=["side"])
    drho = np.asarray(t["delta_rho_deg"], float)
    if not (np.isfinite(drho) & (drho > 0)).all():
        raise InputError(path, "delta_rho_deg", "acceptance angles must be positive")
    return ReceptorTable(
        id=t["id"], side=t["side"],
        position=np.column_stack([t["x"], t["y"], t["z"]]), axis=np.column_stack([t["ax"], t["ay"], t["az"]]),
        facet_diameter_um=t["facet_diameter_um"], delta_phi_deg=t["delta_phi_deg"], delta_rho_deg=t["delta_rho_deg"],
    )
