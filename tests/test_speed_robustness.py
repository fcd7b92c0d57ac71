"""Importable anywhere, callable from many threads, and clear about bad input.

- a read-only install whose user has no writable home: Numba's ``cache=True`` used to fail
  at import (``cannot cache function 'ln_f': no locator available``);
- Numba's ``workqueue`` threading layer aborts the process when two threads launch parallel
  kernels at once;
- bad flags, objects of the wrong class, non-broadcasting shapes and booleans given as
  numbers must be ``ValueError``s naming the field.
"""

from __future__ import annotations

import os
import shutil
import stat
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import agglomtool as at

ROOT = Path(at.__file__).resolve().parent
WATER = at.Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0)
AIR = at.Gas(mu=18.48e-6, rho=1.168)
P = at.Particle(d=1000e-6, rho=2650.0, h0=5e-6, ha=0.1e-6)

_ONE_COLLISION = textwrap.dedent(
    """
    import tempfile
    import warnings
    warnings.simplefilter("always")
    TEMPDIR
    import agglomtool as at
    from agglomtool.collision import _jit
    w = at.Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0)
    g = at.Gas(mu=18.48e-6, rho=1.168)
    p = at.Particle(d=1000e-6, rho=2650.0, h0=5e-6, ha=0.1e-6)
    r = at.collide(p, p, liquid=w, gas=g, u0=[0.01, 0.5], details=False)
    print("OK", at.__file__, _jit.cache_status(), r.e_w.tolist())
    """
)


def _read_only_copy(tmp_path):
    """A copy of the package that no locator of Numba can cache into, even for root.

    ``chmod a-w`` does not stop root, so every ``__pycache__`` is made a regular file (no
    directory can be created there) and the copy is then made read-only for other users.
    """
    dest = tmp_path / "site"
    shutil.copytree(ROOT, dest / "agglomtool",
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "*.nbi", "*.nbc"))
    for d, _, _ in os.walk(dest / "agglomtool"):
        (Path(d) / "__pycache__").write_text("not a directory\n")
    for d, dirs, files in os.walk(dest):
        for name in dirs + files:
            p = Path(d) / name
            p.chmod(p.stat().st_mode & ~(stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH))
    return dest


def _unwritable_home(tmp_path):
    """A HOME under a regular file: nothing can be created below it."""
    blocker = tmp_path / "blocker"
    blocker.write_text("a file, not a directory\n")
    return blocker / "home"


def _run(code, env, cwd):
    return subprocess.run([sys.executable, "-c", code], env=env, cwd=cwd, capture_output=True,
                          text=True, timeout=600)


@pytest.mark.parametrize("tmp_writable", [True, False])
def test_read_only_install_without_writable_home_imports_and_collides(tmp_path, tmp_writable):
    """Imports and collides; with a writable temp directory the kernels are cached there,
    without one caching is off; either way a one-time RuntimeWarning says so."""
    site = _read_only_copy(tmp_path)
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_CACHE")}
    env["HOME"] = str(_unwritable_home(tmp_path))
    env["XDG_CACHE_HOME"] = str(_unwritable_home(tmp_path) / "cache")
    env["PYTHONPATH"] = str(site)
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    # No temporary directory either: tempfile's directory under a regular file.
    no_tmp = f"tempfile.tempdir = {str(_unwritable_home(tmp_path) / 'tmp')!r}"
    out = _run(_ONE_COLLISION.replace("TEMPDIR", "" if tmp_writable else no_tmp), env,
               cwd=tmp_path)
    assert out.returncode == 0, out.stderr[-2000:]
    line = out.stdout.strip().splitlines()[-1]
    assert line.startswith("OK " + str(site)), line  # the read-only copy was imported
    expected = at.collide(P, P, liquid=WATER, gas=AIR, u0=[0.01, 0.5], details=False).e_w
    assert expected[0] == 0.0 < expected[1]
    assert line.endswith(str(expected.tolist())), line
    if tmp_writable:
        assert "temporary directory" in line
    else:
        assert " off " in line
    assert out.stderr.count("no writable Numba cache directory") == 1, out.stderr[-2000:]


def test_the_simulation_breaks_the_unpatched_caching(tmp_path):
    """The set-up above does reproduce the failure: plain ``cache=True`` cannot cache a
    function of the read-only copy."""
    site = _read_only_copy(tmp_path)
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_CACHE")}
    env["HOME"] = str(_unwritable_home(tmp_path))
    env["XDG_CACHE_HOME"] = str(_unwritable_home(tmp_path) / "cache")
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    code = textwrap.dedent(
        f"""
        import importlib.util, sys
        spec = importlib.util.spec_from_file_location(
            "probe", {str(site / "agglomtool" / "collision" / "bridge.py")!r})
        src = open(spec.origin).read()
        from numba import njit
        def f(x):
            return x
        f.__module__ = "probe"
        f.__code__ = f.__code__.replace(co_filename=spec.origin)
        try:
            njit(cache=True)(f)
        except RuntimeError as exc:
            print("FAILS", exc)
        else:
            print("CACHES")
        """
    )
    out = _run(code, env, cwd=tmp_path)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "FAILS" in out.stdout and "no locator available" in out.stdout, out.stdout


_THREADS = textwrap.dedent(
    """
    import threading
    import numpy as np
    import agglomtool as at
    w = at.Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0)
    g = at.Gas(mu=18.48e-6, rho=1.168)
    p = at.Particle(d=1000e-6, rho=2650.0, h0=5e-6, ha=0.1e-6)
    u0 = np.geomspace(0.01, 1.0, 20000)
    ref = {m: at.collide(p, p, liquid=w, gas=g, u0=u0, beta_deg=30.0, details=False,
                         mode=m).e_w for m in ("paper", "relative", "auto", "stokes")}
    errors = []
    start = threading.Barrier(8)
    def go():
        try:
            start.wait()
            for _ in range(3):
                for m, e in ref.items():
                    r = at.collide(p, p, liquid=w, gas=g, u0=u0, beta_deg=30.0,
                                   details=False, mode=m)
                    assert np.array_equal(r.e_w, e), m
        except Exception as exc:
            errors.append(repr(exc))
    threads = [threading.Thread(target=go) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    import numba
    print("layer", numba.threading_layer(), "errors", errors)
    """
)


def test_eight_threads_on_the_workqueue_layer():
    env = dict(os.environ, NUMBA_THREADING_LAYER="workqueue")
    out = _run(_THREADS, env, cwd=None)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "layer workqueue errors []" in out.stdout, out.stdout + out.stderr[-2000:]


KW = dict(liquid=WATER, gas=AIR, u0=0.1)


@pytest.mark.parametrize("value", ["no", "yes", 1, None])
def test_body_forces_must_be_a_bool(value):
    with pytest.raises(ValueError, match="body_forces"):
        at.collide(P, P, body_forces=value, **KW)
    with pytest.raises(ValueError, match="body_forces"):
        at.critical_impact_speed(P, P, liquid=WATER, gas=AIR, body_forces=value)


def test_details_must_be_a_bool():
    with pytest.raises(ValueError, match="details"):
        at.collide(P, P, details="no", **KW)


@pytest.mark.parametrize("field", ["liquid", "gas", "bed"])
def test_inputs_of_the_wrong_class_are_named(field):
    kw = dict(liquid=WATER, gas=AIR, bed=at.Bed())
    kw[field] = "air"
    with pytest.raises(ValueError, match=rf"^{field} = 'air'"):
        at.collide(P, P, u0=0.1, **kw)
    with pytest.raises(ValueError, match=rf"^{field} = 'air'"):
        at.critical_impact_speed(P, P, **kw)


def test_shapes_that_do_not_broadcast_name_the_fields():
    p_j = at.Particle(d=np.full(3, 1e-3), rho=2650.0, h0=5e-6, ha=0.1e-6)
    with pytest.raises(ValueError, match=r"p_j\.d \(3,\).*u0 \(4,\)"):
        at.collide(P, p_j, liquid=WATER, gas=AIR, u0=np.full(4, 0.1))
    with pytest.raises(ValueError, match=r"beta_deg \(2,\)"):
        at.collide(P, p_j, liquid=WATER, gas=AIR, u0=0.1, beta_deg=[0.0, 1.0])
    with pytest.raises(ValueError, match=r"do not broadcast"):
        at.critical_impact_speed(P, p_j, liquid=WATER, gas=AIR, beta_deg=[0.0, 1.0])


@pytest.mark.parametrize("field", ["d", "rho", "h0", "ha"])
def test_booleans_are_not_numbers(field):
    kw = dict(d=1e-3, rho=2650.0, h0=5e-6, ha=0.1e-6)
    kw[field] = True
    with pytest.raises(ValueError, match=rf"Particle\.{field} = True"):
        at.Particle(**kw)
    kw[field] = np.array([True, False])
    with pytest.raises(ValueError, match=rf"Particle\.{field}"):
        at.Particle(**kw)
    with pytest.raises(ValueError, match="u0 = True"):
        at.collide(P, P, liquid=WATER, gas=AIR, u0=True)
