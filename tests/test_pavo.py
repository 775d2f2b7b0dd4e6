"""A view's catches in pavo's vismodel layout: the columns and row names pavo reads, and pavo's own formulas on
them giving the view's colour coordinates back.

pavo's source, rmaia/pavo at eb19786458ee1318ff69666d80c104b1ab05a1c4 (pavo 2.10.0), is cited by file and line.
"""

import io

import numpy as np
import pandas as pd
import pytest

from beeoptics.io.errors import InputError
from beeoptics.vision.colourspace import colour_coordinates
from beeoptics.vision.pavo import vismodel_table
from beeoptics.vision.receptorset import load_receptor_set


@pytest.fixture(scope="module")
def apis():
    return load_receptor_set("apis_mellifera")


def responses(receptor_set, n=6):
    """A responses.csv's rows of ``n`` receptors: ids from 100, catches drawn at random, the last receptor unlit."""
    q = np.random.default_rng(7).uniform(0.05, 3.0, (n, len(receptor_set.classes)))
    q[-1] = 0.0
    return pd.DataFrame({"id": np.arange(100, 100 + n), **colour_coordinates(q, q[:-1].mean(0), receptor_set)})


def test_the_honey_bee_table_has_pavos_columns_and_row_names(apis):
    table = vismodel_table(responses(apis), apis, background=True)
    # R/hexagon.R line 59 and R/trispace.R line 43 read s, m, l; R/vismodel.R line 264 names the apis
    # receptors so (sensdata's apis.s, apis.m, apis.l, less "apis."), line 405 appends lum after them, and
    # R/coldist.R line 201 takes the last column for lum when achromatic = TRUE.
    assert list(table.columns) == ["s", "m", "l", "lum"]
    # R/coldist.R line 151 labels the pairs by row name: the receptor ids, and the background's row.
    assert table.index.name == "id" and table.index.tolist() == [*range(100, 106), "background"]
    csv = table.to_csv()
    assert csv.splitlines()[0] == "id,s,m,l,lum"
    # The unlit receptor's row is empty fields, which R's read.csv reads as NA.
    assert csv.splitlines()[-2] == "105,,,,"
    back = pd.read_csv(io.StringIO(csv), index_col=0)
    np.testing.assert_allclose(back.loc["background"], 1.0)
    # lum is the achromatic class's catch, the honey bee's G receptor (pavo's achromatic = "l", R/vismodel.R line 400).
    np.testing.assert_array_equal(table["lum"], table["l"])


def test_pavos_formulas_on_the_table_give_the_views_colour(apis):
    rows = responses(apis)
    lit = rows["lit"].to_numpy(bool)
    e = vismodel_table(rows, apis, qcatch="Ei")
    # R/hexagon.R lines 68-69.
    x = np.sqrt(3) / 2 * (e["l"] - e["s"])
    y = e["m"] - 0.5 * (e["s"] + e["l"])
    np.testing.assert_allclose(x[lit], rows["hex_x"][lit], rtol=1e-12)
    np.testing.assert_allclose(y[lit], rows["hex_y"][lit], rtol=1e-12)
    # R/coldist.R: qcatch = "Qi" is logged (line 245); with a Weber fraction for every class the noise is
    # those fractions whatever n (lines 482-483 and 489, e = weber √(n/Σn) / √(n/Σn)); the trichromat's
    # ΔS of Vorobyev & Osorio (1998), each receptor against the background's row.
    q = vismodel_table(rows, apis, background=True)
    f = np.log(q[["s", "m", "l"]].to_numpy())
    d = f[:-1] - f[-1]
    es, em, el = apis.weber
    ds = np.sqrt((es**2 * (d[:, 2] - d[:, 1])**2 + em**2 * (d[:, 2] - d[:, 0])**2 + el**2 * (d[:, 0] - d[:, 1])**2)
                 / ((es * em)**2 + (es * el)**2 + (em * el)**2))
    np.testing.assert_allclose(ds[lit], rows["rnl_dS"][lit], rtol=1e-12)
    np.testing.assert_array_equal(vismodel_table(rows, apis, qcatch="fi").to_numpy(), np.log(q.to_numpy()[:-1]))


def test_other_species_take_pavos_names_for_their_number_of_classes():
    bumblebee = load_receptor_set("bombus_terrestris")
    assert list(vismodel_table(responses(bumblebee), bumblebee).columns) == ["s", "m", "l", "lum"]
    # R/tcspace.R line 46: a tetrachromat's u, s, m, l; the fly's colour classes R7p, R7y, R8p, R8y are pavo's
    # drosophila.u, .s, .m, .l, and its lum the outer receptors' (pavo's dm.r1).
    fly = load_receptor_set("drosophila_melanogaster")
    rows = responses(fly)
    table = vismodel_table(rows, fly)
    assert list(table.columns) == ["u", "s", "m", "l", "lum"]
    np.testing.assert_array_equal(table["u"], rows["q_R7p"])
    np.testing.assert_array_equal(table["lum"], rows["q_R1_6"])


def test_a_scale_pavo_does_not_have_or_a_missing_column_is_refused(apis):
    rows = responses(apis)
    with pytest.raises(InputError, match="qcatch: 'Ri' is not one of pavo's: Qi, fi, Ei"):
        vismodel_table(rows, apis, qcatch="Ri")
    with pytest.raises(InputError, match="q_B: missing column"):
        vismodel_table(rows.drop(columns="q_B"), apis)
