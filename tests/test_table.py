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


def test_a_table_is_written_as_csv_writes_it_its_plain_rows_joined_without_it(tmp_path, monkeypatch):
    import csv
    import io

    real = csv.writer

    def as_csv(columns):
        out = io.StringIO(newline="")
        w = real(out)
        w.writerow(list(columns))
        w.writerows(zip(*[np.asarray(c).astype(str) if np.asarray(c).dtype.kind in "OUSb" else table._format(
            np.asarray(c), 9) for c in columns.values()]))
        return out.getvalue().encode()

    numbers = {"id": np.arange(3), "x": [0.1, np.nan, -2.5e-12], "side": ["left", "right", "left"]}
    words = {"species": ["Bellis perennis", 'a "daisy", white', "two\nlines"], "x": [1.0, np.nan, 3.0]}
    lone = {"x": [1.0, np.nan]}
    # csv's rows only where a field needs its quotes (or is a lone empty one): a flight's 42 MB of numbers is not.
    rows = []
    monkeypatch.setattr(csv, "writer", lambda f: type("W", (), {"writerow": real(f).writerow,
                                                                "writerows": lambda s, r: rows.append(1)
                                                                or real(f).writerows(r)})())
    for name, columns in (("numbers", numbers), ("words", words), ("lone", lone)):
        write_table(tmp_path / f"{name}.csv", columns)
        assert (tmp_path / f"{name}.csv").read_bytes() == as_csv(columns), name
    assert len(rows) == 2  # the words' and the lone column's
