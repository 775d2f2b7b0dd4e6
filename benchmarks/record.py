"""A benchmark's result, printed as its last line and kept: appended, with the commit it measured, to
``results/benchmarks/<name>.jsonl``, one line a run, from which ``docs/readme.py`` writes the README's
tables of speed, noise and daylight (it reads them with :func:`kept`)."""

import json
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def commit(checkout=ROOT):
    """The short hash of the commit ``checkout`` (a folder in a git checkout) has now, or None outside one."""
    done = subprocess.run(["git", "-C", str(checkout), "rev-parse", "--short", "HEAD"], capture_output=True,
                          text=True)
    return done.stdout.strip() or None


def _kept_file(results, name):
    return Path(results) / "benchmarks" / f"{name}.jsonl"


def record(name, result):
    """Print ``result`` (a dict) as one JSON line, and append it, with the commit, to the benchmark's file."""
    print(json.dumps(result), flush=True)
    path = _kept_file(ROOT / "results", name)
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "a") as f:
        f.write(json.dumps({"commit": commit(), **result}) + "\n")


def kept(results, name):
    """A benchmark's kept runs in the folder ``results``, oldest first."""
    return [json.loads(line) for line in _kept_file(results, name).read_text().splitlines() if line]
