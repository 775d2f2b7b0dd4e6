"""How good a relaxed facet lattice is, and how close its optics come to the bee's.

The eye stage measures these itself and writes them to
``results/eyes/{eye}/quality.json``; the tests assert them. Where the eye
description gives published values, each comparison is also recorded as a
pass or fail under ``checks``.
"""

import numpy as np
from scipy.spatial import ConvexHull
from scipy.spatial.distance import pdist

from beeoptics.eye.lattice import mean_over_edges, neighbour_counts
from beeoptics.headframe import RIGHT, eye_azimuth_elevation, eye_direction

#: Half-width of the band around the equator within which the azimuthal
#: extent of the field of view is read, degrees: about one row of facets.
EQUATOR_BAND_DEG = 2.0
#: Fraction of receptors with the smallest Δφ whose median direction marks
#: where the eye samples most finely.
FINEST_FRACTION = 0.1
#: Spacing errors are also reported in this many bands of target diameter,
#: from the smallest facets to the largest.
DIAMETER_BANDS = 4


def lattice_quality(edges, boundary, geodesic, chord, target_um):
    """Neighbour statistics and spacing error of a relaxed lattice.

    Parameters
    ----------
    edges : ndarray, shape (m, 2)
        Delaunay neighbours.
    boundary : ndarray of bool
        Facets on the rim.
    geodesic, chord : ndarray, shape (m,)
        Geodesic and straight lengths of the edges, mm.
    target_um : ndarray
        The map's facet diameter at each facet, µm.
    """
    n = len(target_um)
    interior = ~boundary
    count = neighbour_counts(edges, n)
    error = mean_over_edges(edges, geodesic, n) * 1e3 / target_um - 1.0
    bands = np.array_split(np.argsort(target_um[interior]), DIAMETER_BANDS)
    err_in = np.abs(error[interior])
    ratio = geodesic / chord - 1.0
    return {
        "interior_facets": int(interior.sum()),
        "six_neighbour_fraction": float((count[interior] == 6).mean()),
        "neighbour_count_histogram": {int(k): int(v) for k, v in zip(*np.unique(count[interior], return_counts=True))},
        "spacing_median_abs_relative_error": float(np.median(err_in)),
        "spacing_median_relative_error": float(np.median(error[interior])),
        "spacing_error_by_diameter_band": [
            {
                "diameter_um": [float(target_um[interior][b].min()), float(target_um[interior][b].max())],
                "median_abs_relative_error": float(np.median(err_in[b])),
            }
            for b in bands
        ],
        "geodesic_over_chord_minus_one": {"median": float(np.median(ratio)), "max": float(ratio.max())},
    }


def optics_quality(axes_head, dphi, facet_um, points_head):
    """Δφ percentiles, field of view and size of one eye (the right one, head frame)."""
    az, el = eye_azimuth_elevation(axes_head, RIGHT)
    band = np.abs(el) <= EQUATOR_BAND_DEG
    finest = dphi <= np.quantile(dphi, FINEST_FRACTION)
    finest_dir = np.median(axes_head[finest], axis=0)
    f_az, f_el = eye_azimuth_elevation(finest_dir, RIGHT)
    hull = points_head[ConvexHull(points_head).vertices]
    return {
        "delta_phi_deg": {
            "p5": float(np.percentile(dphi, 5)),
            "p50": float(np.percentile(dphi, 50)),
            "p95": float(np.percentile(dphi, 95)),
        },
        "finest_sampling_direction_deg": {"azimuth": float(f_az), "elevation": float(f_el)},
        "field_of_view_deg": {
            "azimuth_at_equator": [float(az[band].min()), float(az[band].max())],
            "elevation": [float(el.min()), float(el.max())],
        },
        "facet_diameter_um": {"min": float(facet_um.min()), "max": float(facet_um.max())},
        "eye_length_mm": float(pdist(hull).max()),
    }


def zone_contrast(axes_head, dphi, facet_um, anchor, radius_deg):
    """Facet diameter and Δφ within ``radius_deg`` of an anchor's direction, and outside it."""
    centre = eye_direction(anchor["azimuth_deg"], anchor["elevation_deg"], RIGHT)
    inside = axes_head @ centre >= np.cos(np.radians(radius_deg))
    return {
        "anchor": anchor["name"],
        "radius_deg": radius_deg,
        "facets_inside": int(inside.sum()),
        "facet_diameter_um": {"inside": float(np.median(facet_um[inside])), "outside": float(np.median(facet_um[~inside]))},
        "delta_phi_deg": {"inside": float(np.median(dphi[inside])), "outside": float(np.median(dphi[~inside]))},
    }


def published_checks(eye, count, lattice, optics, zone):
    """Pass or fail for each published bound the eye description gives."""
    out = {}
    if eye.facet_count_sd is not None:
        out["facet_count_within_spread"] = bool(abs(count - eye.facet_count) <= eye.facet_count_sd)
    out["six_neighbour_fraction_at_least_0.85"] = lattice["six_neighbour_fraction"] >= 0.85
    out["spacing_error_at_most_5_percent"] = bool(
        lattice["spacing_median_abs_relative_error"] <= 0.05
        and all(b["median_abs_relative_error"] <= 0.05 for b in lattice["spacing_error_by_diameter_band"])
    )
    published = eye.published
    dp = published.get("delta_phi_deg")
    if dp:
        p = optics["delta_phi_deg"]
        if "median" in dp:
            out["delta_phi_median_in_range"] = dp["median"][0] <= p["p50"] <= dp["median"][1]
        if "p5_min" in dp:
            out["delta_phi_p5_at_least"] = p["p5"] >= dp["p5_min"]
        if "p95_max" in dp:
            out["delta_phi_p95_at_most"] = p["p95"] <= dp["p95_max"]
    fov = published.get("field_of_view_deg")
    if fov:
        tol = fov.get("tolerance", 10.0)
        got = optics["field_of_view_deg"]
        if "azimuth" in fov:
            out["fov_azimuth_within_tolerance"] = bool(
                np.all(np.abs(np.subtract(got["azimuth_at_equator"], fov["azimuth"])) <= tol)
            )
        if "elevation" in fov:
            out["fov_elevation_within_tolerance"] = bool(
                np.all(np.abs(np.subtract(got["elevation"], fov["elevation"])) <= tol)
            )
    finest = published.get("finest_sampling_deg")
    if finest:
        got = optics["finest_sampling_direction_deg"]
        out["finest_sampling_in_region"] = bool(
            finest["azimuth"][0] <= got["azimuth"] <= finest["azimuth"][1]
            and finest["elevation"][0] <= got["elevation"] <= finest["elevation"][1]
        )
    if zone:
        out["acute_zone_larger_facets_finer_sampling"] = bool(
            zone["facet_diameter_um"]["inside"] > zone["facet_diameter_um"]["outside"]
            and zone["delta_phi_deg"]["inside"] < zone["delta_phi_deg"]["outside"]
        )
    return {k: bool(v) for k, v in out.items()}
