"""How good a relaxed facet lattice is, and how close its optics come to the bee's.

The eye stage measures these itself and writes them to
``results/eyes/{eye}/quality.json``; the tests assert them. Where the eye
description gives published values, each comparison is also recorded as a
pass or fail under ``checks``.
"""

import igl
import numpy as np
from scipy.spatial import ConvexHull, cKDTree
from scipy.spatial.distance import pdist

from beeoptics.eye import fieldmodel
from beeoptics.eye.fieldofview import MAP_WIDTH_PX, extent, visual_field
from beeoptics.eye.lattice import mean_over_edges, neighbour_counts
from beeoptics.headframe import LEFT, RIGHT, eye_azimuth_elevation, eye_direction, in_eye_plane, mirror

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
    # A rim facet every triangle of which bridged the rim has no neighbour, and no Δφ (NaN).
    finest = dphi <= np.nanquantile(dphi, FINEST_FRACTION)
    finest_dir = np.median(axes_head[finest], axis=0)
    f_az, f_el = eye_azimuth_elevation(finest_dir, RIGHT)
    hull = points_head[ConvexHull(points_head).vertices]
    return {
        "delta_phi_deg": {
            "p5": float(np.nanpercentile(dphi, 5)),
            "p50": float(np.nanpercentile(dphi, 50)),
            "p95": float(np.nanpercentile(dphi, 95)),
            "facets_without_neighbours": int(np.isnan(dphi).sum()),
        },
        "finest_sampling_direction_deg": {"azimuth": float(f_az), "elevation": float(f_el)},
        "field_of_view_deg": {
            "azimuth_at_equator": [float(az[band].min()), float(az[band].max())],
            "elevation": [float(el.min()), float(el.max())],
        },
        "facet_diameter_um": {"min": float(facet_um.min()), "max": float(facet_um.max())},
        "eye_length_mm": float(pdist(hull).max()),
    }


def fields(axes_head, normals_head, delta_rho_deg, delta_phi_deg, normals_delta_phi_deg, width_px=MAP_WIDTH_PX):
    """Both eyes' fields with the receptors' axes and with the corneal normals at their facets.

    Parameters
    ----------
    axes_head, normals_head : ndarray (n, 3)
        The right eye's receptor axes and its cornea's normals at the facets, head frame.
    delta_rho_deg, delta_phi_deg, normals_delta_phi_deg : ndarray (n,)
        Acceptance angles, and the interommatidial angles of the axes and of the normals.

    Returns
    -------
    dict
        For ``axes`` and ``normals``: each eye's solid angle, the binocular
        overlap's and the total (sr and share of the sphere,
        :func:`beeoptics.eye.fieldofview.extent`), and the right eye's
        elevation limits and azimuth limits at the equator, degrees.
    """
    n = len(axes_head)
    sides = np.repeat([RIGHT, LEFT], n)
    out = {}
    for label, axes, dphi in (("axes", axes_head, delta_phi_deg), ("normals", normals_head, normals_delta_phi_deg)):
        field = visual_field(np.vstack([axes, mirror(axes)]), sides, np.tile(delta_rho_deg, 2), np.tile(dphi, 2),
                             width_px)
        az, el = eye_azimuth_elevation(axes, RIGHT)
        band = np.abs(el) <= EQUATOR_BAND_DEG
        out[label] = {**extent(field), "elevation_deg": [float(el.min()), float(el.max())],
                      "azimuth_at_equator_deg": [float(az[band].min()), float(az[band].max())] if band.any()
                      else None}
    return out


def field_match(axes_head, delta_rho_deg, delta_phi_deg, width_px=MAP_WIDTH_PX):
    """How one eye's field (the right one, head frame) covers the measured field and strays beyond it.

    A direction is in our field when it lies inside the lattice of axes or
    within Δρ/2 of one (:func:`beeoptics.eye.fieldofview.visual_field`), and
    in the measured field when :func:`beeoptics.eye.fieldmodel.inside` says
    so; both are weighed by solid angle.

    Returns
    -------
    dict
        ``covered``: the share of the measured field ours covers, the polar
        caps beyond the border's closed rings included
        (:func:`beeoptics.eye.fieldmodel.inside`), and ``covered_without_caps``
        the share of the band between them; ``outside``: the share of ours
        outside the measured field; both solid angles, sr.
    """
    field = visual_field(axes_head, np.full(len(axes_head), RIGHT), delta_rho_deg, delta_phi_deg, width_px)
    azimuth, elevation = np.meshgrid(field.azimuth_deg, field.elevation_deg)
    # Map azimuths run towards +y; an eye's run towards its own side, -y for the right eye.
    measured = fieldmodel.inside(-azimuth, elevation)
    band = fieldmodel.inside(-azimuth, elevation, caps=False)
    ours = field.eyes > 0
    weight = np.broadcast_to(np.cos(np.radians(field.elevation_deg))[:, None], ours.shape)
    pixel = (np.pi / ours.shape[0]) * (2.0 * np.pi / ours.shape[1])
    return {
        "covered": float(weight[ours & measured].sum() / weight[measured].sum()),
        "covered_without_caps": float(weight[ours & band].sum() / weight[band].sum()),
        "outside": float(weight[ours & ~measured].sum() / weight[ours].sum()),
        "ours_sr": float(weight[ours].sum() * pixel),
        "measured_sr": float(weight[measured].sum() * pixel),
    }


def anisotropy(points, axes_head, edges, rotation, lines="rows"):
    """Horizontal and vertical Δφ of a lattice against the field model, and the lattice's orientation.

    Seidl's (1982) Δφ_v is the angle between neighbours in a vertical
    column of ommatidia, his Δφ_h between neighbours in a horizontal row;
    columns are Δφ_h/2 apart and rows Δφ_v/2, every other one shifted by
    half a step (:mod:`beeoptics.eye.fieldmodel`). In a hexagonal lattice
    of lenses only one of the two is a line of adjacent facets: rows, with
    ``lines`` "rows", or columns, with "columns" (the eye description's
    ``lattice.lines``). In the eye's plane (anterior, dorsal), an edge within
    30° of the lines' direction (horizontal or vertical) joins neighbours in
    a line: its angle is a sample of that line's Δφ. The other edges join a
    facet to the next line, half a step along it: twice their step across
    the lines in the visual field samples the other Δφ (twice the
    difference in elevation for rows; twice the horizontal part of the
    angle, about the facet's own axis, for columns). Each facet's values are
    the means over its edges; the model's are taken at the facet's own axis.

    ``vertical_neighbours`` holds, per facet, the share of the directions
    to its six nearest neighbours that stand within 15° of the vertical in
    the visual field (:func:`vertical_neighbour_share`), its neighbours taken
    among the axes (``field``, as Stürzl et al.'s array is built: a third
    for Seidl's lattice) and among the lenses on the cornea (``lenses``:
    Seidl's columns are of adjacent facets; none for a lattice in rows),
    near the equator (|elevation| ≤ 20°, azimuth 20–140°) and over the eye.

    Parameters
    ----------
    points : ndarray (n, 3)
        Facets, the eye's local frame, mm.
    axes_head : ndarray (n, 3)
        Their axes, head frame (right eye).
    edges : ndarray (m, 2)
        Lattice neighbours.
    rotation : ndarray (3, 3)
        The eye's rotation.
    lines : {"rows", "columns"}
        How the eye's lenses line up.

    Returns
    -------
    dict
        Medians of ours and the model's Δφ_h and Δφ_v, the median per-facet
        ratios and the correlations over the facets, the ratio of horizontal
        to vertical, Δφ_v at the equator (|elevation| < 5°) and at
        |elevation| 45–75°, ``lines`` and ``lines_off_deg``, the angle of the
        lattice's lines from the head's horizontal (rows) or vertical
        (columns) in the eye's plane, degrees, and ``vertical_neighbours``.
    """
    planar = points[:, :2] @ in_eye_plane(rotation).T
    step = planar[edges[:, 1]] - planar[edges[:, 0]]
    direction = np.degrees(np.arctan2(step[:, 1], step[:, 0]))
    from_horizontal = np.abs((direction + 90.0) % 180.0 - 90.0)
    azimuth, elevation = eye_azimuth_elevation(axes_head, RIGHT)
    angle = np.degrees(np.arccos(np.clip((axes_head[edges[:, 0]] * axes_head[edges[:, 1]]).sum(1), -1.0, 1.0)))
    n = len(points)
    if lines == "columns":
        along = from_horizontal > 60.0
        cos = vertical_cosines(axes_head, edges[:, 0], edges[:, 1])
        across = 2.0 * angle * np.sqrt(1.0 - cos**2)
        ours_v = mean_over_edges(edges[along], angle[along], n)
        ours_h = mean_over_edges(edges[~along], across[~along], n)
    else:
        along = from_horizontal < 30.0
        across = 2.0 * np.abs(elevation[edges[:, 1]] - elevation[edges[:, 0]])
        ours_h = mean_over_edges(edges[along], angle[along], n)
        ours_v = mean_over_edges(edges[~along], across[~along], n)
    model_h = fieldmodel.delta_phi_horizontal(azimuth, elevation)
    model_v = fieldmodel.delta_phi_vertical(elevation)
    ok = np.isfinite(ours_h) & np.isfinite(ours_v)
    equator, high = np.abs(elevation) < 5.0, (np.abs(elevation) >= 45.0) & (np.abs(elevation) <= 75.0)
    # A hexagonal lattice is six-fold symmetric, so the mean of exp(6iθ) gives its orientation: rows
    # along the horizontal at 0°, columns along the vertical at 30° (modulo 60°).
    rows = np.degrees(np.angle(np.exp(6j * np.radians(direction)).mean())) / 6.0
    off = (rows - LINES_AT_DEG[lines] + 30.0) % 60.0 - 30.0
    middle = (np.abs(elevation) <= VERTICAL_BAND_DEG) & (azimuth >= VERTICAL_AZIMUTH_DEG[0]) & \
        (azimuth <= VERTICAL_AZIMUTH_DEG[1])
    shares = {kind: vertical_neighbour_share(among, axes_head) for kind, among in (("field", axes_head),
                                                                                   ("lenses", points))}

    def median(values, where=ok):
        # None (JSON's null) where no facet is, as where a patch of lattice does not reach 45–75° of elevation.
        return float(np.median(values[where])) if where.any() else None

    return {
        "delta_phi_h_deg": {"ours": median(ours_h), "model": median(model_h),
                            "median_ratio": median(ours_h / model_h),
                            "correlation": float(np.corrcoef(ours_h[ok], model_h[ok])[0, 1])},
        "delta_phi_v_deg": {"ours": median(ours_v), "model": median(model_v),
                            "median_ratio": median(ours_v / model_v),
                            "correlation": float(np.corrcoef(ours_v[ok], model_v[ok])[0, 1]),
                            "equator": {"ours": median(ours_v, ok & equator), "model": median(model_v, equator)},
                            "elevation_45_75": {"ours": median(ours_v, ok & high), "model": median(model_v, high)}},
        "horizontal_over_vertical": {"ours": median(ours_h) / median(ours_v),
                                     "model": median(model_h) / median(model_v)},
        "lines": lines,
        "lines_off_deg": float(off),
        "vertical_neighbours": {kind: {"equator": float(s[middle].mean()), "eye": float(s.mean())}
                                for kind, s in shares.items()} | {
            "within_deg": VERTICAL_WITHIN_DEG,
            "definition": (f"per facet, the share of the directions to its six nearest neighbours, nearest among "
                           f"the axes (field) or among the lenses' positions on the cornea (lenses), that stand "
                           f"within {VERTICAL_WITHIN_DEG:g} deg of the vertical in the visual field (the "
                           f"neighbours' axes about the facet's own); the mean over the facets near the equator "
                           f"(|elevation| <= {VERTICAL_BAND_DEG:g} deg, azimuth {VERTICAL_AZIMUTH_DEG[0]:g}-"
                           f"{VERTICAL_AZIMUTH_DEG[1]:g} deg) and over the eye")},
    }


#: Where a hexagonal lattice's six-fold orientation lies when its lines are horizontal rows or vertical
#: columns, degrees.
LINES_AT_DEG = {"rows": 0.0, "columns": 30.0}
#: Neighbour directions within this angle of the vertical count as vertical, degrees; and the region
#: near the equator where the share is read: |elevation| up to the band, azimuth within the range.
VERTICAL_WITHIN_DEG = 15.0
VERTICAL_BAND_DEG = 20.0
VERTICAL_AZIMUTH_DEG = (20.0, 140.0)


def vertical_cosines(axes_head, i, j):
    """|cos| of the angle between the visual vertical at axes ``i`` and the direction to axes ``j``.

    The direction is the step from one unit axis to the other in the plane
    tangent to the first, head frame; ``i`` and ``j`` broadcast together.
    """
    a = axes_head[i]
    step = axes_head[j] - a
    step -= (step * a).sum(-1, keepdims=True) * a
    up = np.array([0.0, 0.0, 1.0]) - a[..., 2:3] * a
    lengths = np.linalg.norm(step, axis=-1) * np.linalg.norm(up, axis=-1)
    return np.minimum(np.abs((step * up).sum(-1)) / lengths, 1.0)


def vertical_neighbour_share(among, axes_head):
    """For each facet, the share of the directions to its six nearest neighbours (nearest among ``among``: the
    axes, or the lenses' positions) that stand within :data:`VERTICAL_WITHIN_DEG` of the vertical in the visual
    field: of the neighbours' axes, about the facet's own, head frame."""
    near = cKDTree(among).query(among, k=7)[1]
    cos = vertical_cosines(axes_head, np.arange(len(among))[:, None], near[:, 1:])
    return (cos >= np.cos(np.radians(VERTICAL_WITHIN_DEG))).mean(1)


def size(vertices, faces, rotation, facet_count, facet_um):
    """The cornea's length, width and area, and the area its facets cover.

    Length and width are the mesh's extents along the head's dorsal and
    anterior directions in the eye's plane (as an eye is measured on a
    photograph of the head); the facets' area is count × √3/2 × mean(D²),
    hexagons of diameter D flat to flat.
    """
    planar = vertices[:, :2] @ in_eye_plane(rotation).T
    area = 0.5 * float(igl.doublearea(vertices, faces).sum())
    facets = float(facet_count * np.sqrt(3.0) / 2.0 * np.mean((np.asarray(facet_um) * 1e-3) ** 2))
    return {
        "eye_length_mm": float(np.ptp(planar[:, 1])),
        "eye_width_mm": float(np.ptp(planar[:, 0])),
        "corneal_area_mm2": area,
        "facets_area_mm2": facets,
        "mean_facet_area_um2": area / facet_count * 1e6,
        "facet_diameter_max_um": float(np.max(facet_um)),
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
        "delta_phi_deg": {"inside": float(np.nanmedian(dphi[inside])),
                          "outside": float(np.nanmedian(dphi[~inside]))},
    }


#: Bounds on the match to the measured field (issues 12 and 23 of the project): the share of the
#: measured field covered, of ours outside it, the median ratio of Δφ to the model's, the
#: correlation of Δφ with the model's over the facets, the angle of the lattice's lines from the
#: horizontal (rows) or the vertical (columns), degrees, and the share of neighbours straight
#: above or below in the visual field near the equator, among the axes and, for a lattice in
#: columns, among the lenses (an array built by Stürzl et al.'s recipe has 0.23 of them).
FIELD_COVERED_MIN, FIELD_OUTSIDE_MAX = 0.9, 0.1
DELTA_PHI_RATIO_TOLERANCE = 0.1
DELTA_PHI_CORRELATION_MIN = 0.5
LINES_OFF_MAX_DEG = 10.0
LINES_ALONG = {"rows": "horizontal", "columns": "vertical"}
VERTICAL_NEIGHBOURS_MIN = 0.15


def published_checks(eye, count, lattice, optics, zone, field=None, sizes=None, seen=None):
    """Pass or fail for each published bound the eye description gives (``seen``: :func:`fields`)."""
    out = {}
    if field is not None:
        out["field_covered_at_least_0.9"] = field["coverage"]["covered"] >= FIELD_COVERED_MIN
        out["field_outside_at_most_0.1"] = field["coverage"]["outside"] <= FIELD_OUTSIDE_MAX
    if field is not None and "anisotropy" in field and eye.axis_model == "field":
        shape = field["anisotropy"]
        for key in ("delta_phi_h_deg", "delta_phi_v_deg"):
            out[f"{key}_median_ratio_within_10_percent"] = abs(shape[key]["median_ratio"] - 1.0) <= \
                DELTA_PHI_RATIO_TOLERANCE
            out[f"{key}_correlation_at_least_0.5"] = shape[key]["correlation"] >= DELTA_PHI_CORRELATION_MIN
        ratio = shape["horizontal_over_vertical"]
        out["horizontal_over_vertical_within_10_percent"] = abs(ratio["ours"] / ratio["model"] - 1.0) <= \
            DELTA_PHI_RATIO_TOLERANCE
        out[f"{shape['lines']}_{LINES_ALONG[shape['lines']]}_within_10_deg"] = \
            abs(shape["lines_off_deg"]) <= LINES_OFF_MAX_DEG
        out["vertical_neighbours_in_the_field_near_the_equator_at_least_0.15"] = \
            shape["vertical_neighbours"]["field"]["equator"] >= VERTICAL_NEIGHBOURS_MIN
        if shape["lines"] == "columns":
            out["vertical_neighbours_among_lenses_near_the_equator_at_least_0.15"] = \
                shape["vertical_neighbours"]["lenses"]["equator"] >= VERTICAL_NEIGHBOURS_MIN
    for key in ("eye_length_mm", "eye_width_mm", "corneal_area_mm2", "facet_diameter_max_um"):
        spec = eye.published.get(key)
        if spec and sizes is not None:
            out[f"{key}_within_tolerance"] = abs(sizes[key] / spec["value"] - 1.0) <= spec["tolerance"]
    spec = eye.published.get("field_fraction")
    if spec and seen is not None:
        out["field_fraction_within_tolerance"] = abs(seen["axes"]["right_fraction"] / spec["value"] - 1.0) <= \
            spec["tolerance"]
    if eye.facet_count_sd is not None:
        out["facet_count_within_spread"] = bool(abs(count - eye.facet_count) <= eye.facet_count_sd)
    if lattice is not None:  # a relaxed lattice's; given receptors have none
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
