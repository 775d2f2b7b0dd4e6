"""A workflow killed in the middle of a trace completes when run again, with the same outputs."""

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml

from conftest import ROOT

DATA = ROOT / "tests" / "data"
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
TRACED = Path("results/tiny/flower/parts/radiance_0_of_1.npz")
OUTPUTS = ["results/tiny/flower/responses.csv", "results/tiny/flower/irradiance.npz",
           "results/tiny/flower/catches.exr", "results/tiny/flower/voronoi_map3.png"]


def command(work, *args):
    return [SNAKEMAKE, "--snakefile", str(ROOT / "Snakefile"), "--directory", str(work),
            "--configfile", str(work / "config.yaml"), "--cores", "1", *args]


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGKILL], ids=["interrupted", "killed"])
def test_a_run_stopped_mid_trace_completes_on_rerun_with_identical_outputs(tmp_path, sig):
    work = tmp_path / "work"
    shutil.copytree(DATA / "eyes", work / "eyes")
    shutil.copytree(DATA / "scenes", work / "scenes")
    config = {
        "eyes": ["tiny"], "scenes": ["flower"],
        "eyes_dir": str(work / "eyes"), "scenes_dir": str(work / "scenes"),
        "spectral": {"step_nm": 10},
        # Enough samples that the trace runs for seconds, long enough to be stopped in.
        "trace": {"samples_per_receptor": 16384, "depth": 2, "seed": 3, "batch_rays": 262144},
        "images": {"width_px": 64, "visual_field_width_px": 90},
        "human_view": {"samples_per_pixel": 1},
    }
    (work / "config.yaml").write_text(yaml.safe_dump(config))
    targets = OUTPUTS
    # A run started in the background by a shell (`make test &`) inherits SIGINT ignored, and Python
    # then never turns Ctrl-C into KeyboardInterrupt: the run gets it back, as a terminal's run has it.
    run = subprocess.Popen(command(work, *targets), cwd=work, start_new_session=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                           preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    log = work / "results/logs/trace/tiny/flower/0_of_1.log"
    deadline = time.monotonic() + 300
    # Wait for the trace's own first line, not just for its log file: the run is then mid-trace.
    while (not log.exists() or "tracing receptors" not in log.read_text()) and run.poll() is None \
            and time.monotonic() < deadline:
        time.sleep(0.05)
    # The trace has started; it runs for seconds after that.
    time.sleep(0.3)
    assert run.poll() is None and not (work / TRACED).exists(), "the trace ended before it could be stopped"
    # SIGINT is Ctrl-C, to every process of the run; SIGKILL gives nothing a chance to clean up.
    os.killpg(run.pid, sig)
    run.wait(60)
    assert not (work / TRACED).exists()
    assert not [p for p in (work / TRACED.parent).glob("*") if not p.name.startswith(".")]
    if sig == signal.SIGKILL:
        # Snakemake's lock outlives a killed run; --unlock is the documented way back.
        subprocess.run(command(work, "--unlock"), cwd=work, check=True, capture_output=True)
    again = subprocess.run(command(work, *targets), cwd=work, capture_output=True, text=True)
    assert again.returncode == 0, again.stderr[-3000:]
    first = {o: (work / o).read_bytes() for o in OUTPUTS}
    # An uninterrupted trace of the same config gives the same bytes.
    fresh = subprocess.run(command(work, "--forcerun", "trace", *targets), cwd=work, capture_output=True, text=True)
    assert fresh.returncode == 0, fresh.stderr[-3000:]
    for o in OUTPUTS:
        assert (work / o).read_bytes() == first[o], o
