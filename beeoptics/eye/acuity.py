"""The acuity of an eye pair, in one row: how finely it samples and resolves, and how much it sees."""

import numpy as np

from beeoptics.eye.fieldofview import extent
from beeoptics.eye.optics import nyquist_limit_cpd, rayleigh_limit_deg


def acuity(table, rayleigh_nm, field):
    """Acuity figures of an eye pair's receptors (both eyes together).

    Parameters
    ----------
    table : ReceptorTable
    rayleigh_nm : dict of str to float
        Receptor class to the wavelength at which its Rayleigh limit is given, nm.
    field : VisualField
        What the table's receptors see (:func:`beeoptics.eye.fieldofview.visual_field`), on the map the
        field of view is measured on: the caller's, who draws it too.

    Returns
    -------
    dict
        ``receptors``; percentiles 5/50/95 of Δφ and Δρ (°); f_max =
        1/(2Δφ) (cycles/°) at the median and 5th-percentile Δφ; the median
        facet diameter D (µm); the Rayleigh limit 1.22 λ/D (°) at each
        wavelength for the median and the largest facet; the solid angle each
        eye sees and the binocular overlap (sr, at half sensitivity), and the
        share of the sphere both see.
    """
    dphi, drho, d_um = table.delta_phi_deg, table.delta_rho_deg, table.facet_diameter_um
    row = {"receptors": len(dphi)}
    for label, values in (("delta_phi_deg", dphi), ("delta_rho_deg", drho)):
        # Over the receptors that have it: a rim facet left without neighbours has no Δφ (NaN).
        row.update({f"{label}_p{p}": np.nanpercentile(values, p) for p in (5, 50, 95)})
    row["f_max_cpd_median"] = nyquist_limit_cpd(np.nanmedian(dphi))
    row["f_max_cpd_p5"] = nyquist_limit_cpd(np.nanpercentile(dphi, 5))
    row["facet_diameter_um_median"] = np.median(d_um)
    for receptor, lam in rayleigh_nm.items():
        for label, d in (("median", np.median(d_um)), ("largest", d_um.max())):
            row[f"rayleigh_deg_{receptor}_{label}_facet"] = rayleigh_limit_deg(lam, d)
    field_extent = extent(field)
    row.update({k: field_extent[k] for k in ("right_sr", "left_sr", "binocular_sr", "total_fraction")})
    return row
