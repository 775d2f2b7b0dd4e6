"""The README's cluster command, as written, plans every job with the profile's resources."""

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
