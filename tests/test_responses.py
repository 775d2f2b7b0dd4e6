"""responses.csv's colour columns follow from its own catch columns, as the README states."""

import re

import numpy as np
import pytest

from beeoptics.eye.optics import acceptance_solid_angle
from beeoptics.io.receptortable import COLUMNS, read_receptors
from beeoptics.io.table import read_table, write_table
from beeoptics.light.scene import load_scene
from beeoptics.pipeline.trace import gather_responses
from beeoptics.tracing import respond
from beeoptics.spectra import grid
from beeoptics.vision.catches import quantum_catches
from beeoptics.vision.colourspace import excitation
from beeoptics.vision.receptorset import brightness_weights, curves, load_receptor_set
from conftest import DATA, ROOT

SPECTRAL = {"start_nm": 300, "end_nm": 700, "step_nm": 10}
FLOWER = DATA / "scenes" / "flower" / "scene.yaml"


def _responses(tmp_path, receptor_set, background):
    """Gather a table of 300 receptors of acceptance angles 1.5–4° seeing random spectra, some none."""
    rng = np.random.default_rng(37)
    n, wl = 300, grid(**SPECTRAL)
    axes = rng.normal(size=(n, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    table = dict(zip(COLUMNS, (np.arange(n), np.where(np.arange(n) % 2, "left", "right"), *rng.normal(size=(3, n)),
                               *axes.T, np.full(n, 20.0), np.full(n, 2.0), rng.uniform(1.5, 4.0, n))))
    write_table(tmp_path / "receptors.csv", table)
    # Each receptor a random mix of three smooth spectra, W m⁻² sr⁻¹ nm⁻¹; one in ten sees nothing.
    basis = np.stack([np.exp(-0.5 * ((wl - m) / 60.0) ** 2) for m in (350.0, 480.0, 600.0)])
    radiance = rng.uniform(0.0, 0.05, (n, 3)) @ basis * (rng.random(n) > 0.1)[:, None]
    # Eight replicates scattered about it, and their catches as the trace gives them.
    spread = rng.uniform(0.8, 1.2, (n, 8, 1))
    replicates = radiance[:, None] * spread / spread.mean(axis=1, keepdims=True)
    omega = acceptance_solid_angle(table["delta_rho_deg"])
    catches = quantum_catches(replicates * omega[:, None, None], curves(receptor_set, wl), wl)
    np.savez(tmp_path / "part.npz", id=np.arange(n), radiance=radiance, catches=catches,
             radiance_se=replicates.std(axis=1, ddof=1) / np.sqrt(8), samples=np.full(n, 256))
    out = {"responses": tmp_path / "responses.csv", "irradiance": tmp_path / "irradiance.npz"}
    gather_responses(tmp_path / "receptors.csv", FLOWER, [tmp_path / "part.npz"], out, spectral=SPECTRAL,
                     receptor_set=receptor_set, background=background)
    return read_table(out["responses"]), np.load(out["irradiance"]), wl, catches


@pytest.mark.parametrize("species, background", [("apis_mellifera", "scene"), ("apis_mellifera", "leaf"),
                                                 ("drosophila_melanogaster", "scene")])
def test_the_colour_columns_follow_from_the_tables_own_catches(tmp_path, species, background):
    rs = load_receptor_set(species)
    table, arrays, wl, replicate_catches = _responses(tmp_path, rs, background)
    q = np.column_stack([table[c] for c in rs.classes]).astype(float)
    # Each receptor's catch over its acceptance solid angle, adapted to the scene's mean of it over the
    # receptors that have the class, or to a material's (the irradiance file's background_q).
    radiance_q = q / table["acceptance_sr"][:, None]
    reference = np.nanmean(radiance_q, axis=0) if background == "scene" else arrays["background_q"]
    lit = (q > 0).any(axis=1)
    adapted = np.where(lit[:, None], radiance_q / reference, np.nan)
    e = adapted / (adapted + 1)
    # Each class's standard error from its eight replicates' catches; the samples as the trace took them.
    se = np.where(np.isnan(q), np.nan, replicate_catches.std(axis=1, ddof=1) / np.sqrt(8))
    expect = {"lit": lit.astype(int), **{f"q_{c}": adapted[:, k] for k, c in enumerate(rs.classes)},
              **{f"se_{c}": se[:, k] for k, c in enumerate(rs.classes)}, "samples": np.full(len(q), 256),
              **{f"E_{c}": e[:, k] for k, c in enumerate(rs.classes)}}
    if rs.overall is not None:
        expect["brightness"] = q @ brightness_weights(rs, wl, curves(rs, wl))
    if rs.spaces:
        # pavo's formulas (R/hexagon.R, R/coc.R, R/trispace.R), written out.
        uv, b, g = e[:, rs.chromatic].T
        x, y = np.sqrt(3) / 2 * (g - uv), b - (uv + g) / 2
        rel = adapted[:, rs.chromatic] / adapted[:, rs.chromatic].sum(1, keepdims=True)
        expect.update(hex_x=x, hex_y=y, hex_hue_deg=(90 - np.degrees(np.arctan2(y, x))) % 360, hex_r=np.hypot(x, y),
                      coc_A=-9.86 * uv + 7.70 * b + 2.16 * g, coc_B=-5.17 * uv + 20.25 * b - 15.08 * g,
                      tri_x=(rel[:, 2] - rel[:, 1]) / np.sqrt(2),
                      tri_y=np.sqrt(2 / 3) * (rel[:, 0] - (rel[:, 1] + rel[:, 2]) / 2))
    if rs.weber is not None:
        # Vorobyev & Osorio (1998), eq. for trichromats, against the background (log q = 0).
        (e1, e2, e3), (f1, f2, f3) = rs.weber, np.log(adapted[:, rs.chromatic]).T
        expect["rnl_dS"] = np.sqrt((e1**2 * (f3 - f2) ** 2 + e2**2 * (f3 - f1) ** 2 + e3**2 * (f1 - f2) ** 2)
                                   / ((e1 * e2) ** 2 + (e1 * e3) ** 2 + (e2 * e3) ** 2))
    # The colour columns' errors need the replicates, not the table: the test below checks them.
    derived_se = {c for c in table if c.startswith("se_") and c[3:] not in rs.classes}
    assert set(expect) | {"id", "side", "acceptance_sr", "ommatidium", *rs.classes} >= set(table) - derived_se
    assert not lit.all() and np.ptp(table["acceptance_sr"]) > 0
    for name, values in expect.items():
        # The table's nine significant digits.
        np.testing.assert_allclose(np.asarray(table[name], float), values, rtol=1e-7, atol=1e-7, err_msg=name)


def test_with_replicate_catches_each_colour_column_has_its_standard_error_beside_it(tmp_path):
    rs = load_receptor_set("apis_mellifera")
    table, _, wl, _ = _responses(tmp_path, rs, "scene")
    receptors, scene = read_receptors(tmp_path / "receptors.csv"), load_scene(FLOWER, wl, geometry=False)
    radiance = np.load(tmp_path / "part.npz")["radiance"]
    q = np.column_stack([table[c] for c in rs.classes]).astype(float)
    # Synthetic replicates: the catches times 5 % lognormal noise, eight a receptor.
    replicates = q[:, None] * np.random.default_rng(4).lognormal(0.0, 0.05, (len(q), 8, 3))
    plain, _ = respond(receptors, radiance, scene, wl, FLOWER, receptor_set=rs)
    columns, _ = respond(receptors, radiance, scene, wl, FLOWER, receptor_set=rs, replicate_catches=replicates)
    colour = [c for c in plain if c not in ("id", "side", "acceptance_sr", "brightness", "lit", *rs.classes)]
    names = list(columns)
    for c in colour:
        np.testing.assert_array_equal(columns[c], plain[c])
        assert names[names.index(c) + 1] == f"se_{c}", c
    assert not any(c.startswith("se_") for c in plain)
    # The replicate estimate with the table's own background for every replicate.
    omega = table["acceptance_sr"][:, None]
    reference = np.nanmean(q / omega, axis=0)
    e = excitation(replicates / omega[:, None] / reference)
    x = np.sqrt(3) / 2 * (e[..., 2] - e[..., 0])
    lit = (q > 0).any(1)
    np.testing.assert_allclose(columns["se_hex_x"][lit], x[lit].std(1, ddof=1) / np.sqrt(8), rtol=1e-7)
    # The hue's error on the circle: small where the receptor is coloured, whichever side of 0° it lies.
    coloured = lit & (columns["hex_r"] > 0.1)
    assert (columns["se_hex_hue_deg"][coloured] < 20.0).all()


def test_the_readme_names_every_column_of_responses_csv(tmp_path):
    rs = load_receptor_set("apis_mellifera")
    table, _, wl, _ = _responses(tmp_path, rs, "scene")
    receptors, scene = read_receptors(tmp_path / "receptors.csv"), load_scene(FLOWER, wl, geometry=False)
    q = np.column_stack([table[c] for c in rs.classes]).astype(float)
    columns, _ = respond(receptors, np.load(tmp_path / "part.npz")["radiance"], scene, wl, FLOWER, receptor_set=rs,
                         replicate_catches=np.repeat(q[:, None], 2, 1))
    text = (ROOT / "README.md").read_text()
    entry = text[text.index("responses.csv       per receptor"):text.index("    parts/ ")]
    for name in columns:
        # A class's columns are named once for all classes: q_UV, q_B, q_G as q_*.
        generic = re.sub(rf"_({'|'.join(rs.classes)})$", "_*", name)
        assert re.search(rf"\b{re.escape(name)}\b|{re.escape(generic)}", entry), name
