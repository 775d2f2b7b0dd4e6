"""A table of catches in the layout of pavo's ``vismodel`` output, for R users.

pavo (Maia et al. 2019) models colour vision from a data frame of quantum
catches: ``vismodel`` returns one row per stimulus, its row names the
stimuli's names, and one column per receptor class, then ``lum``, the
achromatic receptor's catch (NA when none is modelled). The receptor columns
are named by pavo's convention for the number of classes, the names its
colour spaces read: ``s``, ``l`` for a dichromat, ``s``, ``m``, ``l`` for a
trichromat (the honey bee's UV, B and G receptors) and ``u``, ``s``, ``m``,
``l`` for a tetrachromat. ``coldist`` and ``colspace`` take such a table read
with ``read.csv(..., row.names = 1)``, told its ``qcatch``.

Sources, rmaia/pavo at eb19786458ee1318ff69666d80c104b1ab05a1c4 (pavo 2.10.0):
``R/vismodel.R`` lines 264 (receptor columns named by the visual system,
``apis`` giving s, m, l), 405 (``lum`` appended), 426 (``lum`` left out of
von Kries's correction) and 457 (``lum`` NA without an achromatic receptor);
``R/dispace.R`` line 33, ``R/trispace.R`` line 43, ``R/hexagon.R`` line 59 and
``R/tcspace.R`` line 46 (the names each space reads); ``R/coldist.R`` lines
151 (pairs labelled by row name), 201 (with ``achromatic = TRUE`` the last
column is ``lum``) and 220 (``qcatch`` required of a plain data frame).

References
----------
Maia R, Gruson H, Endler JA, White TE (2019) pavo 2: new tools for the
spectral and spatial analysis of colour in R. Methods Ecol Evol 10:1097–1107.
"""

import numpy as np
import pandas as pd

from beeoptics.io.errors import InputError

#: pavo's receptor names by the number of classes colour vision compares, shortest wavelength first.
PAVO_NAMES = {2: ("s", "l"), 3: ("s", "m", "l"), 4: ("u", "s", "m", "l")}
#: pavo's ``qcatch`` options from the von Kries-adapted catch q: q itself, Fechner's ln q, excitation q/(q + 1).
QCATCH = {"Qi": lambda q: q, "fi": np.log, "Ei": lambda q: q / (q + 1.0)}


def vismodel_table(responses, receptor_set, qcatch="Qi", background=False):
    """Receptors' catches as pavo's ``vismodel(..., relative = FALSE, vonkries = TRUE)`` returns them.

    Parameters
    ----------
    responses : pandas.DataFrame
        Rows of ``responses.csv`` (``view.table()``, or the file read with
        pandas): ``id`` and the von Kries-adapted catch ``q_<class>`` of each
        class (dimensionless, the background's 1). Any subset of rows: pavo's
        ``coldist`` compares every pair of rows, so give it the receptors to
        compare (a flower's), not a whole eye's.
    receptor_set : beeoptics.vision.ReceptorSet
        The eye's receptor set: its colour classes, shortest wavelength first,
        become pavo's columns, and its achromatic class ``lum``.
    qcatch : {"Qi", "fi", "Ei"}
        pavo's scale of the catches: q (for ``coldist``), ln q (Fechner) or
        the excitation q/(q + 1) (for ``colspace(space = "hexagon")``).
    background : bool
        Append a row named ``background``: the adapting background itself, q = 1
        in every class (von Kries's definition), so that
        ``coldist(..., subset = "background")`` gives each receptor's distance
        from it (the view's ``rnl_dS``, ``hex_r`` through the hexagon).

    Returns
    -------
    pandas.DataFrame
        Indexed by receptor id (``id``), one column per colour class named as
        pavo names it, then ``lum``, the achromatic class's catch on the same
        scale (pavo leaves its ``lum`` unadapted; the contrasts ``coldist``
        takes from it are the same). A receptor that caught no light has NaN,
        which ``to_csv`` writes empty and R reads as NA.

    Raises
    ------
    InputError
        If the set's colour vision has other than two to four classes, pavo's
        spaces, ``qcatch`` is not one of pavo's, or a column is missing.
    """
    colour = [receptor_set.classes[i] for i in receptor_set.chromatic]
    if len(colour) not in PAVO_NAMES:
        raise InputError(receptor_set.path, "colour.classes", f"pavo names the receptors of di-, tri- and "
                         f"tetrachromats; this set's colour vision has {len(colour)} classes")
    if qcatch not in QCATCH:
        raise InputError("vismodel_table", "qcatch", f"{qcatch!r} is not one of pavo's: {', '.join(QCATCH)}")
    wanted = ["id", *(f"q_{k}" for k in [*colour, receptor_set.classes[receptor_set.achromatic]])]
    missing = [c for c in wanted if c not in responses]
    if missing:
        raise InputError("vismodel_table", missing[0], "missing column (responses.csv's q_<class> for each class)")
    q = responses[wanted[1:]].to_numpy(float)
    ids = responses["id"].tolist()
    if background:
        q, ids = np.vstack([q, np.ones(len(wanted) - 1)]), [*ids, "background"]
    return pd.DataFrame(QCATCH[qcatch](q), index=pd.Index(ids, name="id"),
                        columns=[*PAVO_NAMES[len(colour)], "lum"])
