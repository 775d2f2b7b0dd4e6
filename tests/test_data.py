"""The package's measured data: each file is what the package's importer writes from the published file.

The workflow needs these at run time, when ``../shared`` is not there, so they ship in the
package; these tests write each again from the published file beside the repository and
compare bytes, so the shipped values are the published ones and the writer is the package's.
"""

import pytest

from beeoptics.io.table import import_table
from conftest import ROOT

PACKAGE = ROOT / "beeoptics"
#: Shipped file: (published file under ../shared/data, source columns → ours, minimum).
IMPORTS = {
    "vision/data/apis_mellifera_peitsch1992.csv": (
        "apis_sensitivity_peitsch1992.csv", {"wl": "wl", "apis.s": "UV", "apis.m": "B", "apis.l": "G"}, None),
    "vision/data/drosophila_melanogaster_sharkey2020.csv": (
        "drosophila/drosophila_sensitivity_sharkey2020.csv",
        {"wl": "wl", "dm.r1": "R1_6", "drosophila.u": "R7p", "drosophila.s": "R7y", "drosophila.m": "R8p",
         "drosophila.l": "R8y"}, 0.0),
    "eye/data/apis_mellifera_worker_field_border_stuerzl2010.csv": (
        "worker_eye_border_stuerzl2010.csv",
        {"elevation_1_2": "lateral_elevation_deg", "azimuth_max_1_2": "lateral_azimuth_deg",
         "elevation_3_4": "medial_elevation_deg", "azimuth_max_3_4": "medial_azimuth_deg"}, None),
    "light/data/ground_albedo_feister_grewe1995.csv": (
        "ground_albedo_feister_grewe1995.csv",
        {c: c for c in ("wl", "loam", "sand", "grass", "lawn", "stubble", "beet", "oat", "rye", "concrete_dry",
                        "concrete_wet", "snow")}, None),
}


@pytest.mark.parametrize("shipped", sorted(IMPORTS))
def test_a_shipped_measurement_is_the_published_one_written_by_the_package(shipped, shared_data, tmp_path):
    source, columns, minimum = IMPORTS[shipped]
    import_table(shared_data / source, tmp_path / "again.csv", columns, minimum)
    assert (tmp_path / "again.csv").read_bytes() == (PACKAGE / shipped).read_bytes()
    # Not a copy: the package writes its own layout.
    assert (PACKAGE / shipped).read_bytes() != (shared_data / source).read_bytes()
