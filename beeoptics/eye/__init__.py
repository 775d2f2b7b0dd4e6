"""The eye: from a hand-made mesh to the receptors of an eye pair, and how well they sample the world.

Stage by stage: the eye description (:mod:`.description`), remeshing
(:mod:`.remesh`), mesh queries and geodesics (:mod:`.meshquery`,
:mod:`.geodesic`), the facet-diameter map (:mod:`.facetmap`), the facet
lattice and its relaxation (:mod:`.lattice`, :mod:`.relax`), the measured
field and the axes mapped onto it (:mod:`.fieldmodel`, :mod:`.axismodel`),
corneas shaped from measurements (:mod:`.shape`), the dorsal rim area
(:mod:`.dorsalrim`), the receptors (:mod:`.receptors`), all of it together
(:mod:`.build`), then how good it
is (:mod:`.quality`), the receptors' optics (:mod:`.optics`), the field of
view on the sphere (:mod:`.fieldofview`) and the eye's acuity (:mod:`.acuity`).
"""

from beeoptics._exports import exports

__all__, __getattr__ = exports(__name__, {
    "description": ("EyeDescription", "load_eye", "load_eye_mesh"),
    "remesh": ("remesh", "smooth_normals", "target_edge_mm"),
    "meshquery": ("MeshQuery",),
    "geodesic": ("heat_distances", "pair_distances"),
    "facetmap": ("anchor_vertices", "diameter_map"),
    "lattice": ("MAX_EDGE", "conformal_map", "edge_angles", "hex_grid", "mean_over_edges", "neighbour_counts",
                "kernel_mean", "neighbour_edges", "project_grid", "sphere_triangles", "triangle_edges"),
    "fieldmodel": ("border", "delta_phi_horizontal", "delta_phi_vertical", "direction_of_shares", "inside",
                   "ommatidia_count", "row_count"),
    "axismodel": ("field_axes",),
    "shape": ("cornea", "field_outline"),
    "dorsalrim": ("dorsal_rim", "microvillar_angle", "rim_summary"),
    "relax": ("Relaxation", "fill_factor", "relax"),
    "receptors": ("delta_phi", "measure_spacing", "read_receptor_file", "receptor_format", "receptor_table",
                  "to_head"),
    "build": ("BuiltEye", "build_eye"),
    "quality": ("anisotropy", "field_match", "lattice_quality", "optics_quality", "published_checks", "size",
                "zone_contrast"),
    "optics": ("AcceptanceModel", "acceptance_angles", "acceptance_solid_angle", "angular_sensitivity",
               "measured_delta_rho", "nyquist_limit_cpd", "rayleigh_limit_deg", "snyder_delta_rho"),
    "fieldofview": ("EYE_BITS", "VisualField", "directions", "extent", "visual_field", "within_lattice"),
    "acuity": ("acuity",),
})
