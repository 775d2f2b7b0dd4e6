"""Benchmark: the run's HTML report, its size and how long headless Chromium takes to draw it.

    .venv/bin/snakemake --report report.html
    .venv/bin/python benchmarks/report.py [--report report.html] [--runs 3]

Opens the report from disk in headless Chromium with the network blocked, ``--runs`` times, each
time on the real clock from Chromium's start until it has written a screenshot of the page once
loaded (Snakemake embeds every figure in the page as a data URI, so loading it reads them all);
an empty page opened the same way times Chromium's own start and stop. The viewers are linked
from the report, not embedded: each link (a path from the report's folder) must find its page.
The last line printed is one JSON object: ``bytes``, ``megabytes``, ``drawn_s`` and ``empty_s``
(the medians), ``runs`` (each run's), ``viewers`` (the pages linked). Bounds (issue 37): ≤ 50 MB,
drawn within 10 s.
"""

import argparse
import re
import statistics
import sys
import tempfile
import time
from pathlib import Path

from record import record

ROOT = Path(__file__).resolve().parents[1]
#: A viewer's link in a caption, as the report's JSON holds it.
VIEWER_LINK = re.compile(r'href=\\"(results/[^"\\]*viewer\.html)\\"')


def opening_s(page, tmp):
    """Seconds from Chromium's start until it has drawn ``page`` and written its screenshot."""
    from beeoptics.images.headless import open_page

    start = time.perf_counter()
    seen = open_page(page, Path(tmp) / "page.png", virtual_time=False)
    elapsed = time.perf_counter() - start
    if seen["errors"]:
        sys.exit(f"{page}: not drawn offline: {seen['errors'][:2]}")
    return elapsed


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--report", type=Path, default=ROOT / "report.html",
                        help="the report to open (default: %(default)s)")
    parser.add_argument("--runs", type=int, default=3, help="times to open it (default: %(default)s)")
    args = parser.parse_args(argv)
    if not args.report.exists():
        sys.exit(f"{args.report}: no such file (.venv/bin/snakemake --report report.html writes it)")
    page = args.report.resolve()
    viewers = sorted(set(VIEWER_LINK.findall(page.read_text(encoding="utf-8"))))
    missing = [v for v in viewers if not (page.parent / v).exists()]
    if missing:
        sys.exit(f"{args.report}: links {missing[0]}, which is not beside it")
    from beeoptics.images.headless import chromium
    from beeoptics.io.errors import InputError

    try:
        chromium()
    except InputError as e:
        sys.exit(f"beeoptics: error: {e}")
    runs, empty = [], []
    with tempfile.TemporaryDirectory() as tmp:
        blank = Path(tmp) / "empty.html"
        blank.write_text("<!DOCTYPE html><html><body></body></html>")
        for _ in range(args.runs):
            runs.append(round(opening_s(page, tmp), 2))
            empty.append(round(opening_s(blank, tmp), 2))
    size = page.stat().st_size
    record("report", {"report": str(args.report), "bytes": size, "megabytes": round(size / 1e6, 2),
                      "drawn_s": statistics.median(runs), "runs": runs, "empty_s": statistics.median(empty),
                      "viewers": viewers})


if __name__ == "__main__":
    main()
