"""CSV tables of named columns, the form every per-receptor result takes.

Tables are plain comma-separated text with a header row, readable as they
are by R (``read.csv``), pandas or a spreadsheet. Floats are written with
nine significant digits, enough to round-trip the float32 values of the
tracer and to keep metre-scale scene coordinates at micrometre precision.
A value that is not defined (NaN) is an empty field, which R reads as NA
and pandas as NaN, and which is read back here as NaN.
"""

import csv
import functools
import os

import numpy as np

from beeoptics.io.atomic import atomic_path
from beeoptics.io.errors import InputError
from beeoptics.io.provenance import note


#: The characters for which csv quotes a field: its delimiter, its quote and those of its line ends.
QUOTED = frozenset(',"\r\n')


def write_table(path, columns, digits=9):
    """Write a dict of equal-length columns to a CSV file, atomically, floats to ``digits`` significant digits."""
    names = list(columns)
    cols = [np.asarray(columns[k]) for k in names]
    n = len(cols[0])
    if any(len(c) != n for c in cols):
        raise ValueError("columns differ in length")
    words = [c.dtype.kind in "OUSb" for c in cols]
    text = [c.astype(str) if word else _format(c, digits) for c, word in zip(cols, words)]
    # Fields csv would not quote (numbers, and words without its delimiter, quote or line ends: every table here),
    # joined as csv joins them, five times as fast (a flight's responses, 42 MB: 0.2 s against 1.1); the same bytes.
    # csv quotes a lone empty field, which a table of one column may have.
    plain = len(names) > 1 and not any(QUOTED.intersection(v) for c, word in zip(text, words) if word for v in c)
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(names)
        if plain:
            f.writelines(",".join(row) + "\r\n" for row in zip(*text))
        else:
            w.writerows(zip(*text))


def _format(column, digits):
    if column.dtype.kind in "iu":
        return column.astype(str)
    # Python's own formatting, value by value: four times as fast as numpy's char.mod, which calls it too.
    form = f"%.{digits}g"
    return [form % v if v == v else "" for v in column.astype(float).tolist()]


def read_table(path, numeric=(), text=()):
    """Read a CSV table into a dict of arrays: numbers as int or float, others as str.

    Parameters
    ----------
    path : str or Path
    numeric, text : sequence of str
        Columns that must be present; ``numeric`` ones must hold numbers.

    Empty fields of a column of numbers are NaN. A file read again while
    unchanged (its inode, size and modification time) is parsed once: a
    stage's functions each read the responses and receptors they need (an
    eye's images job read its tables seven times). Each call returns arrays
    of its own.

    Raises
    ------
    InputError
        If the file is missing or empty, a listed column is absent, or a
        numeric column holds something else (naming its row and value).
    """
    note(path)
    try:
        stat = os.stat(path)
    except FileNotFoundError:
        raise InputError(path, "", "no such file") from None
    columns = _parsed(path, stat.st_ino, stat.st_size, stat.st_mtime_ns)
    for name in [*numeric, *text]:
        if name not in columns:
            raise InputError(path, name, "missing column")
    for name in numeric:
        if columns[name].dtype.kind not in "iuf":
            row, value = next((k, v) for k, v in enumerate(columns[name].tolist(), 2) if not _is_number(v))
            raise InputError(path, name, f"row {row}: {value!r} is not a number")
    return {name: values.copy() for name, values in columns.items()}


@functools.lru_cache(maxsize=8)
def _parsed(path, inode, size, mtime_ns):
    """The columns of the table at ``path``, parsed once while it keeps its inode, size and modification time
    (nanoseconds; a file rewritten atomically is a new inode)."""
    try:
        # utf-8-sig: spreadsheets (Excel's "CSV UTF-8") begin the file with a byte-order mark, which
        # would otherwise become part of the first column's name.
        with open(path, newline="", encoding="utf-8-sig") as f:
            rows = list(csv.reader(f))
    except FileNotFoundError:
        raise InputError(path, "", "no such file") from None
    except UnicodeDecodeError:
        raise InputError(path, "", "not a UTF-8 text file") from None
    if not rows:
        raise InputError(path, "", "the table is empty")
    header, body = rows[0], rows[1:]
    short = next((k for k, r in enumerate(body, 2) if len(r) != len(header)), None)
    if short is not None:
        raise InputError(path, f"row {short}", f"has {len(body[short - 2])} fields; the header has {len(header)}")
    return {name: _parse(values) for name, values in zip(header, zip(*body) if body else [()] * len(header))}


def _parse(values):
    try:
        return np.array([int(v) for v in values])
    except ValueError:
        pass
    try:
        # An empty field is NaN; one of blanks fails here, and is NaN too below.
        return np.array([float(v or "nan") for v in values])
    except ValueError:
        pass
    try:
        return np.array([float(v) if v.strip() else np.nan for v in values])
    except ValueError:
        return np.array(values)


def _is_number(text):
    try:
        float(text)
    except ValueError:
        return not text.strip()
    return True


#: Significant digits of measured data written into the package: every digit of the published values.
MEASURED_DIGITS = 12


def import_table(source, target, columns, minimum=None):
    """Write a published table of measurements into the package's layout.

    The package keeps each measurement it needs at run time in its own
    layout, written by this function from the published file: the columns
    named as the package names them (``columns`` maps the source's names
    to ours, in the order written), values unchanged to the twelve
    significant digits they are written with, more than any published
    value here has. The source and licence stand in the data folder's README.

    Parameters
    ----------
    source, target : path
    columns : dict of str to str
        Source column → the package's name.
    minimum : float, optional
        Values below it are set to it: pavo's ``sensdata`` sets the negative
        ends of recorded spectral sensitivities to zero, and so does the
        package, once, here.
    """
    table = read_table(source, numeric=list(columns))
    out = {ours: np.asarray(table[theirs], float) for theirs, ours in columns.items()}
    if minimum is not None:
        out = {k: np.maximum(v, minimum) for k, v in out.items()}
    write_table(target, out, MEASURED_DIGITS)
