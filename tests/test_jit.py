"""The compiled kernels: compiled once, said once, then loaded from numba's cache."""

import os
import subprocess
import sys

CALL = ("import numpy as np\n"
        "from beeoptics.light.sampler import uniform\n"
        "uniform(1, np.arange(3), np.arange(3), 0)\n")


def test_a_kernel_is_compiled_and_said_so_once_then_loaded_silently(tmp_path):
    # NUMBA_CACHE_DIR stands for the user-wide cache numba falls back to where the
    # package's own folder is read-only; an empty one makes the first run compile.
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    first, second = (subprocess.run([sys.executable, "-c", CALL], env=env, capture_output=True, text=True, check=True)
                     for _ in range(2))
    assert "compiled _uniform_many in" in first.stderr
    assert "compiled" not in second.stderr
    assert any(tmp_path.rglob("*.nbi")), "numba wrote no index of its cache"
