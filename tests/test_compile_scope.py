"""A job compiles the kernels of its own tier only (a first run in mode "relative" does not
compile the "paper" kernel, and the other way round)."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

JOB = textwrap.dedent("""
    import sys
    from numba.core import event

    compiled = set()

    class Listener(event.Listener):
        def on_start(self, ev):
            compiled.add(ev.data["dispatcher"].py_func.__name__)

        def on_end(self, ev):
            pass

    event.register("numba:compile", Listener())
    import agglomtool as at

    mode = sys.argv[1]
    p = at.Particle(d=500e-6, rho=2600.0, h0=5e-6, ha=0.1e-6)
    liq = at.Liquid(mu=1e-3, gamma=0.07, rho=1000.0)
    gas = at.Gas(mu=18e-6, rho=1.2)
    at.collide(p, p, liquid=liq, gas=gas, u0=[0.1, 0.2, 0.5], mode=mode)
    at.critical_impact_speed(p, p, liquid=liq, gas=gas, mode=mode)
    print(" ".join(sorted(compiled)))
""")


@pytest.mark.parametrize(("mode", "own", "other"), [
    ("relative", "relative_kernel", "paper_kernel"),
    ("paper", "paper_kernel", "relative_kernel"),
])
def test_a_job_compiles_its_own_tier_only(tmp_path, mode, own, other):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path),
           "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    out = subprocess.run([sys.executable, "-c", JOB, mode], env=env, capture_output=True,
                         text=True, timeout=600, check=True).stdout.split()
    assert own in out
    assert other not in out
