"""Benchmark: the worker × meadow viewer's size, and how long headless Chromium takes to draw it.

    .venv/bin/python benchmarks/viewer.py [--page results/worker/meadow/viewer.html] [--runs 3]
    .venv/bin/python benchmarks/viewer.py --screenshot docs/viewer_worker_meadow.png --receptor 1200

Opens the page (written by the workflow's ``viewer`` rule: run ``make workflow`` first) from disk
in headless Chromium with the network blocked, ``--runs`` times, and reads the time the page
says it was drawn (``performance.now()`` once plotly has drawn it and its hover data are in
place: from the start of navigation, so parsing the page's 8 MB counts), on the real clock
(``drawn_s``) and on the virtual clock the tests' screenshots use (``drawn_virtual_s``), which
runs ahead of the real one by the timers Chromium skips (each opening takes a screenshot, as
Chromium's headless mode then ends once the page has loaded). The last line printed is one JSON
object: ``bytes``, ``megabytes``, ``drawn_s`` and ``drawn_virtual_s`` (the medians), ``runs``
and ``virtual_runs`` (each run's) and ``receptors``. Bounds (issue 26): ≤ 10 MB and drawn in
≤ 3 s. With ``--screenshot`` it also writes a PNG of the page with receptor ``--receptor``'s
hover label open: the README's figure.
"""

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

from record import record

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--page", type=Path, default=ROOT / "results" / "worker" / "meadow" / "viewer.html",
                        help="the viewer to open (default: %(default)s)")
    parser.add_argument("--runs", type=int, default=3, help="times to open it (default: %(default)s)")
    parser.add_argument("--screenshot", type=Path, help="also write a PNG of the page with a label open")
    parser.add_argument("--receptor", type=int, default=0, help="the receptor whose label the screenshot shows")
    args = parser.parse_args(argv)
    from beeoptics.images.headless import open_page

    if not args.page.exists():
        sys.exit(f"{args.page}: no such file (make workflow writes it)")
    page = args.page.resolve()
    runs = {True: [], False: []}
    for _ in range(args.runs):
        for virtual in runs:
            with tempfile.TemporaryDirectory() as tmp:
                seen = open_page(page, Path(tmp) / "page.png", virtual_time=virtual)
            if seen["errors"] or seen["drawn"] is None:
                sys.exit(f"{page}: not drawn offline: {seen['errors'][:2]}")
            runs[virtual].append(seen["drawn"]["drawn_ms"] / 1000.0)
    if args.screenshot is not None:
        open_page(page, args.screenshot.resolve(), f"#receptor={args.receptor}")
    size = page.stat().st_size
    record("viewer", {"page": str(args.page), "bytes": size, "megabytes": round(size / 1e6, 2),
                      "drawn_s": statistics.median(runs[False]), "runs": runs[False],
                      "drawn_virtual_s": statistics.median(runs[True]), "virtual_runs": runs[True],
                      "receptors": seen["drawn"]["receptors"]})


if __name__ == "__main__":
    main()
