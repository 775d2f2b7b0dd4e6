import numpy as np

from beeoptics.io import table
from beeoptics.io.table import read_table, write_table


def test_a_table_read_again_is_parsed_once_until_it_is_rewritten(tmp_path, monkeypatch):
    """An eye's images job reads its responses four times and its receptors three: each file is parsed once,
    each read gets arrays of its own, and a rewritten file is read anew."""
    parsed = []
    parse = table._parse
    monkeypatch.setattr(table, "_parse", lambda values, *args, **kwargs: parsed.append(1) or parse(values, *args,
                                                                                                      **kwargs))
    path = tmp_path / "responses.csv"
    write_table(path, {"id": [0, 1], "side": ["right", "left"], "UV": [1.5, np.nan]})
    first = read_table(path, numeric=["id", "UV"], text=["side"])
    first["UV"][0] = -1.0
    second = read_table(path, numeric=["UV"])
    assert len(parsed) == 3
    np.testing.assert_array_equal(second["UV"], [1.5, np.nan])
    assert list(second["side"]) == ["right", "left"]
    write_table(path, {"id": [0, 1], "side": ["right", "left"], "UV": [2.5, 3.0]})
    np.testing.assert_array_equal(read_table(path)["UV"], [2.5, 3.0])
    assert len(parsed) == 6
