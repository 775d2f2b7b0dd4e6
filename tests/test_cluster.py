"""The README's cluster section, as written: its command plans every job with the profile's resources, and
what it says of a job cancelled by hand holds for the pinned SLURM plugin."""

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import yaml

from conftest import ROOT

SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))


def readme_command(section):
    """The first shell block after a README heading, as arguments."""
    text = (ROOT / "README.md").read_text()
    block = re.search(rf"## {section}\n.*?```sh\n(.*?)```", text, re.S).group(1)
    return shlex.split(block.replace("\\\n", " "))


def planned(output):
    """Each job a dry run plans: its rule and its resources."""
    jobs = []
    for block in re.split(r"\n(?=rule \w+:)", output):
        rule = re.match(r"rule (\w+):", block)
        resources = re.search(r"\n\s+resources: (.*)", block)
        if rule and resources:
            jobs.append((rule.group(1), dict(kv.split("=", 1) for kv in resources.group(1).split(", "))))
    return jobs


def test_the_readme_cluster_command_plans_jobs_with_the_profiles_resources(tmp_path):
    args = readme_command("On a cluster")
    assert args[0] == ".venv/bin/snakemake"
    args = [SNAKEMAKE, *(a.replace("<account>", "acct").replace("<partition>", "part") for a in args[1:]), "-n"]
    for name in ("Snakefile", "workflow", "config", "eyes", "scenes"):
        copy = shutil.copytree if (ROOT / name).is_dir() else shutil.copy
        copy(ROOT / name, tmp_path / name)
    result = subprocess.run(args, cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    profile = yaml.safe_load((ROOT / "workflow" / "profiles" / "slurm" / "config.yaml").read_text())
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    jobs = planned(result.stdout + result.stderr)
    # --config trace='{parts: 16}': each trace in sixteen jobs.
    assert sum(rule == "trace" for rule, _ in jobs) == 16 * len(config["eyes"]) * len(config["scenes"])
    for rule, resources in jobs:
        assert resources["slurm_account"] == "acct" and resources["slurm_partition"] == "part", rule
        want = {**profile["default-resources"], **profile["set-resources"].get(rule, {})}
        for key in ("mem_mb", "runtime"):
            assert int(resources[key]) == want[key], (rule, key)
        # The CPUs a job asks for follow its threads, set in one place, the profile's set-threads.
        assert "cpus_per_task" not in resources, rule


def plugin_status(tmp_path, monkeypatch, state):
    """What the pinned SLURM plugin makes of one job that sacct reports in ``state``: "error", "success"
    or "running" (the plugin's own status check, run against a stand-in sacct on the PATH)."""
    import asyncio
    from types import SimpleNamespace
    from unittest import mock

    from snakemake_executor_plugin_slurm import Executor

    sacct = tmp_path / "sacct"
    sacct.write_text(f"#!/bin/sh\necho '123|{state}'\n")
    sacct.chmod(0o755)
    monkeypatch.setenv("PATH", f"{tmp_path}:{os.environ['PATH']}")
    settings = SimpleNamespace(init_seconds_before_status_checks=40, status_attempts=1, keep_successful_logs=True,
                               requeue=False)
    seen = []
    executor = mock.MagicMock(
        workflow=SimpleNamespace(executor_settings=settings), run_uuid="run", _status_query_calls=0,
        _status_query_failures=0, _status_query_total_seconds=0.0, _status_query_min_seconds=None,
        _status_query_max_seconds=0.0, _status_query_cycle_rows=[], next_seconds_between_status_checks=40,
        _preemption_warning=False, _failed_nodes=set(),
        report_job_error=lambda *a, **k: seen.append("error"), report_job_success=lambda *a, **k: seen.append("success"))
    executor.get_status_command.return_value = "sacct"
    job = SimpleNamespace(external_jobid="123", aux={"slurm_logfile": tmp_path / "123.log"})

    async def check():
        return [j async for j in Executor.check_active_jobs(executor, [job])]

    still = asyncio.run(check())
    return seen[0] if seen else ("running" if still else "lost")


def test_the_readme_says_what_to_do_while_the_plugin_misreads_a_cancelled_job(tmp_path, monkeypatch):
    """sacct reports a job cancelled by hand as 'CANCELLED by <uid>'. While the pinned plugin takes that
    for a running job, the run waits forever and the README must say what to do; once it does not,
    the paragraph goes."""
    assert plugin_status(tmp_path, monkeypatch, "CANCELLED") == "error"
    misread = plugin_status(tmp_path, monkeypatch, "CANCELLED by 0") == "running"
    cluster = re.search(r"## On a cluster\n(.*?)\n## ", (ROOT / "README.md").read_text(), re.S).group(1)
    assert misread == ("scancel" in cluster and "Ctrl-C" in cluster)
