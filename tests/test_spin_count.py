"""OpenMP's idle threads spin 30,000 times before they sleep where the user set neither
GOMP_SPINCOUNT nor OMP_WAIT_POLICY (set when the package's compiled code is first
imported, before any parallel launch); a user's own setting is kept. In a child process:
the variable is read once per process."""

import os
import subprocess
import sys

import pytest

PROBE = ("import os, agglomtool as at; at.Scene; "
         "print(os.environ.get('GOMP_SPINCOUNT', 'unset'))")


@pytest.mark.parametrize("given, expected", [
    ({}, "30000"),
    ({"GOMP_SPINCOUNT": "1000"}, "1000"),  # the user's spin count
    ({"OMP_WAIT_POLICY": "PASSIVE"}, "unset"),  # the user's policy sets its own spin
])
def test_spin_count_default_and_the_users_own(given, expected):
    env = {k: v for k, v in os.environ.items()
           if k not in ("GOMP_SPINCOUNT", "OMP_WAIT_POLICY")}
    run = subprocess.run([sys.executable, "-c", PROBE], env={**env, **given},
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == expected
