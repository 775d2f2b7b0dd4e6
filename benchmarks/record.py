"""A benchmark's result, printed as its last line and kept: appended, with the commit it measured, to
``results/benchmarks/<name>.jsonl``, one line a run, from which ``docs/readme.py`` writes the README's
tables of speed, noise and daylight."""

import json
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
KEPT = ROOT / "results" / "benchmarks"


def record(name, result):
    """Print ``result`` (a dict) as one JSON line, and append it, with the commit, to the benchmark's file."""
    line = json.dumps(result)
    print(line, flush=True)
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    KEPT.mkdir(parents=True, exist_ok=True)
    with open(KEPT / f"{name}.jsonl", "a") as f:
        f.write(json.dumps({"commit": commit or None, **result}) + "\n")
