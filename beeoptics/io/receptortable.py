"""Receptor tables: one row per ommatidium of both eyes, in the head frame.

Columns of ``receptors.csv`` (``results/eyes/{eye}/receptors.csv``):

``id``
    0 … n−1; the right eye's receptors first.
``side``
    ``right`` or ``left`` (:data:`beeoptics.headframe.SIDES`).
``x, y, z``
    Facet centre in the head frame, mm (+x anterior, +y left, +z dorsal).
``ax, ay, az``
    Receptor axis; a table may give any non-zero length, and it is read as
    the unit vector along it.
``facet_diameter_um``
    Lens diameter, µm.
``delta_phi_deg``
    Mean angle between this receptor's axis and its neighbours' axes.
``delta_rho_deg``
    Acceptance angle (full width at half maximum of A(θ)).

Eyes that describe a dorsal rim area add two columns
(:mod:`beeoptics.eye.dorsalrim`):

``dorsal_rim``
    1 for a facet of the dorsal rim area, else 0.
``microvilli_deg``
    The orientation of its UV receptors' microvilli about the axis, from
    the head's dorsal towards its anterior direction, degrees in [0, 180);
    empty (NaN) outside the area, where the rhabdoms twist.
"""

import logging
from typing import NamedTuple

import numpy as np

from beeoptics.headframe import EYE_SIZE_MM, SIDES
from beeoptics.io.errors import InputError
from beeoptics.io.table import read_table, write_table

log = logging.getLogger("beeoptics")

COLUMNS = ("id", "side", "x", "y", "z", "ax", "ay", "az",
           "facet_diameter_um", "delta_phi_deg", "delta_rho_deg")
#: The columns that measure a receptor's optics, one number each.
MEASURES = ("facet_diameter_um", "delta_phi_deg", "delta_rho_deg")
#: Columns of eyes with a dorsal rim area.
DORSAL_RIM_COLUMNS = ("dorsal_rim", "microvilli_deg")
#: Insect facet diameters, µm: about 5 to 100 (Land & Nilsson 2012, Animal Eyes, 2nd ed., ch. 7), warned of
#: outside them (a diameter measured from a micro-CT eye's neighbours reaches 113 µm at its rim); ten times
#: beyond them, below 1 or above 1000, a column is in other units (0.02 is millimetres) and is refused.
FACET_DIAMETER_UM, FACET_DIAMETER_UNITS_UM = (5.0, 100.0), (1.0, 1000.0)
#: Acceptance angles of compound eyes' receptors, degrees: 0.5 to 20 as measured (Land 1997, Annu Rev Entomol
#: 42:147), warned of outside them; beyond 30 (the config's largest Δρ) a receptor would see a sixth of the
#: sphere at half its sensitivity, which no ommatidium does, and is refused.
DELTA_RHO_DEG, DELTA_RHO_MAX_DEG = (0.5, 20.0), 30.0
#: Neighbouring axes more than a right angle apart (Δφ, degrees) belong to no compound eye: compound eyes' Δφ
#: run from 0.24° to some 20° (Land 1997).
DELTA_PHI_MAX_DEG = 90.0


class ReceptorTable(NamedTuple):
    """The receptors of an eye pair, one entry per receptor.

    ``position`` (n, 3) is in mm and ``axis`` (n, 3) a unit vector, both in
    the head frame; the other fields are (n,) arrays named as the columns of
    :data:`COLUMNS`. ``focal_offset_mm`` is CompoundRay's focal point offset,
    None for a table that does not come from a ``.eye`` file; ``dorsal_rim``
    and ``microvilli_deg`` (:data:`DORSAL_RIM_COLUMNS`) are None for an eye
    without a dorsal rim area.
    """

    id: np.ndarray
    side: np.ndarray
    position: np.ndarray
    axis: np.ndarray
    facet_diameter_um: np.ndarray
    delta_phi_deg: np.ndarray
    delta_rho_deg: np.ndarray
    focal_offset_mm: np.ndarray = None
    dorsal_rim: np.ndarray = None
    microvilli_deg: np.ndarray = None

    def columns(self):
        """The table as the named columns of :data:`COLUMNS` (and :data:`DORSAL_RIM_COLUMNS`, if given)."""
        rim = {} if self.dorsal_rim is None else {"dorsal_rim": np.asarray(self.dorsal_rim).astype(int),
                                                   "microvilli_deg": self.microvilli_deg}
        return {"id": self.id, "side": self.side,
                **dict(zip(("x", "y", "z"), self.position.T)), **dict(zip(("ax", "ay", "az"), self.axis.T)),
                "facet_diameter_um": self.facet_diameter_um, "delta_phi_deg": self.delta_phi_deg,
                "delta_rho_deg": self.delta_rho_deg, **rim}


def rows_of(table, rows):
    """The receptors ``rows`` (indices or a mask) of a table, every column taken alike."""
    return ReceptorTable(*(None if column is None else np.asarray(column)[rows] for column in table))


def write_receptors(path, table):
    """Write a :class:`ReceptorTable` as ``receptors.csv``, atomically."""
    write_table(path, table.columns())


def read_receptors(path):
    """Read and check a receptor table written by :func:`write_receptors`.

    Raises
    ------
    InputError
        If a column is missing or not numeric, or a receptor is unusable
        (:func:`checked`).
    """
    rim = [c for c in DORSAL_RIM_COLUMNS if c in read_table(path)]
    t = read_table(path, numeric=[*(c for c in COLUMNS if c != "side"), *rim], text=["side"])
    return checked(ReceptorTable(
        id=t["id"], side=t["side"],
        position=np.column_stack([t["x"], t["y"], t["z"]]), axis=np.column_stack([t["ax"], t["ay"], t["az"]]),
        facet_diameter_um=t["facet_diameter_um"], delta_phi_deg=t["delta_phi_deg"], delta_rho_deg=t["delta_rho_deg"],
        dorsal_rim=t.get("dorsal_rim"), microvilli_deg=t.get("microvilli_deg"),
    ), path)


def checked(table, path):
    """The table with unit axes, once every receptor is found usable for tracing.

    A receptor needs a finite position, an axis of finite, non-zero length,
    a positive, finite acceptance angle of at most :data:`DELTA_RHO_MAX_DEG` (warned of outside
    :data:`DELTA_RHO_DEG`), a facet diameter within :data:`FACET_DIAMETER_UM`, a Δφ within
    (0, :data:`DELTA_PHI_MAX_DEG`] and a side of :data:`~beeoptics.headframe.SIDES`;
    ids must be whole and unique; each eye must be of a size bee eyes have
    (:data:`~beeoptics.headframe.EYE_SIZE_MM`), or its positions are in other
    units than millimetres (all at one point is a pinhole eye, and allowed). Δφ and the facet diameter may be missing (NaN):
    nothing is traced with them.

    Raises
    ------
    InputError
        Naming ``path``, the column and the first receptor at fault.
    """
    ids = np.asarray(table.id)
    if ids.dtype.kind not in "iu":
        raise InputError(path, "id", "ids must be whole numbers")
    if len(np.unique(ids)) != len(ids):
        raise InputError(path, "id", f"receptor {_first(ids, _repeated(ids))} appears twice")
    length = np.linalg.norm(table.axis, axis=1)
    drho = np.asarray(table.delta_rho_deg, float)
    facet = np.asarray(table.facet_diameter_um, float)
    dphi = np.asarray(table.delta_phi_deg, float)
    low, high = FACET_DIAMETER_UNITS_UM
    for column, bad, message in (
        ("side", ~np.isin(np.asarray(table.side).astype(str), SIDES), f"side must be one of {', '.join(SIDES)}"),
        ("x, y, z", ~np.isfinite(table.position).all(1), "the position is not finite"),
        ("ax, ay, az", ~np.isfinite(table.axis).all(1), "the axis is not finite"),
        ("ax, ay, az", length == 0.0, "the axis has zero length; a receptor needs a direction"),
        ("delta_rho_deg", ~(np.isfinite(drho) & (drho > 0)), "acceptance angles must be positive and finite"),
        ("delta_rho_deg", drho > DELTA_RHO_MAX_DEG, f"an acceptance angle above {DELTA_RHO_MAX_DEG:g}° is no "
         f"ommatidium's (compound eyes' are {DELTA_RHO_DEG[0]:g}–{DELTA_RHO_DEG[1]:g}°, Land 1997)"),
        ("facet_diameter_um", ~np.isnan(facet) & ~((facet >= low) & (facet <= high)),
         f"insect facets are {FACET_DIAMETER_UM[0]:g}–{FACET_DIAMETER_UM[1]:g} µm across (Land & Nilsson 2012), and "
         f"outside {low:g}–{high:g} µm the column is in other units"),
        ("delta_phi_deg", ~np.isnan(dphi) & ~((dphi > 0) & (dphi <= DELTA_PHI_MAX_DEG)),
         f"an interommatidial angle must be above 0° and at most {DELTA_PHI_MAX_DEG:g}°"),
    ):
        if bad.any():
            raise InputError(path, column, f"receptor {_first(ids, bad)}: {message}")
    for column, values, (least, most), unit, source in (
            ("delta_rho_deg", drho, DELTA_RHO_DEG, "°", "compound eyes' acceptance angles (Land 1997)"),
            ("facet_diameter_um", facet, FACET_DIAMETER_UM, " µm", "insect facets (Land & Nilsson 2012)")):
        unusual = (values < least) | (values > most)
        if unusual.any():
            log.warning("%s: %s: %d receptors (the first %s, %.3g%s) lie outside the %g–%g%s of %s", path, column,
                        unusual.sum(), _first(ids, unusual), values[unusual][0], unit, least, most, unit, source)
    if table.dorsal_rim is not None:
        rim = np.asarray(table.dorsal_rim, float)
        angle = np.asarray(table.microvilli_deg, float)
        for column, bad, message in (
            ("dorsal_rim", ~np.isin(rim, (0.0, 1.0)), "dorsal_rim must be 1 (in the dorsal rim area) or 0"),
            ("microvilli_deg", (rim == 1.0) & ~((angle >= 0.0) & (angle < 180.0)),
             "a dorsal-rim receptor needs a microvillar orientation in [0, 180) degrees"),
        ):
            if bad.any():
                raise InputError(path, column, f"receptor {_first(ids, bad)}: {message}")
    for side in SIDES:
        mine = table.position[np.asarray(table.side).astype(str) == side]
        size = np.ptp(mine, axis=0).max() if len(mine) else 0.0
        # All receptors at one point (size 0) is a pinhole eye, a deliberate model.
        if size != 0.0 and not EYE_SIZE_MM[0] <= size <= EYE_SIZE_MM[1]:
            raise InputError(path, "x, y, z", f"the {side} eye is {size:.3g} mm across; bee eyes are "
                             f"{EYE_SIZE_MM[0]:g}–{EYE_SIZE_MM[1]:g} mm, so its positions are in other units")
    # Axes of unit length as far as the file's nine digits go are kept bit for bit.
    unit = np.abs(length - 1.0) <= 1e-6
    return table._replace(axis=np.where(unit[:, None], table.axis, table.axis / length[:, None]))


def _first(ids, bad):
    return ids[np.flatnonzero(bad)[0]]


def _repeated(ids):
    order = np.argsort(ids, kind="stable")
    twice = np.zeros(len(ids), bool)
    twice[order[1:][np.diff(ids[order]) == 0]] = True
    return twice
