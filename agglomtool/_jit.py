"""How the kernels are compiled and launched: the on-disk cache and the parallel-launch lock.

On-disk cache
-------------
Numba's ``cache=True`` needs a writable directory: next to the sources (``__pycache__``),
or the user-wide cache (``NUMBA_CACHE_DIR`` or the home directory's cache). A read-only
install run by a user without a writable home has neither, and Numba refuses to even
*define* a cached function there (``RuntimeError: cannot cache function ...: no locator
available``). :data:`CACHE` is decided once, at import: ``True`` where Numba can cache; else
a fresh temporary directory is tried as the cache directory (then ``True``); else ``False``
(compile at every start). Each fallback is noted once with a :class:`RuntimeWarning`.

OpenMP's spin
-------------
Where the user set neither ``GOMP_SPINCOUNT`` nor ``OMP_WAIT_POLICY``, :data:`SPIN_COUNT`
is set as ``GOMP_SPINCOUNT`` when this module is imported, before any parallel launch:
OpenMP's idle threads then sleep sooner, and a map on every thread is not held up by a
core that another process uses.

Stale kernels
-------------
Numba's cache notices a change in a cached function's own source file, not in the files of
the compiled functions it calls (nor a module constant they read): after an update of a
source checkout (``git pull``, an edit), a cached kernel could run the old code of another
module. :func:`drop_stale_kernels`, run at import, fingerprints the package's sources
(each ``.py`` file's size and modification time) and, where the fingerprint differs from
the one recorded in the package's ``__pycache__`` by the last import, deletes the
package's cached kernels there (``*.nbi``, ``*.nbc``) before any is loaded: everything is
compiled anew once. A fresh install has fresh files and no cache; caches kept elsewhere
(``NUMBA_CACHE_DIR``) are not touched.

Parallel launches
-----------------
Numba's ``workqueue`` threading layer (used when neither TBB nor OpenMP is installed) is not
thread-safe: two threads launching parallel kernels at once abort the process
("Concurrent access has been detected"). :func:`parallel_launch` serialises launches with a
lock on that layer (and until the layer is known); TBB and OpenMP run concurrent launches
without it.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
import threading
import warnings

#: How long OpenMP's idle threads spin before they sleep, where the user set neither this
#: nor ``OMP_WAIT_POLICY`` (GNU OpenMP, Numba's OpenMP layer on Linux; read when the layer
#: starts, at the first parallel launch: so before any). Its default, 300,000 spins, keeps
#: a map's threads busy between the few dozen launches of a map; where another process
#: holds a core, the thread that shares it is late to every launch. With 30,000, the
#: 1e6-point water map of ``benchmarks/bench_sweep.py --busy`` took 0.045 s on 16 threads
#: of a 16-core machine with one core held by a busy loop, against 0.135 s with the default
#: (0.032 and 0.034 s with nothing else running; medians of 7), and 0.25-0.27 s against
#: 0.30-0.34 s on 2 threads of a 2-core machine (0.117 and 0.115-0.142 s quiet).
SPIN_COUNT = "30000"
if "GOMP_SPINCOUNT" not in os.environ and "OMP_WAIT_POLICY" not in os.environ:
    os.environ["GOMP_SPINCOUNT"] = SPIN_COUNT

import numba  # noqa: E402  (after the spin count: Numba reads no OpenMP setting at import)
from numba import njit  # noqa: E402

__all__ = ["CACHE", "SPIN_COUNT", "parallel_launch", "cache_status", "drop_stale_kernels"]

#: The file in the package's ``__pycache__`` that records the sources' fingerprint.
STAMP_NAME = "agglomtool-sources.stamp"


def _fingerprint(root: str) -> str:
    """A digest of the size and modification time of every ``.py`` file under ``root``."""
    digest = hashlib.sha1()
    for here, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for name in sorted(files):
            if name.endswith(".py"):
                st = os.stat(os.path.join(here, name))
                rel = os.path.relpath(os.path.join(here, name), root)
                digest.update(f"{rel}:{st.st_size}:{st.st_mtime_ns}\n".encode())
    return digest.hexdigest()


def drop_stale_kernels(root: str | None = None) -> int:
    """Delete the cached kernels in the ``__pycache__`` folders under ``root`` (the
    package's folder) where its sources changed since the fingerprint recorded there
    (module docstring); returns how many files were deleted. Quietly does nothing where
    the folder cannot be read or written."""
    root = root or os.path.dirname(os.path.abspath(__file__))
    stamp = os.path.join(root, "__pycache__", STAMP_NAME)
    try:
        now = _fingerprint(root)
    except OSError:
        return 0
    try:
        with open(stamp, encoding="ascii") as f:
            if f.read() == now:
                return 0
    except OSError:
        pass  # no record yet (or unreadable): treat every cached kernel as stale
    deleted = 0
    for here, _, files in os.walk(root):
        if os.path.basename(here) != "__pycache__":
            continue
        for name in files:
            if name.endswith((".nbi", ".nbc")):
                try:
                    os.remove(os.path.join(here, name))
                    deleted += 1
                except FileNotFoundError:
                    pass  # another process cleared it first
                except OSError:
                    return deleted  # not ours to clear (read-only): leave the record alone
    try:
        os.makedirs(os.path.dirname(stamp), exist_ok=True)
        with open(stamp, "w", encoding="ascii") as f:
            f.write(now)
    except OSError:
        pass
    return deleted

_STATUS = "default"


def _try_cache() -> bool:
    """True when Numba can cache a function defined in this directory."""

    def _probe(x):  # pragma: no cover - compiled lazily, never called
        return x

    try:
        njit(cache=True)(_probe)
    except RuntimeError:
        return False
    return True


def _decide_cache() -> bool:
    global _STATUS
    if _try_cache():
        return True
    try:
        tmp = tempfile.mkdtemp(prefix="agglomtool-numba-")
    except OSError:
        tmp = None
    if tmp is not None and os.access(tmp, os.W_OK):
        numba.config.CACHE_DIR = tmp
        if _try_cache():
            _STATUS = f"temporary directory {tmp}"
            warnings.warn(
                "agglomtool: no writable Numba cache directory (package directory and "
                f"user cache are read-only); compiled kernels are cached in {tmp} for this "
                "session. Set NUMBA_CACHE_DIR to a writable directory to keep them.",
                RuntimeWarning,
                stacklevel=3,
            )
            return True
    _STATUS = "off"
    warnings.warn(
        "agglomtool: no writable Numba cache directory; kernels are compiled at every start "
        "(set NUMBA_CACHE_DIR to a writable directory to cache them).",
        RuntimeWarning,
        stacklevel=3,
    )
    return False


drop_stale_kernels()

#: Passed as ``cache=`` to every compiled function of the package (the collision core, the
#: properties' vectorised kernels, the Monte Carlo summary).
CACHE: bool = _decide_cache()


def cache_status() -> str:
    """Where compiled kernels are cached: ``"default"``, ``"temporary directory ..."`` or
    ``"off"``."""
    return _STATUS


_LOCK = threading.Lock()
_LAYER_SAFE = False  # True once a concurrent-safe layer (tbb, omp) is known to be running


def parallel_launch(kernel, *args):
    """Call the parallel (``prange``) ``kernel`` with ``args``, holding a process-wide lock
    where the threading layer cannot take concurrent launches (module docstring)."""
    global _LAYER_SAFE
    if _LAYER_SAFE:
        return kernel(*args)
    with _LOCK:
        out = kernel(*args)
        try:
            _LAYER_SAFE = numba.threading_layer() in ("tbb", "omp")
        except ValueError:  # no parallel region ran yet
            pass
    return out
