"""What the README says, the tool does: every command of its shell blocks runs, as written, and fails
this test when it errors.

The commands run in a copy of the repository's eyes, scenes, config and workflow (their outputs go
there, not into the repository), in the order the README gives them, with these adaptations and no
others (:func:`as_run`):

- Snakemake plans (``--dry-run``) rather than runs: the default workflow takes minutes. Its
  ``--report`` needs a finished run, so it is made of the test workflow's (the ``workdir`` fixture).
- ``make`` prints what it would do (``-n``): ``make test`` is what runs this suite.
- The CLI traces at 4 samples (``--samples``), the README's own sample counts being for results.
- Placeholders in angle brackets (a cluster's account) are given a value.
- Files the README says are the user's own are supplied: the micro-CT eye and Buchner's map from
  ``../shared/data``, a meadow file copied from the shipped meadow's. The meadow's mesh is not: as in
  a fresh clone, the first command given the meadow generates it.
- The conda route is not run (this machine has no conda); its pip line must install what the
  Makefile installs.
"""

import importlib.util
import json
import re
import runpy
import shlex
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT, SHARED, run

README = ROOT / "README.md"
BLOCK = re.compile(r"```sh\n(.*?)```", re.S)
PYTHON = re.compile(r"```python\n(.*?)```", re.S)
#: The repository's files the commands read, copied for them.
COPIED = ("eyes", "scenes", "config", "workflow", "Snakefile", "Makefile", "pyproject.toml", "requirements.lock",
          "environment.yml")
#: Files the README's commands take to be the user's own, and where the test finds them.
USERS_OWN = {
    "BT_77970-real.eye": SHARED / "eyes_ct" / "BT_77970-real.eye",
    "receptor_directions_buchner71.csv": SHARED / "drosophila" / "receptor_directions_buchner71.csv",
    "my_meadow.yaml": ROOT / "scenes" / "meadow" / "meadow.yaml",
}
CONDA_ROUTE = ("conda ", "pip ", "beeoptics ", "snakemake ")


def commands(text):
    """The shell commands of the README's ``sh`` blocks, in order: continuation lines joined, comments
    dropped."""
    for block in BLOCK.findall(text):
        for line in re.sub(r"\\\n\s*", " ", block).splitlines():
            command = re.sub(r"\s+#.*$", "", line).strip()
            if command and not command.startswith("#"):
                yield command


def as_run(command):
    """The command as the test runs it (a list of arguments), or None for the conda route's."""
    if command.startswith(CONDA_ROUTE):
        return None
    command = re.sub(r"<(\w+)>", r"\1", command)
    args = shlex.split(command)
    if args[0] == "make":
        return ["make", "-n", *args[1:]]
    if args[0] == ".venv/bin/snakemake":
        return args if "--report" in args else [*args, "--dry-run"]
    if "--samples" in args:
        args[args.index("--samples") + 1] = "4"
    return args


def test_the_readme_names_its_commands():
    """The parser finds the README's commands (a test that ran none would pass on anything)."""
    found = list(commands(README.read_text()))
    assert any(c.startswith(".venv/bin/beeoptics render") for c in found)
    assert any(c.startswith(".venv/bin/snakemake --workflow-profile") and "--config" in c for c in found)
    assert "snakemake --cores all" in found


def test_the_readme_names_the_target_that_runs_only_a_sweep():
    """A Snakemake command whose target is a sweep's summary, the output of workflow/rules/sweeps.smk's
    sweep_summary, for a sweep the command declares."""
    rules = (ROOT / "workflow" / "rules" / "sweeps.smk").read_text()
    output = re.search(r'rule sweep_summary:.*?summary=report\("([^"]+)"', rules, re.S).group(1)
    target = re.compile(re.escape(output).replace(re.escape("{sweep}"), r"(\w+)") + "$")
    for command in commands(README.read_text()):
        args = shlex.split(command)
        found = [m.group(1) for m in map(target.match, args) if m]
        if args[0] == ".venv/bin/snakemake" and found and f"{found[0]}:" in command.split("--config", 1)[-1]:
            return
    pytest.fail(f"no README command runs a sweep alone (its target: {output})")


def test_the_conda_route_installs_what_the_makefile_installs():
    conda = [c for c in commands(README.read_text()) if as_run(c) is None]
    makefile = (ROOT / "Makefile").read_text()
    pins = set(re.findall(r"\b\w+==[\w.]+", " ".join(conda)))
    assert pins and all(pin in makefile for pin in pins)
    assert "pip install --no-deps -e ." in " ".join(conda)


@pytest.mark.skipif(not shutil.which("make"), reason="make is not installed")
def test_every_readme_command_runs_as_written(tmp_path, workdir, shared_data):
    for name in COPIED:
        source = ROOT / name
        if source.is_dir():
            shutil.copytree(source, tmp_path / name,
                            ignore=shutil.ignore_patterns("meadow.ply", "meadow_flowers.csv", "__pycache__"))
        else:
            shutil.copy(source, tmp_path / name)
    (tmp_path / ".venv").symlink_to(ROOT / ".venv")
    for name, source in USERS_OWN.items():
        shutil.copy(source, tmp_path / name)
    ran = 0
    for command in commands(README.read_text()):
        args = as_run(command)
        if args is None:
            continue
        if "--report" in args:
            result = run(workdir, *args[1:])
            report = workdir / args[args.index("--report") + 1]
            assert report.stat().st_size > 0
        else:
            result = subprocess.run(args, cwd=tmp_path, capture_output=True, text=True)
        assert result.returncode == 0, f"{command}\n{result.stderr[-3000:]}"
        ran += 1
    print(f"{ran} README commands ran")


def test_the_readme_python_snippets_run_in_a_fresh_process():
    """Each ``python`` block of the README's "From Python", in the repository's folder as a fresh clone has
    it, in a process of its own: an error fails the test."""
    section = README.read_text().split("\n## From Python\n", 1)[1].split("\n## ", 1)[0]
    snippets = PYTHON.findall(section)
    assert snippets
    for snippet in snippets:
        result = subprocess.run([sys.executable, "-c", snippet], cwd=ROOT, capture_output=True, text=True)
        assert result.returncode == 0, f"{snippet}\n{result.stderr[-3000:]}"
        assert "UV" in result.stdout


def test_every_benchmark_the_readme_names_exists_and_takes_help(monkeypatch, capsys):
    """Each runs as ``python benchmarks/<name>.py --help`` would, in this process (whose imports of the
    package most benchmarks share: a process each would spend seconds importing it again)."""
    named = set(re.findall(r"benchmarks/(\w+)\.py", README.read_text()))
    assert named
    # As `python benchmarks/<name>.py` runs it: with its folder first on the path, for benchmarks/record.py.
    monkeypatch.syspath_prepend(str(ROOT / "benchmarks"))
    for name in sorted({p.stem for p in (ROOT / "benchmarks").glob("*.py")} - {"record"} | named):
        script = ROOT / "benchmarks" / f"{name}.py"
        assert script.exists(), f"benchmarks/{name}.py: no such file"
        monkeypatch.setattr(sys, "argv", [str(script), "--help"])
        with pytest.raises(SystemExit) as ended:
            runpy.run_path(str(script), run_name="__main__")
        assert ended.value.code == 0 and "usage" in capsys.readouterr().out, f"benchmarks/{name}.py --help"


def readme_script():
    spec = importlib.util.spec_from_file_location("readme", ROOT / "docs" / "readme.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_passage_the_readme_takes_from_a_run_has_its_writer():
    script = readme_script()
    found = [m.group(2) for m in script.BLOCK.finditer(README.read_text())]
    assert sorted(found) == sorted(script.PASSAGES)


def test_the_readme_tables_of_benchmarks_are_written_from_their_kept_runs(tmp_path):
    """docs/readme.py writes the speed table from the last three runs of each setting that
    benchmarks/record.py kept, the noise table from each scene's last, and the workflow's time from
    Snakemake's log of the last whole default run."""
    script = readme_script()
    kept = tmp_path / "results" / "benchmarks"
    kept.mkdir(parents=True)
    runs = [{"commit": f"c{k}", "eye": "worker", "spp": 256, "depth": 3, "scene": "meadow", "threads": 1,
             "scene_triangles": 1178472, "trace_s": t, "wall_s": t + 3, "embree_fraction": 0.5, "embree_cpu_share": 0.7,
             "bare_rays_per_s": 2.0e6, "peak_memory_mb": 1400.0} for k, t in enumerate((99.0, 7.0, 8.5, 7.5))]
    (kept / "trace.jsonl").write_text("".join(json.dumps(r) + "\n" for r in runs))
    table = script.speed(tmp_path / "results", None)
    assert "| worker, 256, 3 | meadow (1,178,472 triangles) | 1 | 7.0–8.5 | 10.0–11.5 | 0.50 (0.70) | 2.00 |" in table
    assert "c0" not in table  # the oldest of four runs is left out
    estimator = {"p50_rel_se": 0.017, "p90_rel_se": 0.064, "p99_rel_se": 0.097, "trace_s": 6.6}
    (kept / "noise.jsonl").write_text(json.dumps({
        "commit": "c9", "scene": "meadow", "spp": 256, "depth": 3, "seeds": 8, "default": estimator,
        "escape": estimator, "efficiency_vs_escape": 0.67,
        "noise_sources": {"sun_share": 0.75, "sun_rel_se": 0.072, "sky_rel_se": 0.017}}) + "\n")
    noise = script.noise(tmp_path / "results", None)
    assert "| meadow | nee (default) | 1.70 % | 6.40 % | 9.70 % | 6.6 | 0.67 |" in noise and "the sun 75 %" in noise
    assert "8 seeds" in noise
    logs = tmp_path / ".snakemake" / "log"
    logs.mkdir(parents=True)
    (logs / "2026-01-01T000000.snakemake.log").write_text(
        "[Thu Jan  1 00:00:05 2026]\nlocalrule all:\n[Thu Jan  1 00:04:50 2026]\n70 of 70 steps (100%) done\n")
    (logs / "2026-01-02T000000.snakemake.log").write_text(
        "[Fri Jan  2 00:00:05 2026]\nrule pond:\n[Fri Jan  2 00:01:00 2026]\n7 of 7 steps (100%) done\n")
    assert "70 jobs in 4 min 45 s" in script.workflow(tmp_path / "results", None)
