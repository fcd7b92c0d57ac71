"""What a sweep will take, said as it starts: points, blocks, time, memory, store size.

Every :func:`agglomtool.maps.sweep` (and :func:`estimate_sweep`, without running) counts the
grid's points and blocks and the bytes of every output exactly, from the grid's lengths,
before any work. The time is measured, not guessed: the sweep computes three of its blocks
first, spread over the grid (one if it has few), times them (their ``u0*`` part apart) and
scales them to the grid, the ``u0*`` time by the grid's ``u0*`` points, the rest by points.
The kernels are compiled or loaded first, on a small sample of the grid's points, and
compilation is excluded (Numba's event API times it). So the one line a sweep logs comes
after those blocks, for sweeps of at least :data:`CALIBRATE_ABOVE` points and more than one
block (others say it before they start, without a time). It is an estimate: the machine's
load, the blocks not timed and, with a store, block writes change the real time.

A sweep held in memory (no ``store=``) whose result exceeds the memory available is refused
with a :class:`SweepTooLargeError` before any work.
"""

from __future__ import annotations

import itertools
import logging
import math
import shutil
import time
from dataclasses import dataclass
from pathlib import Path
from typing import cast

import numpy as np

from .._fields import CATEGORICAL_FIELDS
from .._validate import _bytes, available_memory

__all__ = ["SweepEstimate", "SweepTooLargeError", "estimate_sweep", "available_memory",
           "BIG_POINTS", "BIG_SECONDS", "CALIBRATE_ABOVE", "COMPILE_SECONDS",
           "check_memory"]

logger = logging.getLogger("agglomtool.maps")

#: A sweep of more points than this, or of more estimated seconds than :data:`BIG_SECONDS`,
#: is big: its estimate is logged at WARNING (shown on stderr by default); others at INFO.
BIG_POINTS = 1_000_000
BIG_SECONDS = 10.0
#: Sweeps of at least this many points (and more than one block) have their time measured
#: on their first block (the kernels' warm-up before it takes a few tenths of a second).
CALIBRATE_ABOVE = 100_000
#: The warm-up's sample sizes (either side of the kernels' serial-parallel switch) and its
#: number of combinations of the grid's names.
SAMPLE_POINTS, SMALL_POINTS, MAX_COMBOS = 512, 16, 4
#: Blocks timed for the estimate, spread over the grid (one where there are fewer than four
#: times as many to do).
TIMED_BLOCKS = 3

#: Seconds to compile the kernels of a model tier from an empty cache, for the compile
#: note: Numba's compile time in ``python -m agglomtool map`` of the README's example in each
#: mode, on the 2-core machine of the README's figures (2026-11-25). A grid over several
#: modes adds them up (their shared kernels make that an overestimate). ``relative`` and
#: ``paper`` include the compiled sticking set (re-measured 2026-11-25: 26 s and 29 s for the
#: whole first run against 4.9 s warm, at load 1.2-1.4). ``ode``, ``ode_selfconsistent`` and
#: ``auto`` compile the bracketed sticking set's pass as well: on 2026-11-26 (load about 1,
#: a slower day: ``relative`` 33 s) their first runs less the warm ones took 39, 33 and 57 s;
#: the figures below are ``relative``'s 21 s times those ratios.
COMPILE_SECONDS = {"relative": 21.0, "paper": 24.0, "stokes": 5.0, "ode": 25.0,
                   "ode_selfconsistent": 21.0, "auto": 36.0}


class SweepTooLargeError(ValueError):
    """An in-memory sweep's result would not fit in the memory available.

    Attributes ``needed`` and ``available`` are in bytes.
    """

    def __init__(self, message: str, needed: int, available: int):
        super().__init__(message)
        self.needed, self.available = needed, available


@dataclass(frozen=True)
class SweepEstimate:
    """What a sweep will take.

    Attributes
    ----------
    points, blocks : int
        Grid points and blocks.
    memory_bytes : int
        Bytes of the result held in memory (every variable and coordinate).
    store_bytes : int or None
        Bytes of the store's arrays uncompressed (the store is smaller: its chunks are
        zstd-compressed), ``None`` without ``store=``.
    seconds : float or None
        Estimated compute time [s], ``None`` where it was not measured.
    method : str
        How ``seconds`` was obtained.
    memory_available, disk_free : int or None
        Bytes of memory available now and free on the store's disk (``None``: unknown or
        no store).
    """

    points: int
    blocks: int
    memory_bytes: int
    store_bytes: int | None
    seconds: float | None
    method: str
    memory_available: int | None
    disk_free: int | None

    @property
    def big(self) -> bool:
        """More than :data:`BIG_POINTS` points or :data:`BIG_SECONDS` seconds."""
        return self.points > BIG_POINTS or (self.seconds or 0.0) > BIG_SECONDS

    def describe(self) -> str:
        """One line: ``sweep of N points in B blocks: time; memory; store``."""
        head = f"sweep of {_count(self.points)} points in {self.blocks} block" \
               f"{'s' if self.blocks != 1 else ''}"
        if self.seconds is None:
            when = f"time not estimated ({self.method})"
        else:
            when = f"about {_duration(self.seconds)} to compute (an estimate: {self.method})"
        mem = f"result {_bytes(self.memory_bytes)} in memory"
        if self.memory_available is not None:
            mem += f" ({_bytes(self.memory_available)} available)"
        parts = [when, mem]
        if self.store_bytes is not None:
            disk = f"store up to {_bytes(self.store_bytes)} uncompressed"
            if self.disk_free is not None:
                disk += f" ({_bytes(self.disk_free)} free on its disk)"
            parts.append(disk)
        return f"{head}: " + "; ".join(parts)


def _count(n: int) -> str:
    return str(n) if n < 1_000_000 else f"{n:.3g}"


def _duration(s: float) -> str:
    if s < 60:
        return f"{s:.2g} s" if s < 10 else f"{s:.0f} s"
    if s < 3600:
        return f"{s / 60:.0f} min"
    if s < 86400:
        h, m = divmod(round(s / 60), 60)
        return f"{h} h {m} min" if m else f"{h} h"
    return f"{s / 86400:.1f} days"


# ---------------------------------------------------------------------------------------
# Memory and disk


def _disk_free(store) -> int | None:
    path = Path(store).absolute()
    for p in (path, *path.parents):
        if p.exists():
            try:
                return int(shutil.disk_usage(p).free)
            except OSError:
                return None
    return None


def check_memory(est: SweepEstimate) -> None:
    """Refuse an in-memory result larger than the memory available (before any work)."""
    avail = est.memory_available
    if avail is None or est.memory_bytes <= avail:
        return
    raise SweepTooLargeError(
        f"the sweep of {_count(est.points)} points would hold {_bytes(est.memory_bytes)} "
        f"in memory and {_bytes(avail)} is available; pass store='a directory' to write it "
        "block by block to disk (the command line always does: --store), or sweep fewer "
        "points", est.memory_bytes, avail)


# ---------------------------------------------------------------------------------------
# Time


def _combos(plan, rng) -> list[dict]:
    """Up to :data:`MAX_COMBOS` combinations of the grid's names (all if few)."""
    cats = [d for d in plan.grid if d in CATEGORICAL_FIELDS]
    if not cats:
        return [{}]
    every = math.prod(len(plan.grid[d]) for d in cats)
    if every <= MAX_COMBOS:
        return [dict(zip(cats, c, strict=True))
                for c in itertools.product(*[plan.grid[d] for d in cats])]
    return [{d: plan.grid[d][rng.integers(len(plan.grid[d]))] for d in cats}
            for _ in range(MAX_COMBOS)]


#: The sweeps warmed up in this process (:func:`_warm_key`): their kernels are loaded.
_WARMED: set = set()


def _warm_key(plan) -> str:
    """What decides the kernels a sweep runs: its scene's values, the fields it sweeps and
    the names it sweeps (tiers, speed laws, materials); not the numbers swept."""
    import json

    return json.dumps([plan.base, list(plan.grid),
                       {d: [str(v) for v in plan.grid[d]] for d in plan.grid
                        if d in CATEGORICAL_FIELDS}], sort_keys=True, default=str)


def warm_up(plan, seed: int = 0) -> None:
    """Evaluate every group on a small sample of the grid's points (16 and 512 points, up to
    :data:`MAX_COMBOS` combinations of its names): the kernels of both launch variants
    (serial below a size, parallel above) are compiled or loaded before a block is timed.
    Once per process for the same scene and swept fields (:func:`_warm_key`): a sweep run
    again finds its kernels loaded, and the sample's evaluation (10-30 ms of a 1e6-point
    map) would be spent for nothing."""
    key = _warm_key(plan)
    if key in _WARMED:
        return
    _warm_up(plan, seed)
    _WARMED.add(key)


def _warm_up(plan, seed: int) -> None:
    rng = np.random.default_rng(seed)
    nums = [d for d in plan.grid if d not in CATEGORICAL_FIELDS]
    for combo in _combos(plan, rng):
        for m in (SMALL_POINTS, SAMPLE_POINTS):
            pts = {d: plan.grid[d][rng.integers(0, len(plan.grid[d]), m)] for d in nums}
            pts.update({d: np.array([v]) for d, v in combo.items()})
            u_star = plan.eager.get("u_star")
            for group in ("gas", "liquid", "fluid", "critical", "collision"):
                if not plan.group_dims[group]:
                    continue
                vals = plan.sample(pts, group, u_star if group == "collision" else None)
                if group == "critical":
                    u_star = vals["u_star"]


def _timed_block(plan, sl: dict, compute):
    """``(result, u0* seconds, other seconds)`` of ``compute()`` on the block ``sl``, its
    ``u0*`` part timed apart (then kept for the block); compilation excluded."""
    from .progress import CompileClock, listen_to_compiles

    clock = CompileClock()
    with listen_to_compiles(clock.on_start, clock.on_end):
        c0, t0 = clock.seconds, time.perf_counter()
        if plan.group_dims["critical"]:
            plan._critical(sl)
        t_crit = max(0.0, time.perf_counter() - t0 - (clock.seconds - c0))
        c1, t1 = clock.seconds, time.perf_counter()
        result = compute()
        t_rest = max(0.0, time.perf_counter() - t1 - (clock.seconds - c1))
    return result, t_crit, t_rest


def _spread(plan, skip, k: int) -> list:
    """``k`` blocks not in ``skip``, spread over the grid (at 1/2k, 3/2k, ... of the blocks'
    order)."""
    n, out = plan.n_blocks, cast(list, [])
    for i in range(k):
        pos = (2 * i + 1) * n // (2 * k)
        for p in itertools.chain(range(pos, n), range(pos)):
            idx, sl = plan.block_at(p)
            if idx not in skip and idx not in {b[0] for b in out}:
                out.append((idx, sl))
                break
    return out


def timed_blocks(plan, compute, skip=frozenset(), points_todo=None):
    """``(results, seconds, method)``: ``compute(idx, sl)`` of up to :data:`TIMED_BLOCKS`
    blocks spread over the grid (one where there are few), timed, and scaled to the
    ``points_todo`` points left (all by default): their ``u0*`` time by the grid's ``u0*``
    points, the rest by points. ``results``: ``[(idx, sl, result)]``."""
    if points_todo is None:
        points_todo = plan.points
    left = plan.n_blocks - len(skip)
    blocks = _spread(plan, skip, TIMED_BLOCKS if left >= 4 * TIMED_BLOCKS else 1)
    crit = plan.group_dims["critical"]
    results, tc, tr, pc, pr = [], 0.0, 0.0, 0, 0
    for idx, sl in blocks:
        result, t_crit, t_rest = _timed_block(plan, sl, lambda idx=idx, sl=sl:
                                              compute(idx, sl))
        results.append((idx, sl, result))
        tc, tr = tc + t_crit, tr + t_rest
        pc += math.prod(sl[d].stop - sl[d].start for d in crit)
        pr += plan.block_points(sl)
    seconds = (tc / pc * plan.group_work("critical")[0] * points_todo / plan.points
               + tr / pr * points_todo)
    method = (f"{len(blocks)} block{'s' if len(blocks) > 1 else ''} ({pr} points) timed "
              "here and scaled to the grid, compilation excluded")
    return results, seconds, method


def run_blocks_here(plan, compute, done, announce, skip=frozenset()) -> None:
    """Compute every block not in ``skip`` in this process: ``done(idx, sl, compute(idx,
    sl))`` for each. ``announce(seconds, method)`` is called once, before ``done`` is first
    called: with the time of a few blocks (:func:`timed_blocks`, after :func:`warm_up`)
    where there are at least :data:`CALIBRATE_ABOVE` points and more than one block to do;
    else with ``None``, before any block."""
    points_todo = plan.points - sum(plan.block_points(plan.block_slices(i)) for i in skip)
    left = plan.n_blocks - len(skip)
    first = []
    if points_todo >= CALIBRATE_ABOVE and left > 1:
        warm_up(plan)
        first, seconds, method = timed_blocks(plan, compute, skip, points_todo)
        announce(seconds, method)
    else:
        announce(None, "nothing left to compute" if not left else
                 f"fewer than {CALIBRATE_ABOVE:.0e} points to compute"
                 if points_todo < CALIBRATE_ABOVE else "one block")
    for idx, sl, result in first:
        done(idx, sl, result)
    timed = {idx for idx, _, _ in first}
    for idx, sl in plan.blocks():
        if idx not in skip and idx not in timed:
            done(idx, sl, compute(idx, sl))


def estimate_plan(plan, *, store=None, seconds=None, method="not measured") -> SweepEstimate:
    """The :class:`SweepEstimate` of a :class:`~agglomtool.maps.plan.SweepPlan` with the
    time ``seconds`` (``None``: not measured, ``method`` says why)."""
    return SweepEstimate(
        points=plan.points, blocks=plan.n_blocks, memory_bytes=plan.nbytes,
        store_bytes=None if store is None else plan.nbytes, seconds=seconds,
        method=method, memory_available=available_memory(),
        disk_free=None if store is None else _disk_free(store))


def announcer(plan, store=None):
    """``announce(seconds, method)``: log the sweep's estimate once (WARNING when big, else
    INFO) and return it."""

    def announce(seconds=None, method="not measured"):
        est = estimate_plan(plan, store=store, seconds=seconds, method=method)
        logger.log(logging.WARNING if est.big else logging.INFO, est.describe())
        return est

    return announce


def compile_seconds(plan) -> float:
    """The compile note's figure for the sweep's tiers (:data:`COMPILE_SECONDS`)."""
    modes = dict.fromkeys(str(m) for m in plan.grid.get("mode", [plan.base["mode"]]))
    return sum(COMPILE_SECONDS.get(m, max(COMPILE_SECONDS.values())) for m in modes)


def estimate_sweep(scene, *, chunks="auto", nodes: int = 16, store=None, calibrate=None,
                   **grid) -> SweepEstimate:
    """What :func:`agglomtool.maps.sweep` with the same arguments will take, without
    running it.

    Parameters
    ----------
    scene, chunks, nodes, store, **grid
        As for :func:`agglomtool.maps.sweep`.
    calibrate : bool, optional
        Measure the time: compute the sweep's first block (then discarded), timed, and
        scale it to the grid (module docstring). ``None`` (default): where the sweep has at
        least :data:`CALIBRATE_ABOVE` points.

    Returns
    -------
    SweepEstimate
        Points, blocks, bytes in memory and in the store (exact), the estimated seconds,
        the memory available and the store's free disk space;
        :meth:`SweepEstimate.describe` says it in one line.
    """
    from .layout import sweep_chunks
    from .plan import _plan

    # the blocks the sweep will plan (in memory, here: by the thread count)
    plan = _plan(scene, sweep_chunks(chunks, store is None), nodes, grid)
    if calibrate is None:
        calibrate = plan.points >= CALIBRATE_ABOVE
    if not calibrate:
        return estimate_plan(plan, store=store, method="not asked for" if calibrate is False
                             and plan.points >= CALIBRATE_ABOVE
                             else f"fewer than {CALIBRATE_ABOVE:.0e} points")
    warm_up(plan)
    _, seconds, method = timed_blocks(plan, lambda idx, sl: plan.evaluate(sl, plan.owned(idx)))
    return estimate_plan(plan, store=store, seconds=seconds, method=method)
