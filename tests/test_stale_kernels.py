"""Cached kernels are dropped when the package's sources change (``agglomtool._jit``):
Numba's cache notices a change in a cached function's own file only, so a kernel that
calls into an edited module would otherwise run its old code."""

from __future__ import annotations

import os

from agglomtool._jit import STAMP_NAME, drop_stale_kernels


def _tree(tmp_path):
    pkg = tmp_path / "pkg"
    (pkg / "sub" / "__pycache__").mkdir(parents=True)
    (pkg / "__pycache__").mkdir()
    (pkg / "a.py").write_text("x = 1\n")
    (pkg / "sub" / "b.py").write_text("y = 2\n")
    return pkg


def _cache(pkg):
    """Two cached kernels, one per folder, and a file that is not one."""
    for path in (pkg / "__pycache__" / "a.f-1.py311.nbi",
                 pkg / "sub" / "__pycache__" / "b.g-3.py311.1.nbc",
                 pkg / "sub" / "__pycache__" / "b.cpython-311.pyc"):
        path.write_bytes(b"0")


def test_kept_while_the_sources_stay_and_dropped_when_one_changes(tmp_path):
    pkg = _tree(tmp_path)
    _cache(pkg)
    assert drop_stale_kernels(str(pkg)) == 2  # no record yet: all dropped, record written
    assert (pkg / "__pycache__" / STAMP_NAME).exists()
    _cache(pkg)
    assert drop_stale_kernels(str(pkg)) == 0  # the same sources: kept
    assert (pkg / "__pycache__" / "a.f-1.py311.nbi").exists()
    (pkg / "sub" / "b.py").write_text("y = 3  # edited\n")  # another file than a's
    assert drop_stale_kernels(str(pkg)) == 2
    assert not (pkg / "__pycache__" / "a.f-1.py311.nbi").exists()
    assert (pkg / "sub" / "__pycache__" / "b.cpython-311.pyc").exists()  # not a kernel
    _cache(pkg)
    os.utime(pkg / "a.py", ns=(1, 1))  # a modification time alone
    assert drop_stale_kernels(str(pkg)) == 2


def test_a_read_only_package_is_left_alone(tmp_path, monkeypatch):
    """Where a cached kernel cannot be deleted (a read-only install), nothing is recorded
    and nothing raises: the next import tries again."""
    pkg = _tree(tmp_path)
    _cache(pkg)

    def refuse(path):
        raise PermissionError(13, "Permission denied", path)

    monkeypatch.setattr(os, "remove", refuse)
    assert drop_stale_kernels(str(pkg)) == 0
    assert (pkg / "__pycache__" / "a.f-1.py311.nbi").exists()
    assert not (pkg / "__pycache__" / STAMP_NAME).exists()


def test_the_package_records_its_fingerprint():
    import agglomtool

    root = os.path.dirname(agglomtool.__file__)
    stamp = os.path.join(root, "__pycache__", STAMP_NAME)
    if os.access(root, os.W_OK):
        assert os.path.exists(stamp)
        assert drop_stale_kernels(root) == 0  # imported already: the record is current
