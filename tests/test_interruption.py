"""A workflow killed in the middle of a trace completes when run again, with the same outputs."""

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import yaml

from conftest import ROOT

DATA = ROOT / "tests" / "data"
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
TRACED = Path("results/tiny/flower/parts/radiance_0_of_1.npz")
OUTPUTS = ["results/tiny/flower/responses.csv", "results/tiny/flower/irradiance.npz"]
LOG = Path("results/logs/trace/tiny/flower/0_of_1.log")


def command(work, *args):
    return [SNAKEMAKE, "--snakefile", str(ROOT / "Snakefile"), "--directory", str(work),
            "--configfile", str(work / "config.yaml"), "--cores", "1", *args]


def stop_mid_trace(work, sig):
    """Start the run again from its eye (the trace and what follows it removed), stop it with ``sig``
    once the trace has begun, and check that it left no traced part, not even a temporary one."""
    for path in (LOG, TRACED, *OUTPUTS):
        (work / path).unlink()
    # A run started in the background by a shell (`make test &`) inherits SIGINT ignored, and Python
    # then never turns Ctrl-C into KeyboardInterrupt: the run gets it back, as a terminal's run has it.
    run = subprocess.Popen(command(work, *OUTPUTS), cwd=work, start_new_session=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                           preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 300
    # Wait for the trace's own first line, not just for its log file: the run is then mid-trace.
    while (not (work / LOG).exists() or "tracing receptors" not in (work / LOG).read_text()) \
            and run.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    # The trace has started; it runs for seconds after that.
    time.sleep(0.3)
    assert run.poll() is None and not (work / TRACED).exists(), "the trace ended before it could be stopped"
    # SIGINT is Ctrl-C, to every process of the run; SIGKILL gives nothing a chance to clean up.
    os.killpg(run.pid, sig)
    run.wait(60)
    assert not (work / TRACED).exists()
    assert not [p for p in (work / TRACED.parent).glob("*") if not p.name.startswith(".")]


def test_a_run_stopped_mid_trace_completes_on_rerun_with_identical_outputs(tmp_path):
    work = tmp_path / "work"
    shutil.copytree(DATA / "eyes", work / "eyes")
    shutil.copytree(DATA / "scenes", work / "scenes")
    config = {
        "eyes": ["tiny"], "scenes": ["flower"],
        "eyes_dir": str(work / "eyes"), "scenes_dir": str(work / "scenes"),
        "spectral": {"step_nm": 10},
        # Enough samples that the trace runs for seconds (about 4 s here), long enough to be stopped in.
        "trace": {"samples_per_receptor": 2048, "depth": 2, "seed": 3, "batch_rays": 262144},
    }
    (work / "config.yaml").write_text(yaml.safe_dump(config))
    # The outputs of a run that nothing stopped.
    done = subprocess.run(command(work, *OUTPUTS), cwd=work, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-3000:]
    uninterrupted = {o: (work / o).read_bytes() for o in OUTPUTS}
    for sig in (signal.SIGINT, signal.SIGKILL):
        stop_mid_trace(work, sig)
        if sig == signal.SIGKILL:
            # Snakemake's lock outlives a killed run; --unlock is the documented way back.
            subprocess.run(command(work, "--unlock"), cwd=work, check=True, capture_output=True)
        again = subprocess.run(command(work, *OUTPUTS), cwd=work, capture_output=True, text=True)
        assert again.returncode == 0, (sig, again.stderr[-3000:])
        assert "traced receptors" in (work / LOG).read_text(), "the rerun did not trace"
        for o in OUTPUTS:
            assert (work / o).read_bytes() == uninterrupted[o], (sig, o)


def test_a_job_sent_sigterm_mid_write_leaves_no_partial_file(tmp_path):
    # A cluster's scheduler sends SIGTERM at a job's time limit: a workflow job (each runs in logging_to)
    # writing an output ends as Ctrl-C ends it, its temporary file removed, with one line and 128 + 15.
    job = ("import sys, time\n"
           "from beeoptics.io.atomic import atomic_path\n"
           "from beeoptics.pipeline.logs import logging_to\n"
           "with logging_to(sys.argv[1]), atomic_path(sys.argv[2]) as tmp:\n"
           "    tmp.write_text('half an output')\n"
           "    print('writing', flush=True)\n"
           "    time.sleep(60)\n")
    out = tmp_path / "out"
    out.mkdir()
    run = subprocess.Popen([sys.executable, "-c", job, str(tmp_path / "job.log"), str(out / "part.npz")],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert run.stdout.readline().strip() == "writing"
    run.send_signal(signal.SIGTERM)
    _, err = run.communicate(timeout=30)
    assert [p.name for p in out.iterdir()] == []
    assert run.returncode == 128 + signal.SIGTERM
    assert err.strip() == "beeoptics: terminated"
    assert "terminated (SIGTERM)" in (tmp_path / "job.log").read_text()
