"""Files in and out: tables, atomic writes, images, meshes, receptor tables, CompoundRay and PLY
interchange, and the checking of input files against their schemas.

Nothing here knows a stage of the pipeline; every stage reads and writes through it.
"""

from beeoptics._exports import exports

__all__, __getattr__ = exports(__name__, {
    "errors": ("InputError",),
    "atomic": ("atomic_path", "write_json"),
    "table": ("read_table", "write_table"),
    "imagefile": ("read_image", "write_exr", "write_png"),
    "meshfile": ("read_mesh", "read_mesh_normals", "write_mesh"),
    "receptortable": ("COLUMNS", "ReceptorTable", "read_receptors", "write_receptors"),
    "interchange": ("read_compoundray_eye", "read_receptor_ply", "write_compoundray_eye", "write_receptor_ply"),
    "validation": ("CONFIG_SCHEMA", "check_background", "config_default", "config_defaults", "load_yaml", "validate",
                   "validate_config"),
})
