"""Input checks shared by every public entry point.

Bad input fails at the boundary with a ``ValueError`` that names the field, the offending
value and the allowed range. Nothing downstream has to guard against NaN. Input that is
valid but implausible warns with a :class:`PlausibilityWarning`, defined here (low in the
layers) so that the correlations can warn without importing the scene-level checks of
:mod:`agglomtool.plausibility`, which re-exports it.
"""

from __future__ import annotations

import difflib
import functools
import math
import os
from pathlib import Path

import numpy as np

from ._fields import CORE_RANGES, FIELD_RANGES, short_unit


class PlausibilityWarning(UserWarning):
    """Valid input that looks wrong (a unit slip, a size outside a solid's range, ...)."""


def material_key(name) -> str:
    """A material's name as the database spells it: lower case, words joined by ``-``."""
    return "-".join(str(name).strip().lower().replace("_", " ").split())


def suggestion(value, known, *, material: bool = True) -> str:
    """``" (did you mean 'x'?)"`` for the name of ``known`` closest to a mistyped ``value``
    (a missing suffix, a swapped or missing letter), or ``""`` where none is close.
    ``material``: ``value`` is a material's name, compared as the database spells names
    (lower case, words joined by ``-``); otherwise a key, compared as written."""
    if not isinstance(value, str):
        return ""
    key = material_key(value) if material else value.strip()
    known = [str(k) for k in known]
    near = difflib.get_close_matches(key, known, n=1, cutoff=0.6)
    if not near:  # a prefix: "k-silicate" for "k-silicate-ash-melt"
        near = [k for k in known if k.startswith(key) and len(key) >= 3][:1]
    return f" (did you mean {near[0]!r}?)" if near else ""


def unknown_name(field: str, value, kind: str, known) -> ValueError:
    """The error of a name that is not in the materials database (``kind``: gas, solid or
    liquid), naming the field, the value, the known names and the closest of them."""
    plural = {"gas": "gases"}.get(kind, kind + "s")
    known = sorted(str(k) for k in known)
    return ValueError(f"{field} = {value!r} is not in the materials database"
                      f"{suggestion(value, known)}; known {plural}: {', '.join(known)}")


def _first_bad(arr: np.ndarray, bad: np.ndarray) -> float:
    """The first offending value of ``arr`` where ``bad`` is true."""
    return float(np.broadcast_to(arr, bad.shape)[bad].flat[0])


#: SI unit of each input field of the core's API, for pint Quantities given there.
FIELD_UNITS = {
    "d": "m", "h0": "m", "ha": "m", "rho": "kg/m**3", "mu": "Pa*s", "gamma": "N/m",
    "theta_deg": "degree", "eps": "dimensionless", "U": "m/s", "u0": "m/s", "u0_j": "m/s",
    "beta_deg": "degree", "e": "dimensionless", "tol": "dimensionless", "u_max": "m/s",
}


def _from_quantity(name: str, value):
    """A pint Quantity given for field ``name``, in the field's SI unit (a ValueError for a
    field without a unit or a Quantity of another dimension)."""
    from .units import to_si

    unit = FIELD_UNITS.get(name.split(".")[-1].split("[")[0])
    if unit is None:
        raise ValueError(f"{name} = {value!r}: give a plain number (SI) here")
    return to_si(name, value, unit)


def as_float_array(name: str, value, allowed: str = "finite numbers") -> np.ndarray:
    """Convert ``value`` to a float64 array; reject NaN and non-numeric input, naming the
    field, the value and the ``allowed`` range in the message. A pint Quantity is converted
    to the field's SI unit (:data:`FIELD_UNITS`) first: ``d = 500 um`` is 5e-4 m, never
    500 m."""
    if type(value) is float or type(value) is int:  # the common scalar, without numpy
        if value != value:
            raise ValueError(f"{name} = nan is not a number; allowed: {allowed}")
        return np.array(value, dtype=np.float64)
    arr = _float_array(name, value, allowed)
    # One reduction, no mask: the minimum is NaN exactly when some element is (one
    # element: itself, read as a Python float).
    if arr.size and math.isnan(arr.item() if arr.size == 1 else arr.min()):
        _raise_nan(name, arr, allowed)
    return arr


def _float_array(name: str, value, allowed: str) -> np.ndarray:
    """:func:`as_float_array` without the NaN check."""
    if type(value) is np.ndarray and value.dtype == np.float64 and value.size:
        return value  # what np.asarray below would return
    if hasattr(value, "magnitude") and hasattr(value, "units") and hasattr(value, "to"):
        value = _from_quantity(name, value)
    if value is None:
        raise ValueError(f"{name} = None: a value is required; allowed: {allowed}")
    if isinstance(value, (bool, np.bool_)) or getattr(value, "dtype", None) == np.bool_:
        raise ValueError(f"{name} = {value!r} is a boolean, not a number; allowed: {allowed}")
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(
            f"{name} = {value!r} is not a number or an array of numbers; allowed: {allowed}"
        ) from exc
    if arr.size == 0:  # an empty input would give an empty answer, silently
        raise ValueError(f"{name} = {value!r} is empty; allowed: one or more numbers in "
                         f"{allowed}")
    return arr


def _raise_nan(name: str, arr: np.ndarray, allowed: str):
    """The ``ValueError`` for ``arr``, which holds a NaN, naming the first one's index."""
    where = ""
    if arr.ndim:
        where = f" at index {tuple(int(i) for i in np.argwhere(np.isnan(arr))[0])}"
    raise ValueError(f"{name} = nan{where} is not a number; allowed: {allowed}")


@functools.lru_cache(maxsize=256)
def _range_text(lo, hi, lo_open, hi_open, unit, allow_inf=False) -> str:
    """The allowed range as messages state it: ``"(0, inf) m"``, ``"[0, 1]"``,
    ``"(0, 1] m or inf"``."""
    lo_s = "-inf" if lo is None else f"{lo:g}"
    hi_s = "inf" if hi is None else f"{hi:g}"
    rng = f"{'(' if lo_open else '['}{lo_s}, {hi_s}{')' if hi_open or hi is None else ']'}"
    if unit and unit not in ("-", "dimensionless"):
        rng += f" {unit}"
    if allow_inf and hi is not None:
        rng += " or inf"
    return rng


def check_range(
    name: str,
    value,
    lo: float | None = None,
    hi: float | None = None,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    allow_inf: bool = False,
    unit: str = "",
) -> np.ndarray:
    """Return ``value`` as a float array after checking ``lo <= value <= hi``.

    ``lo_open`` / ``hi_open`` make the bound strict. ``+inf`` is refused unless
    ``allow_inf`` (a plate's diameter, say: allowed then besides ``[lo, hi]``); ``-inf`` is
    always refused. ``None``, an empty array, a string that is no number and a boolean are
    refused too, each with a ``ValueError`` naming ``name``, the value and the range.
    """
    if type(value) is float or type(value) is int:  # the common scalar, without numpy
        # Python's comparisons decide it; a value they refuse (NaN included) takes the
        # general path below, which names it.
        if (value == value and (lo is None or (value > lo if lo_open else value >= lo))
                and (hi is None or (value < hi if hi_open else value <= hi))
                and value != -math.inf and (allow_inf or value != math.inf)):
            return np.array(value, dtype=np.float64)
    if type(value) is np.ndarray and value.dtype == np.float64 and value.size:
        arr = value  # what _float_array returns (its range text is for its messages)
    else:
        arr = _float_array(name, value, _range_text(lo, hi, lo_open, hi_open, unit,
                                                    allow_inf))
    if arr.size:
        if (arr.size >= PASS_FROM and arr.flags.c_contiguous
                and not _refused(arr, lo, hi, lo_open, hi_open, allow_inf)):
            return arr  # (a refused value is named below)
        # Two reductions decide the common case (every value allowed) without a mask; the
        # masks below only run to name the first bad value. The minimum is NaN exactly
        # when some element is. One element is its own minimum and maximum (read as a
        # Python float, the same number: no reduction's call to pay).
        if arr.size == 1:
            mn = mx = arr.item()
        else:
            mn, mx = arr.min(), arr.max()
        if math.isnan(mn):
            _raise_nan(name, arr, _range_text(lo, hi, lo_open, hi_open, unit, allow_inf))
        if ((lo is None or (mn > lo if lo_open else mn >= lo))
                and (hi is None or (mx < hi if hi_open else mx <= hi))
                and mn != -np.inf and (allow_inf or mx != np.inf)):
            return arr
    rng = _range_text(lo, hi, lo_open, hi_open, unit, allow_inf)
    bad = np.zeros(arr.shape, dtype=bool)
    if lo is not None:
        bad |= (arr <= lo) if lo_open else (arr < lo)
    if hi is not None:
        above = (arr >= hi) if hi_open else (arr > hi)
        bad |= (above & ~np.isposinf(arr)) if allow_inf else above
    if not allow_inf:
        bad |= np.isinf(arr)
    else:
        bad |= np.isneginf(arr)
    if bad.any():
        where = ""
        if bad.size > 1:  # which element of an array (a grid's point, a batch's collision)
            where = f" at index {tuple(int(i) for i in np.argwhere(bad)[0])}"
        raise ValueError(f"{name} = {_first_bad(arr, bad)!r}{where} is outside the allowed "
                         f"range {rng}")
    return arr


#: Elements from which :func:`check_range` counts the refused values of a C-contiguous
#: float64 array in one compiled pass on every thread (a map's block of impact speeds),
#: not by numpy's minimum and maximum on the calling thread.
PASS_FROM = 1 << 16
#: The loop of :func:`_count_refused`: ``range`` as written, Numba's ``prange`` once
#: compiled (:func:`_refused`). Numba is imported on first use only: this module is
#: imported by the command line's help, which imports no compiled code.
_prange = range
_COUNT_KERNEL: list = []


def _count_refused(a, lo, hi, lo_open, hi_open, allow_inf):
    """How many elements of the 1-D ``a`` are refused by the rule of :func:`check_range`:
    NaN, below ``lo`` (at it with ``lo_open``), above ``hi`` (at it with ``hi_open``) but
    for ``+inf`` with ``allow_inf``, ``-inf``, and ``+inf`` without ``allow_inf``. An
    absent bound is given as the infinity on its side, closed. Plain Python as written
    (the reference the tests run), a parallel loop once compiled."""
    n = 0
    for i in _prange(a.shape[0]):
        x = a[i]
        ok_lo = x > lo if lo_open else x >= lo
        ok_hi = (x < hi if hi_open else x <= hi) or (allow_inf and x == math.inf)
        n += not (ok_lo and ok_hi and x != -math.inf and (allow_inf or x != math.inf))
    return n


def _refused(arr: np.ndarray, lo, hi, lo_open: bool, hi_open: bool, allow_inf: bool) -> int:
    """:func:`_count_refused` of the C-contiguous float64 ``arr``, compiled (Numba, on
    first use) and launched on every thread."""
    global _prange
    from ._jit import CACHE, parallel_launch

    if not _COUNT_KERNEL:
        import numba

        _prange = numba.prange
        _COUNT_KERNEL.append(numba.njit(parallel=True, cache=CACHE)(_count_refused))
    return int(parallel_launch(
        _COUNT_KERNEL[0], arr.reshape(-1), -math.inf if lo is None else float(lo),
        math.inf if hi is None else float(hi), bool(lo_open and lo is not None),
        bool(hi_open and hi is not None), bool(allow_inf)))


def check_field(name: str, value, *, key: str | None = None, allow_inf: bool = False,
                scalar: bool = False) -> np.ndarray:
    """``value`` checked against the physical range of field ``key`` (default ``name``) of
    :data:`agglomtool._fields.CORE_RANGES` or :data:`~agglomtool._fields.FIELD_RANGES`, the
    one table of ranges. ``scalar``: one number is required, not a list or an array."""
    key = name if key is None else key
    if key in CORE_RANGES:
        lo, hi, lo_open, hi_open, unit = CORE_RANGES[key]
    else:
        lo, hi, lo_open, hi_open = FIELD_RANGES[key]
        unit = short_unit(key)
    if scalar and np.ndim(value) and np.size(value) != 0:
        raise ValueError(f"{name} = {value!r} must be a single number in "
                         f"{_range_text(lo, hi, lo_open, hi_open, unit, allow_inf)}, not "
                         f"{np.size(value)} values")
    return check_range(name, value, lo, hi, lo_open=lo_open, hi_open=hi_open,
                       allow_inf=allow_inf, unit=unit)


def check_int(name: str, value, lo: int, hi: int | None = None) -> int:
    """``value`` as an int in ``[lo, hi]``: an integer (not a bool, not 1.5, not "4"), else
    a ``ValueError`` naming ``name``, the value and the range."""
    rng = f"an integer in [{lo}, {'inf' if hi is None else hi}]"
    if isinstance(value, bool | np.bool_) or not isinstance(value, int | np.integer):
        raise ValueError(f"{name} = {value!r} is not allowed: {rng}")
    if value < lo or (hi is not None and value > hi):
        raise ValueError(f"{name} = {value!r} is outside the allowed range: {rng}")
    return int(value)


def check_bool(name: str, value) -> bool:
    """``value`` as a bool: True or False only, else a ``ValueError`` naming ``name``."""
    if not isinstance(value, bool | np.bool_):
        raise ValueError(f"{name} = {value!r} is not allowed: True or False")
    return bool(value)


def _typed(value) -> bool:
    """True where ``value`` holds text or a Quantity: what a person typed, converted since."""
    if isinstance(value, str) or hasattr(value, "units"):
        return True
    return isinstance(value, list | tuple) and any(
        isinstance(v, str) or hasattr(v, "units") for v in value)


def check_typed(name: str, typed, value, *, key: str | None = None, scalar: bool = False,
                allow_inf: bool = False) -> np.ndarray:
    """:func:`check_field` of ``value``, converted to SI from ``typed`` (a unit string, a
    Quantity, a list holding them): the message shows what was typed as well ("h0 = 1.5e+17
    is outside the allowed range [0, 1000] m (given as '5 parsec')")."""
    try:
        return check_field(name, value, key=key, scalar=scalar, allow_inf=allow_inf)
    except ValueError as exc:
        if _typed(typed):
            raise ValueError(f"{exc} (given as {typed!r})") from None
        raise


# ---------------------------------------------------------------------------------------
# Memory: what a request would hold, against what this process may take


def _bytes(n: float) -> str:
    for unit, size in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{int(n)} B"


def _cgroup_room() -> int | None:
    """Bytes this process's cgroup (v2) may still take, where a limit is set."""
    base = Path("/sys/fs/cgroup")
    try:
        limit = (base / "memory.max").read_text().strip()
        if limit == "max":
            return None
        return max(0, int(limit) - int((base / "memory.current").read_text().strip()))
    except (OSError, ValueError):
        return None


def available_memory() -> int | None:
    """Bytes of memory available to this process now (``None`` if it cannot be told):
    ``psutil``'s available memory where psutil is installed, else the kernel's
    ``MemAvailable``, else the free pages; never more than a cgroup limit leaves."""
    found = None
    try:
        import psutil

        found = int(psutil.virtual_memory().available)
    except Exception:  # noqa: BLE001 - not installed or not supported here
        try:
            with open("/proc/meminfo") as f:
                for line in f:
                    if line.startswith("MemAvailable:"):
                        found = int(line.split()[1]) * 1024
                        break
        except (OSError, ValueError, IndexError):
            pass
        if found is None:
            try:
                found = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
            except (ValueError, OSError, AttributeError):
                found = None
    room = _cgroup_room()
    if room is not None:
        found = room if found is None else min(found, room)
    return found


def check_memory_for(name: str, n: int, per_item: float, item: str = "draw") -> None:
    """Refuse ``n`` items of ``per_item`` bytes each (``name = n``: the draws of a Monte
    Carlo, a robust map's samples) where they exceed the memory available now
    (:func:`available_memory`; nothing is refused where that cannot be told): a
    ``ValueError`` naming the field, the value, the memory it needs and the largest value
    that fits, before any work. ``per_item`` is what the request holds for certain, a
    lower bound: a request it lets through may still run short."""
    need = float(n) * float(per_item)
    avail = available_memory()
    if avail is None or need <= avail:
        return
    most = int(avail // per_item)
    raise ValueError(f"{name} = {n} would hold {_bytes(need)} in memory (at least "
                     f"{per_item:g} bytes per {item}) and {_bytes(avail)} is available; "
                     f"allowed: {name} <= {most}")
