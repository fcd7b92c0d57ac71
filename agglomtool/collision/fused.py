"""Pair preparation fused into the compiled loops: from raw inputs to outcomes in one pass.

:func:`agglomtool.pair.prepare_pair` is the readable numpy reference of the preparation
(wet masses, Eqs. 32-33; harmonic radius, Eq. 3; Wen-Yu ``U_mf``; Gidaspow drag, Eqs. 18-21;
weight and buoyancy, Eqs. 22-24; projection on the collision axis, Eqs. 116-119). This
module computes the same numbers per collision inside the compiled loop, so a batch makes no
intermediate arrays: the inputs are read once and only ``e_w``, ``stage``, ``path`` and ``w``
are written.

The physics itself (wet mass, Wen-Yu ``U_mf``, Gidaspow's drag, ``U_e = 1.1 U_mf``) is
written once, in :mod:`.physics`, and called by both; the reference and this module give
bitwise the same masses and body forces (``tests/test_one_source.py``), the other prepared
numbers likewise (``tests/test_fused_equality.py``). Two differences of evaluation, neither
of value:

- only the drag branch that is used is evaluated (the reference broadcasts the scalar
  drag over arrays, which takes one branch per element too);
- the slip speed is ``|z|`` where the lateral slip is exactly zero (``hypot(0, z)`` is
  ``|z|``, without the overflow-safe ``hypot`` call); there the lateral force is a zero
  and its projection (``cos(beta)`` times it) is not formed, which can change only the
  sign of a zero force.

The cosine of the contact angle and the sine of the collision angle are the dearest
numbers of the preparation (each costs about as much as the rest of it together). The
loops take them from the previous collision where its angle is the same (:func:`_angles`):
in a map an angle usually stays fixed over many collisions. The parallel loops run in
blocks of at most :data:`BLOCK` collisions (:func:`launch_blocks`), each a serial loop
carrying that memo. The values are
the same either way (tested bitwise against :func:`prepare_one` on each collision alone).

Inputs
------
Twenty float64 arrays, in the order of :data:`INPUT_NAMES`, each 1-D, C-contiguous and of
length 1 (broadcast to every collision) or ``n``; :func:`fused_batch`'s parallel loop also
takes an input's own values read through its strides over the batch's axes (step
:data:`BROADCAST`, a map block's inputs, no copy: :func:`flat_inputs` with ``lazy=True``);
``U`` is NaN where ``Bed.U`` is None and
``u0_j`` NaN where it is None (head-on: ``u0`` for both). Flags: ``body`` (body forces on),
``particle_slip`` (``drag_slip="particle"``).

Batches below :data:`SERIAL_BELOW` collisions run in a plain loop on the calling thread:
launching the parallel loop costs tens of microseconds, more than a small batch itself.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np
from numba import njit, prange, types
from numba.extending import overload

from .._jit import CACHE, parallel_launch
from ..constants import GRAVITY
from ._codes import N_DETAILS
from .paper import paper_kernel
from .physics import (
    U_E_PER_UMF,
    WEN_YU_C1,
    WEN_YU_C2,
    drag_gidaspow,
    wet_mass,
    wet_sphere,
    wet_umf,
)
from .records import Pair, Prepared, RawPair
from .relative import relative_kernel

__all__ = [
    "INPUT_NAMES",
    "SERIAL_BELOW",
    "prepare_one",
    "prepare_flat",
    "prepare_at",
    "fused_batch",
    "check_speeds",
    "slip_flag",
    "FusedFlags",
    "FusedOutputs",
    "launch_blocks",
    "materialize",
    "BROADCAST",
]

#: The inputs, in the order the fused kernels take them.
INPUT_NAMES = (
    "p_i.d", "p_i.rho", "p_i.h0", "p_i.ha", "p_j.d", "p_j.rho", "p_j.h0", "p_j.ha",
    "liquid.mu", "liquid.gamma", "liquid.rho", "liquid.theta_deg", "gas.mu", "gas.rho",
    "bed.eps", "bed.U", "beta_deg", "e", "u0", "u0_j",
)
N_INPUTS = len(INPUT_NAMES)

#: Batches smaller than this run serially on the calling thread. Measured on 2 busy cores:
#: with its threads awake the parallel loop wins from about 30 collisions (100: 18 against
#: 28 us; 1000: 0.15 against 0.27 ms), but when a worker thread has been descheduled the
#: launch waits at the barrier for milliseconds (7.7 ms seen at 1000 collisions). Below 2000
#: collisions (0.6 ms serially) the serial loop's steady time is preferred.
SERIAL_BELOW = 2000

#: Collisions per block of the parallel loops: each block is a serial loop on one thread,
#: which carries the angles' memo (:func:`_angles`) from one collision to the next.
BLOCK = 4096

#: Blocks per thread that a parallel launch aims at, and the fewest collisions per block:
#: a launch of few blocks per thread (a map's block of 2.4e5 collisions on 16 threads has
#: 58 blocks of :data:`BLOCK`) runs blocks of fewer collisions (:func:`launch_blocks`).
BLOCKS_PER_THREAD = 8
MIN_BLOCK = 256

#: Tier codes of :func:`fused_batch`.
TIER_PAPER, TIER_RELATIVE = 0, 1

def tier_kernel(tier, pair, w, row):
    """``(e_w, stage, path)`` of the ``tier`` kernel (:data:`TIER_PAPER`: ``paper_kernel``,
    :data:`TIER_RELATIVE`: ``relative_kernel``) for the :class:`.records.Pair` ``pair`` at
    relative speed ``w`` [m/s], the details into ``row``, in compiled code only. Where ``tier`` is a
    compile-time constant (the entry points pass :data:`TIER_PAPER` or
    :data:`TIER_RELATIVE`) only that tier's kernel is compiled; else both, chosen at run
    time."""
    raise NotImplementedError("tier_kernel is called from compiled code only")


@overload(tier_kernel, prefer_literal=True, inline="always")
def _tier_kernel(tier, pair, w, row):
    def paper(tier, pair, w, row):
        return paper_kernel(pair, w, row)

    def relative(tier, pair, w, row):
        ew, sg, pa, _ = relative_kernel(pair, w, row)
        return ew, sg, pa

    def either(tier, pair, w, row):
        if tier == TIER_PAPER:
            return paper_kernel(pair, w, row)
        ew, sg, pa, _ = relative_kernel(pair, w, row)
        return ew, sg, pa

    if isinstance(tier, types.IntegerLiteral):
        return paper if tier.literal_value == TIER_PAPER else relative
    return either


_DEG = math.pi / 180.0  # numpy's deg2rad multiplies by the same constant


class GasFlow(NamedTuple):
    """The gas around a pair, as the body forces of :func:`_body_force_n` need it."""

    #: gas viscosity [Pa s]
    mu_g: float
    #: gas density [kg/m3]
    rho_g: float
    #: bed voidage [-]
    eps: float
    #: the emulsion's superficial gas speed [m/s] (``U``, or ``1.1 U_mf``)
    U_e: float


@njit(cache=CACHE)
def _body_force_n(d, h0, m, gas, uy, uz, particle_slip, cs_b):
    """Net body force on one particle projected on the axis ``n`` [N]
    (``pair.body_force_vector`` then Eq. 118); ``(uy, uz)`` its lab velocity [m/s];
    ``gas``: :class:`GasFlow`; ``cs_b``: the cosine and the sine of the collision angle,
    the cosine read only where the lateral slip is nonzero (``particle_slip``)."""
    mu_g, rho_g, eps, U_e = gas
    cos_b, sin_b = cs_b
    if math.isinf(d):
        vol = 0.0
        d_wet = 1.0
        m_f = 0.0
    else:
        d_wet, vol = wet_sphere(d, h0)
        m_f = m
    slip_z = U_e / eps
    slip_y = 0.0
    if particle_slip:
        slip_y = slip_y - uy
        slip_z = slip_z - uz
    # hypot(0, z) is |z| exactly; the cheaper form where the lateral slip is zero.
    speed = math.hypot(slip_y, slip_z) if slip_y != 0.0 else abs(slip_z)
    f_drag = drag_gidaspow(speed, d_wet, vol, eps, mu_g, rho_g)
    safe = speed if speed > 0.0 else 1.0
    f_z = f_drag * slip_z / safe + (rho_g * vol - m_f) * GRAVITY
    if slip_y == 0.0:
        # The lateral force is then a zero (f_drag * 0): its projection adds nothing but,
        # at most, the sign of a zero result.
        return f_z * sin_b
    f_y = f_drag * slip_y / safe
    return f_y * cos_b + f_z * sin_b


@njit(cache=CACHE)
def prepare_one(raw, u0, u0_j, body, particle_slip):
    """The kernel numbers of one collision from its raw inputs ``raw`` (a
    :class:`.records.RawPair`) and its lab speeds ``u0``, ``u0_j`` [m/s] (``u0_j`` NaN:
    head-on, ``u0`` for both) (module docstring).

    Returns a :class:`.records.Prepared`: masses [kg], harmonic radius [m], gaps [m],
    cosine of the contact angle and the angle [rad], projected body forces [N], relative
    normal speed ``u_i + u_j`` [m/s] and its ratio to a head-on ``u0`` [-] (2, or 1 with a
    plate).
    """
    beta_deg = raw.beta_deg
    sin_b = math.sin(beta_deg * _DEG) if body else 0.0
    theta_deg = raw.theta_deg
    (m_i, m_j, r, H0, Ha, cos_t, theta, fn_i, fn_j, w,
     w_per_u0) = _prepare(raw, theta_deg * _DEG, math.cos(theta_deg * _DEG), sin_b, u0,
                          u0_j, body, particle_slip)
    return Prepared(m_i, m_j, r, H0, Ha, cos_t, theta, fn_i, fn_j, w, w_per_u0)


@njit(cache=CACHE, inline="always")
def _prepare(raw, theta, cos_t, sin_b, u0, u0_j, body, particle_slip):
    """:func:`prepare_one` from the contact angle [rad] and its cosine, and the sine of
    the collision angle (read only with ``body``): the loops take them from
    :func:`_angles`. ``raw``'s ``theta_deg`` is not read. A plain tuple, in the order of
    :class:`.records.Prepared` (:func:`_one` adds the angles' memo to it)."""
    d_i, rho_i, h0_i, ha_i = raw.d_i, raw.rho_i, raw.h0_i, raw.ha_i
    d_j, rho_j, h0_j, ha_j = raw.d_j, raw.rho_j, raw.h0_j, raw.ha_j
    rho_l, mu_g, rho_g, eps = raw.rho_l, raw.mu_g, raw.rho_g, raw.eps
    beta_deg = raw.beta_deg
    plate_i = math.isinf(d_i)
    plate_j = math.isinf(d_j)
    m_i = wet_mass(d_i, rho_i, h0_i, rho_l)
    m_j = wet_mass(d_j, rho_j, h0_j, rho_l)
    r = 2.0 / (2.0 / d_i + 2.0 / d_j)
    u_i = 0.0 if plate_i else u0
    if math.isnan(u0_j):
        u_j = 0.0 if plate_j else u0
    else:
        u_j = u0_j
    if body:
        U_e = _gas_speed(raw, m_i, m_j)
        # The cosine of the collision angle only projects a lateral slip (particle_slip).
        cos_b = math.cos(beta_deg * _DEG) if particle_slip else 0.0
        gas = GasFlow(mu_g=mu_g, rho_g=rho_g, eps=eps, U_e=U_e)
        fn_i = _body_force_n(d_i, h0_i, m_i, gas, u_i * cos_b, u_i * sin_b, particle_slip,
                             (cos_b, sin_b))
        fn_j = _body_force_n(d_j, h0_j, m_j, gas, -u_j * cos_b, -u_j * sin_b, particle_slip,
                             (cos_b, sin_b))
    else:
        fn_i = 0.0
        fn_j = 0.0
    w_per_u0 = 1.0 if (plate_i or plate_j) else 2.0
    return (m_i, m_j, r, h0_i + h0_j, ha_i + ha_j, cos_t, theta, fn_i, fn_j, u_i + u_j,
            w_per_u0)


@njit(cache=CACHE, inline="always")
def _gas_speed(raw, m_i, m_j):
    """The superficial gas speed around a pair [m/s] (``raw``: a :class:`.records.RawPair`):
    its ``U``, or where that is NaN the excess gas speed, ``1.1`` times the larger Wen-Yu
    ``U_mf`` of the two wet particles (wet masses ``m_i``, ``m_j`` [kg])."""
    U = raw.U
    if math.isnan(U):
        mu_g, rho_g = raw.mu_g, raw.rho_g
        return U_E_PER_UMF * max(
            wet_umf(raw.d_i, raw.h0_i, m_i, mu_g, rho_g, WEN_YU_C1, WEN_YU_C2),
            wet_umf(raw.d_j, raw.h0_j, m_j, mu_g, rho_g, WEN_YU_C1, WEN_YU_C2))
    return U


@njit(cache=CACHE)
def body_force_range(raw, u_a, u_b):
    """``(lo_i, hi_i, lo_j, hi_j)`` [N]: at every head-on lab speed ``u_a <= u <= u_b``
    [m/s], ``fn_i`` (:func:`prepare_one` with ``body`` and ``particle_slip``) lies within
    ``[lo_i, hi_i]`` and ``fn_j`` within ``[lo_j, hi_j]``: the smaller and the larger of
    its values at the two ends. NaN for a plate (not bounded here).

    Each is monotonic in ``u``. Particle i moves at ``u`` along the axis ``n``, so its slip
    (the gas's velocity less its own) has the component ``z = (U_e / eps) sin(beta) - u``
    along ``n`` and the constant one ``(U_e / eps) cos(beta)`` across it; the drag's
    projection on ``n`` is ``D(s) z / s`` with ``s`` the slip's size. For ``z > 0`` both
    ``D(s)`` (Gidaspow's drag grows with the slip in both branches; ``C_d Re`` jumps
    upwards at ``Re = 1000``) and ``z / s`` are positive and grow with ``z``, and the
    projection is odd in ``z``: it grows with ``z``, so it falls as ``u`` grows. Particle j
    moves at ``-u``, its ``z`` is ``(U_e / eps) sin(beta) + u``: its projection grows with
    ``u``. The weight and buoyancy do not depend on ``u``."""
    if math.isinf(raw.d_i) or math.isinf(raw.d_j):
        return math.nan, math.nan, math.nan, math.nan
    a = prepare_one(raw, u_a, math.nan, True, True)
    b = prepare_one(raw, u_b, math.nan, True, True)
    return (min(a.fn_i, b.fn_i), max(a.fn_i, b.fn_i), min(a.fn_j, b.fn_j),
            max(a.fn_j, b.fn_j))


class FusedFlags(NamedTuple):
    """The flags of a fused loop (:func:`fused_batch`), one record for a batch."""

    #: weight, buoyancy and drag on
    body: bool
    #: the drag's slip is the particle's own speed: ``True``, or ``None`` for false
    #: (:func:`slip_flag`: the loop is compiled without the lateral-slip code)
    particle_slip: object
    #: validate the lab speeds in the same pass (:func:`check_speeds`' rules)
    check: bool


class FusedOutputs(NamedTuple):
    """The output arrays of a fused loop, one element (row) per collision."""

    #: velocity restitution coefficients [-]
    e_w: np.ndarray
    #: stage codes (int8)
    stage: np.ndarray
    #: path codes (int8)
    path: np.ndarray
    #: relative normal impact speeds [m/s]
    w: np.ndarray
    #: details, ``(n, N_DETAILS)``, or ``(n, 0)`` without
    det: np.ndarray


#: The angles' memo of a loop before its first collision (:func:`_angles`).
NO_ANGLES = (math.nan, math.nan, math.nan, math.nan)


@njit(cache=CACHE, inline="always")
def _angles(ins, st, k, body, last):
    """``(theta_deg, cos_t, beta_deg, sin_b)`` of collision ``k``, the cosine and the sine
    taken from ``last`` (the previous collision's) where its angle is the same. A map
    usually holds an angle fixed over many collisions, and a cosine or a sine costs as
    much as the rest of the preparation's arithmetic together; the values are the same
    either way (a NaN angle never matches, so it is evaluated)."""
    td = ins[11][k * st[11]]
    if td == last[0]:
        ct = last[1]
    else:
        ct = math.cos(td * _DEG)
    bd = ins[16][k * st[16]]
    if not body:
        sb = 0.0
    elif bd == last[2]:
        sb = last[3]
    else:
        sb = math.sin(bd * _DEG)
    return td, ct, bd, sb


@njit(cache=CACHE, inline="always")
def _one(ins, st, k, body, particle_slip, last):
    """:func:`prepare_one` of collision ``k`` of the fused inputs followed by the angles'
    memo for the next collision (four more items; ``last``: this loop's previous memo, or
    :data:`NO_ANGLES`). One flat tuple: numba's parallel loops do not unpack nested ones."""
    ang = _angles(ins, st, k, body, last)
    raw = RawPair(
        ins[0][k * st[0]], ins[1][k * st[1]], ins[2][k * st[2]], ins[3][k * st[3]],
        ins[4][k * st[4]], ins[5][k * st[5]], ins[6][k * st[6]], ins[7][k * st[7]],
        ins[8][k * st[8]], ins[9][k * st[9]], ins[10][k * st[10]], ang[0],
        ins[12][k * st[12]], ins[13][k * st[13]], ins[14][k * st[14]], ins[15][k * st[15]],
        ang[2], ins[17][k * st[17]],
    )
    return _prepare(raw, ang[0] * _DEG, ang[1], ang[3], ins[18][k * st[18]],
                    ins[19][k * st[19]], body, particle_slip) + ang


@njit(cache=CACHE)
def _fused_block(ins, st, flags, tier, out, k0, k1):
    """The fused loop over collisions ``k0 <= k < k1`` (one thread, carrying the angles'
    memo), its flags a :class:`FusedFlags`, its outputs written into ``out`` (a
    :class:`FusedOutputs`). Returns each speed rule's first offender among them (``n``:
    none); with ``flags.check`` a collision that breaks rule 3 or 4 is not computed (NaN,
    stage -1)."""
    body, particle_slip, check = flags
    e_w, stage, path, w_out, det = out
    n = e_w.shape[0]
    g1 = n
    g2 = n
    g3 = n
    g4 = n
    last = NO_ANGLES
    for k in range(k0, k1):
        if check:
            g1, g2, g3, g4, skip = _rules_update(ins, st, k, g1, g2, g3, g4)
            if skip:  # no approach, or an infinite speed: nothing to compute
                e_w[k] = math.nan
                stage[k] = -1
                path[k] = 0
                w_out[k] = math.nan
                continue
        row = det[k]  # of length 0 without details (cheaper than choosing an empty array)
        (m_i, m_j, r, H0, Ha, cos_t, theta, fn_i, fn_j, w, _, a_t, a_c, a_b,
         a_s) = _one(ins, st, k, body, particle_slip, last)
        last = (a_t, a_c, a_b, a_s)
        mu_l = ins[8][k * st[8]]
        gamma = ins[9][k * st[9]]
        e = ins[17][k * st[17]]
        ew, sg, pa = tier_kernel(tier, Pair(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta,
                                            fn_i, fn_j, e), w, row)
        e_w[k] = ew
        stage[k] = sg
        path[k] = pa
        w_out[k] = w
    return g1, g2, g3, g4


# The serial and the parallel loop run the same compiled block function: numba's cache does
# not tell a function compiled with parallel=True from one without, so the two entry points
# are two functions, but the loop body is written once.


@njit(cache=CACHE)
def _fused_serial(ins, st, flags, tier, out):
    return _fused_block(ins, st, flags, tier, out, 0, out.e_w.shape[0])


def launch_blocks(n: int, full: int = BLOCK, least: int = MIN_BLOCK) -> tuple[int, int]:
    """``(block, lanes)`` of a parallel launch over ``n`` items: blocks of at most ``full``
    items, fewer (at least ``least``) where there would be under
    :data:`BLOCKS_PER_THREAD` blocks per thread; ``lanes`` the threads' count (at most the
    blocks'). Lane ``t`` runs blocks ``t, t + lanes, t + 2 lanes, ...``: numba gives each
    thread a contiguous share of a ``prange``, so each lane's blocks are spread over the
    whole batch and a region of dear collisions (a map's corner) is shared by all threads.
    Only the order of the work changes, never a collision's arithmetic."""
    threads = numba.get_num_threads()
    block = max(min(least, full), min(full, -(-n // (threads * BLOCKS_PER_THREAD))))
    return block, max(1, min(threads, -(-n // block)))


@njit(parallel=True, cache=CACHE)
def _fused_parallel(ins, st, flags, tier, out, block, lanes):
    n = out.e_w.shape[0]
    nb = (n + block - 1) // block
    # Each speed rule's first offender as a min-reduction over the lanes (check_speeds'
    # rules and answer, whatever order the threads take).
    f1 = n
    f2 = n
    f3 = n
    f4 = n
    for t in prange(lanes):
        h1 = n
        h2 = n
        h3 = n
        h4 = n
        for b in range(t, nb, lanes):
            g1, g2, g3, g4 = _fused_block(ins, st, flags, tier, out, b * block,
                                          min(n, (b + 1) * block))
            h1 = min(h1, g1)
            h2 = min(h2, g2)
            h3 = min(h3, g3)
            h4 = min(h4, g4)
        f1 = min(f1, h1)
        f2 = min(f2, h2)
        f3 = min(f3, h3)
        f4 = min(f4, h4)
    return f1, f2, f3, f4


# One pair of entry points per tier, the tier a compile-time constant: only that tier's
# kernel is compiled into the loops (tier_kernel). A first run in mode "relative" compiles
# no "paper" kernel, and the other way round.


# Their ``flags`` and ``out`` come from Python as plain tuples and are made records here:
# numba's dispatcher types a plain tuple as fast as separate arguments, named tuples more
# slowly: these two cost about 1 us more per call as records (measured; a collide of one
# pair takes about 40 us).


@njit(cache=CACHE)
def _fused_serial_paper(ins, st, flags, out):
    return _fused_serial(ins, st, FusedFlags(*flags), TIER_PAPER, FusedOutputs(*out))


@njit(cache=CACHE)
def _fused_serial_relative(ins, st, flags, out):
    return _fused_serial(ins, st, FusedFlags(*flags), TIER_RELATIVE, FusedOutputs(*out))


@njit(cache=CACHE)
def _fused_parallel_paper(ins, st, flags, out, block, lanes):
    return _fused_parallel(ins, st, FusedFlags(*flags), TIER_PAPER, FusedOutputs(*out), block,
                           lanes)


@njit(cache=CACHE)
def _fused_parallel_relative(ins, st, flags, out, block, lanes):
    return _fused_parallel(ins, st, FusedFlags(*flags), TIER_RELATIVE, FusedOutputs(*out),
                           block, lanes)


#: (tier, parallel) -> the loop's entry point.
_FUSED_ENTRY = {(TIER_PAPER, False): _fused_serial_paper,
                (TIER_RELATIVE, False): _fused_serial_relative,
                (TIER_PAPER, True): _fused_parallel_paper,
                (TIER_RELATIVE, True): _fused_parallel_relative}


# -- broadcast inputs read in place ---------------------------------------------------------
# A map's block hands the fused loop inputs that vary along some of its axes only (the
# liquid's properties along T, the coating along h0, ...). Broadcast to the block and copied,
# each cost a pass over the block's memory on the calling thread (new memory: page faults
# too), 25-40 ms of a 4e6-point water map's serial time at 1 thread. Instead the parallel
# loop takes each such input as its own values (step BROADCAST) with its strides over the
# block's axes (:func:`flat_inputs` with ``lazy=True``), and each lane copies one block of
# collisions of them at a time into a small buffer of its own (in cache), from which the
# same loop body (:func:`_fused_block`) reads them with step 1. The arithmetic of every
# collision is unchanged.

#: The step of an input read through its strides over the batch's axes (``layout``).
BROADCAST = 2


@njit(cache=CACHE)
def _fill(src, strides, shape, k0, m, row, idx):  # pragma: no cover - compiled
    """``row[:m]`` = the values of collisions ``k0 .. k0 + m - 1`` of an input whose own
    values ``src`` are read with ``strides`` (elements) over the batch's axes ``shape``
    (C order); ``idx``: scratch of the axes' count."""
    nd = shape.shape[0]
    rest = k0
    off = 0
    for d in range(nd - 1, -1, -1):
        idx[d] = rest % shape[d]
        rest //= shape[d]
        off += idx[d] * strides[d]
    last = nd - 1
    for j in range(m):
        row[j] = src[off]
        d = last
        idx[d] += 1
        off += strides[d]
        while d > 0 and idx[d] == shape[d]:
            off -= strides[d] * shape[d]
            idx[d] = 0
            d -= 1
            idx[d] += 1
            off += strides[d]


@njit(cache=CACHE, inline="always")
def _pick(a, s, buf, q, k0, k1):  # pragma: no cover - compiled
    """Input ``q`` of the block ``k0 .. k1`` as the loop reads it from 0: the input itself
    (step 0), its slice (step 1), or its row of the lane's buffer (:data:`BROADCAST`)."""
    if s == 0:
        return a
    if s == 1:
        return a[k0:k1]
    return buf[q, : k1 - k0]


@njit(cache=CACHE)
def _block_inputs(ins, st, buf, k0, k1):  # pragma: no cover - compiled
    """The fused inputs of the collisions ``k0 .. k1``, indexed from 0 (:func:`_pick`)."""
    return (
        _pick(ins[0], st[0], buf, 0, k0, k1), _pick(ins[1], st[1], buf, 1, k0, k1),
        _pick(ins[2], st[2], buf, 2, k0, k1), _pick(ins[3], st[3], buf, 3, k0, k1),
        _pick(ins[4], st[4], buf, 4, k0, k1), _pick(ins[5], st[5], buf, 5, k0, k1),
        _pick(ins[6], st[6], buf, 6, k0, k1), _pick(ins[7], st[7], buf, 7, k0, k1),
        _pick(ins[8], st[8], buf, 8, k0, k1), _pick(ins[9], st[9], buf, 9, k0, k1),
        _pick(ins[10], st[10], buf, 10, k0, k1), _pick(ins[11], st[11], buf, 11, k0, k1),
        _pick(ins[12], st[12], buf, 12, k0, k1), _pick(ins[13], st[13], buf, 13, k0, k1),
        _pick(ins[14], st[14], buf, 14, k0, k1), _pick(ins[15], st[15], buf, 15, k0, k1),
        _pick(ins[16], st[16], buf, 16, k0, k1), _pick(ins[17], st[17], buf, 17, k0, k1),
        _pick(ins[18], st[18], buf, 18, k0, k1), _pick(ins[19], st[19], buf, 19, k0, k1),
    )


@njit(cache=CACHE)
def _lane_broadcast(ins, st, layout, flags, tier, out, lane):  # pragma: no cover - compiled
    """The lane ``lane = (block, lanes, t)`` of :func:`_fused_parallel_broadcast`: its
    blocks (:func:`launch_blocks`), each run by :func:`_fused_block` on its own slices;
    each speed rule's first offender (``n``: none)."""
    block, lanes, t = lane
    shape, strides = layout
    e_w, stage, path, w_out, det = out
    n = e_w.shape[0]
    buf = np.empty((N_INPUTS, block))
    idx = np.empty(shape.shape[0], dtype=np.int64)
    local = np.minimum(st, 1)  # the buffer's rows are read with step 1
    nb = (n + block - 1) // block
    h1 = n
    h2 = n
    h3 = n
    h4 = n
    for b in range(t, nb, lanes):
        k0 = b * block
        k1 = min(n, k0 + block)
        m = k1 - k0
        for q in range(N_INPUTS):
            if st[q] == BROADCAST:
                _fill(ins[q], strides[q], shape, k0, m, buf[q], idx)
        g = _fused_block(_block_inputs(ins, st, buf, k0, k1), local, flags, tier,
                         FusedOutputs(e_w[k0:k1], stage[k0:k1], path[k0:k1], w_out[k0:k1],
                                      det[k0:k1]), 0, m)
        h1 = min(h1, g[0] + k0 if g[0] < m else n)
        h2 = min(h2, g[1] + k0 if g[1] < m else n)
        h3 = min(h3, g[2] + k0 if g[2] < m else n)
        h4 = min(h4, g[3] + k0 if g[3] < m else n)
    return h1, h2, h3, h4


@njit(parallel=True, cache=CACHE)
def _fused_parallel_broadcast(ins, st, layout, flags, tier, out, block, lanes):
    n = out.e_w.shape[0]
    f1 = n
    f2 = n
    f3 = n
    f4 = n
    for t in prange(lanes):
        h1, h2, h3, h4 = _lane_broadcast(ins, st, layout, flags, tier, out, (block, lanes, t))
        f1 = min(f1, h1)
        f2 = min(f2, h2)
        f3 = min(f3, h3)
        f4 = min(f4, h4)
    return f1, f2, f3, f4


@njit(cache=CACHE)
def _fused_broadcast_paper(ins, st, layout, flags, out, block, lanes):
    return _fused_parallel_broadcast(ins, st, layout, FusedFlags(*flags), TIER_PAPER,
                                     FusedOutputs(*out), block, lanes)


@njit(cache=CACHE)
def _fused_broadcast_relative(ins, st, layout, flags, out, block, lanes):
    return _fused_parallel_broadcast(ins, st, layout, FusedFlags(*flags), TIER_RELATIVE,
                                     FusedOutputs(*out), block, lanes)


#: tier -> the parallel loop that reads broadcast inputs in place.
_FUSED_BROADCAST = {TIER_PAPER: _fused_broadcast_paper,
                    TIER_RELATIVE: _fused_broadcast_relative}


@njit(cache=CACHE)
def _prepare_block(ins, st, idx, body, particle_slip, out, j0, j1):
    """Columns ``j0 <= j < j1`` of :func:`prepare_flat`'s array, from the collisions
    ``idx[j]`` (all collisions in order where ``idx`` is empty)."""
    last = NO_ANGLES
    every = idx.shape[0] == 0
    for j in range(j0, j1):
        k = j if every else idx[j]
        (m_i, m_j, r, H0, Ha, cos_t, theta, fn_i, fn_j, w, wpu, a_t, a_c, a_b,
         a_s) = _one(ins, st, k, body, particle_slip, last)
        last = (a_t, a_c, a_b, a_s)
        out[0, j] = m_i
        out[1, j] = m_j
        out[2, j] = r
        out[3, j] = H0
        out[4, j] = Ha
        out[5, j] = ins[8][k * st[8]]
        out[6, j] = ins[9][k * st[9]]
        out[7, j] = cos_t
        out[8, j] = theta
        out[9, j] = w
        out[10, j] = fn_i
        out[11, j] = fn_j
        out[12, j] = ins[17][k * st[17]]
        out[13, j] = wpu


@njit(cache=CACHE)
def _prepare_serial(ins, st, idx, body, particle_slip, out):
    _prepare_block(ins, st, idx, body, particle_slip, out, 0, out.shape[1])


@njit(parallel=True, cache=CACHE)
def _prepare_parallel(ins, st, idx, body, particle_slip, out):
    n = out.shape[1]
    for b in prange((n + BLOCK - 1) // BLOCK):
        _prepare_block(ins, st, idx, body, particle_slip, out, b * BLOCK,
                       min(n, (b + 1) * BLOCK))


#: ``idx`` of :func:`_prepare_block` for every collision in order.
_EVERY = np.empty(0, dtype=np.int64)


def _prepare_columns(ins, steps, idx, n, body, particle_slip):
    out = np.empty((14, n))
    args = (ins, steps, idx, bool(body), slip_flag(particle_slip), out)
    if n < SERIAL_BELOW:
        _prepare_serial(*args)
    else:
        parallel_launch(_prepare_parallel, *args)
    return out


def prepare_at(ins, steps, idx, body, particle_slip):
    """:func:`prepare_flat` of the collisions ``idx`` only (an int64 index array)."""
    idx = np.ascontiguousarray(idx, dtype=np.int64)
    if idx.shape[0] == 0:
        return np.empty((14, 0))
    return _prepare_columns(ins, steps, idx, idx.shape[0], body, particle_slip)


@njit(cache=CACHE, inline="always")
def _speed_rules_at(ins, st, k):
    """:func:`_speed_rules` of collision ``k`` of the fused inputs (``u0_j`` NaN: None)."""
    return _speed_rules((ins[0], ins[4], ins[18], ins[19]), (st[0], st[4], st[18], st[19]),
                        not math.isnan(ins[19][k * st[19]]), k)


@njit(cache=CACHE, inline="always")
def _rules_update(ins, st, k, g1, g2, g3, g4):
    """Collision ``k``'s speed rules (:func:`_speed_rules_at`) folded into ``g1 .. g4``,
    each rule's first offender so far: ``(g1, g2, g3, g4, skip)``, ``skip`` True where the
    collision breaks rule 3 or 4 (then it is not computed). A flat tuple: a parallel loop's
    body cannot unpack a nested one."""
    broken = _speed_rules_at(ins, st, k)
    g1, g2, g3, g4 = _fold_rules(k, broken, (g1, g2, g3, g4))
    return g1, g2, g3, g4, (broken[2] or broken[3])


@njit(cache=CACHE, inline="always")
def _fold_rules(k, broken, first):
    """Each rule's first offender so far, ``first`` (four indices), after collision ``k``
    broke the rules ``broken`` (four booleans; a serial scan in order of ``k``)."""
    r1, r2, r3, r4 = broken
    g1, g2, g3, g4 = first
    if r1 and k < g1:
        g1 = k
    if r2 and k < g2:
        g2 = k
    if r3 and k < g3:
        g3 = k
    if r4 and k < g4:
        g4 = k
    return g1, g2, g3, g4


@njit(cache=CACHE, inline="always")
def _speed_rules(arrays, steps, given, k):
    """The rules of :func:`check_speeds` broken by collision ``k``: four booleans.
    ``arrays``: ``(d_i, d_j, u0, u0_j)``; ``steps``: their steps (0 or 1); ``given``:
    ``u0_j`` is read."""
    d_i, d_j, u0, u0_j = arrays
    si, sj, su, sv = steps
    plate_i = math.isinf(d_i[k * si])
    plate_j = math.isinf(d_j[k * sj])
    u = u0[k * su]
    r1 = False
    r2 = False
    if given:
        v = u0_j[k * sv]
        r1 = plate_j and v != 0.0
        r2 = plate_i and u != 0.0
        w = u + v
    else:
        w = (0.0 if plate_i else u) + (0.0 if plate_j else u)
    return r1, r2, not w > 0.0, math.isinf(w)


@njit(cache=CACHE)
def _check_speeds_serial(arrays, steps, given, n):
    f1 = n
    f2 = n
    f3 = n
    f4 = n
    for k in range(n):
        f1, f2, f3, f4 = _fold_rules(k, _speed_rules(arrays, steps, given, k), (f1, f2, f3, f4))
    return f1, f2, f3, f4


@njit(parallel=True, cache=CACHE)
def _check_speeds_parallel(arrays, steps, given, n):
    # Each rule's first offender as a min-reduction over the collisions: the same answer as
    # the serial scan, whatever order the threads take.
    f1 = n
    f2 = n
    f3 = n
    f4 = n
    for k in prange(n):
        r1, r2, r3, r4 = _speed_rules(arrays, steps, given, k)
        f1 = min(f1, k if r1 else n)
        f2 = min(f2, k if r2 else n)
        f3 = min(f3, k if r3 else n)
        f4 = min(f4, k if r4 else n)
    return f1, f2, f3, f4


def check_speeds(d_i, d_j, u0, u0_j, n):
    """Validate the lab speeds of ``n`` collisions (arrays of length 1 or ``n``).

    Returns ``(code, index)`` of the first failing rule, in the order the rules are checked
    (``code`` 0: all good): 1 a plate j with ``u0_j != 0``; 2 a plate i with ``u0 != 0``
    when ``u0_j`` is given; 3 not approaching (``u_i + u_j <= 0``); 4 an infinite speed.
    ``index`` is that rule's first offending collision. ``u0_j`` of length 0 means None.
    Batches of :data:`SERIAL_BELOW` collisions or more are scanned on every thread.
    """
    given = u0_j.shape[0] > 0
    steps = (1 if d_i.shape[0] > 1 else 0, 1 if d_j.shape[0] > 1 else 0,
             1 if u0.shape[0] > 1 else 0, 1 if (given and u0_j.shape[0] > 1) else 0)
    args = ((d_i, d_j, u0, u0_j), steps, given, n)
    if n < SERIAL_BELOW:
        first = _check_speeds_serial(*args)
    else:
        first = parallel_launch(_check_speeds_parallel, *args)
    return _first_rule(first, n)


def _first_rule(first, n):
    """``(code, index)`` of the first broken rule from each rule's first offender (``n``:
    none), in the order the rules are checked; ``(0, -1)`` when all hold."""
    for code in range(1, 5):
        if first[code - 1] < n:
            return code, int(first[code - 1])
    return 0, -1


def slip_flag(particle_slip):
    """The ``particle_slip`` argument of the compiled loops: ``True``, or ``None`` for
    false. Numba compiles a separate loop for ``None``, without the lateral-slip code that
    the flag guards; a runtime ``False`` leaves that code and its branches in the loop
    (measured: ~7 % of the paper tier's time)."""
    return True if particle_slip else None


def _flat_input(a, shape, n):
    """``a`` (an array broadcasting to ``shape`` of ``n`` elements) as a writable
    C-contiguous float64 1-D array of length 1 or ``n``, and its step (0 or 1)."""
    if type(a) is not np.ndarray or a.dtype != np.float64:
        a = np.asarray(a, dtype=np.float64)
    if a.size == 1:
        return np.array(a, dtype=np.float64).reshape(1), 0
    if a.size != n:  # broadcast into a copy of its own (numpy's copy broadcasts it)
        full = np.empty(shape)
        np.copyto(full, a)
        return full.reshape(-1), 1
    if a.flags.c_contiguous and a.flags.writeable:
        # Already as required: no copy, and no new view of a 1-D array. Its elements are in
        # the broadcast order: ``a`` has the shape's ``n`` elements, so its axes longer
        # than 1 are the shape's, in order.
        return (a if a.ndim == 1 else a.reshape(-1)), 1
    return np.array(a, dtype=np.float64, order="C").reshape(-1), 1  # a writable copy


def _own_values(a, shape, n):
    """``a`` (broadcasting to ``shape``) as its own values, C-contiguous 1-D, and its
    strides in elements over ``shape``; None where :func:`_flat_input` takes ``a`` with no
    copy (one value, or ``n`` contiguous ones)."""
    if type(a) is not np.ndarray or a.dtype != np.float64:
        a = np.asarray(a, dtype=np.float64)
    if a.size == 1 or (a.size == n and a.flags.c_contiguous and a.flags.writeable):
        return None
    own = np.ascontiguousarray(a)
    if not own.flags.writeable:  # (the loops take one array type: writable, as the copies)
        own = own.copy()
    # its strides as np.broadcast_to(own, shape) has them: its own along an axis of the
    # shape's length (longer than 1), else 0
    lead = len(shape) - own.ndim
    return own.reshape(-1), [0] * lead + [own.strides[d] // 8 if m == shape[lead + d] != 1
                                          else 0 for d, m in enumerate(own.shape)]


def _layout(shape, strides: dict):
    """``(axes, strides, full)`` of the broadcast inputs (``strides``: ``{q: strides over
    shape}``): the axes' lengths, those of length 1 dropped and neighbours that every input
    steps through as one merged; an ``(N_INPUTS, axes)`` int64 array of each input's
    strides over them; and one over ``shape`` itself (for :func:`materialize`)."""
    axes: list = []  # [length, {q: stride}]
    for d, size in enumerate(shape):
        if size == 1:
            continue
        st = {q: s[d] for q, s in strides.items()}
        if axes and all(axes[-1][1][q] == st[q] * size for q in strides):
            axes[-1] = [axes[-1][0] * size, st]
        else:
            axes.append([size, st])
    lengths = np.array([a[0] for a in axes], dtype=np.int64)
    table = np.zeros((N_INPUTS, len(axes)), dtype=np.int64)
    full = np.zeros((N_INPUTS, len(shape)), dtype=np.int64)
    for q, s in strides.items():
        full[q] = s
        for j, (_, st) in enumerate(axes):
            table[q, j] = st[q]
    return lengths, table, full


def materialize(ins, steps, layout, shape):
    """The inputs of :func:`flat_inputs` with ``lazy=True`` as it returns them without:
    every :data:`BROADCAST` input broadcast to ``shape`` and copied (step 1)."""
    if layout is None:
        return ins, steps
    arrays, out = list(ins), steps.copy()
    for q in np.flatnonzero(steps == BROADCAST):
        view = np.lib.stride_tricks.as_strided(
            ins[q], shape=tuple(shape), strides=tuple(int(s) * 8 for s in layout[2][q]),
            writeable=False)
        arrays[q] = np.ascontiguousarray(view).reshape(-1)
        out[q] = 1
    return tuple(arrays), out


def flat_inputs(values, shape, lazy=False):
    """The tuple of flat input arrays and the array of their steps for :data:`INPUT_NAMES`
    ``values`` (float64 arrays, or Python floats) broadcasting to ``shape``. Scalars share
    one small array (one allocation: a call with scalar inputs costs microseconds, not tens
    of them).

    ``lazy=True`` (for :func:`fused_batch`'s parallel loop): an input that would be copied
    (broadcast, or not C-contiguous) is given as its own values with step
    :data:`BROADCAST` instead, and a third item is returned, the ``layout`` of those
    inputs (:func:`_layout`; None where there is none): no copy is made here
    (:func:`materialize` makes them, where needed)."""
    n = math.prod(shape)
    arrays = list(values)
    steps = np.zeros(len(values), dtype=np.int64)
    scalar_at = []
    done: dict = {}  # id -> (flat, step): one array given twice (h0 and h0_j) flattened once
    spread: dict = {}  # q -> strides over shape of the inputs read in place (lazy)
    for q, v in enumerate(values):
        if type(v) is float or v.ndim == 0:
            scalar_at.append(q)
        elif id(v) in done:
            arrays[q], steps[q] = done[id(v)][:2]
            if steps[q] == BROADCAST:
                spread[q] = done[id(v)][2]
        elif lazy and (own := _own_values(v, shape, n)) is not None:
            arrays[q], spread[q] = own
            steps[q] = BROADCAST
            done[id(v)] = (arrays[q], BROADCAST, spread[q])
        else:
            arrays[q], steps[q] = done[id(v)] = _flat_input(v, shape, n)
    if scalar_at:
        # Each scalar is a row of one (k, 1) array: a C-contiguous 1-D array of length 1.
        # (Equal lengths by construction; strict=True would cost a microsecond more, as the
        # array's iterator ends by an IndexError.)
        packed = np.array([float(values[q]) for q in scalar_at]).reshape(-1, 1)
        for q, row in zip(scalar_at, packed, strict=False):
            arrays[q] = row
    if not lazy:
        return tuple(arrays), steps
    if not spread:
        return tuple(arrays), steps, None
    return tuple(arrays), steps, _layout(shape, spread)


def fused_batch(ins, steps, n, tier, *, body, particle_slip, details=False, check=False,
                into=(None, None), layout=None, shape=None):
    """Run the fused preparation and the ``tier`` kernel (:data:`TIER_PAPER` or
    :data:`TIER_RELATIVE`) on ``n`` collisions.

    Returns ``(e_w, stage, path, w, det)``; ``det`` has shape ``(n, N_DETAILS)`` with
    ``details``, else ``(n, 0)``. With ``check`` the lab speeds are validated in the same
    pass, by the rules of :func:`check_speeds` (``u0_j`` NaN meaning None), and a sixth
    item ``(code, index)`` is returned as there; collisions that break rule 3 or 4 are not
    computed (their outputs are NaN, stage -1), so a caller must raise on a nonzero code.
    ``into``: ``(e_w, stage)``, 1-D arrays of ``n`` (float64, int8) to write those outputs
    into (e.g. a map's result), or None for new ones. ``layout``, ``shape``: the inputs'
    layout (:func:`flat_inputs` with ``lazy=True``) and their broadcast shape: the parallel
    loop reads the :data:`BROADCAST` inputs in place.
    """
    if layout is not None and n < SERIAL_BELOW:
        ins, steps = materialize(ins, steps, layout, shape)
        layout = None
    e_w, stage = into
    # FusedOutputs and FusedFlags, as plain tuples (the entry points make them records)
    out = (np.empty(n) if e_w is None else e_w,
           np.empty(n, dtype=np.int8) if stage is None else stage,
           np.empty(n, dtype=np.int8), np.empty(n), np.empty((n, N_DETAILS if details else 0)))
    args = (ins, steps, (bool(body), slip_flag(particle_slip), bool(check)), out)
    if n < SERIAL_BELOW:
        first = _FUSED_ENTRY[int(tier), False](*args)
    elif layout is not None:
        first = parallel_launch(_FUSED_BROADCAST[int(tier)], ins, steps, layout[:2], *args[2:],
                                *launch_blocks(n))
    else:
        first = parallel_launch(_FUSED_ENTRY[int(tier), True], *args, *launch_blocks(n))
    if not check:
        return out
    return (*out, _first_rule(first, n))


def prepare_flat(ins, steps, n, body, particle_slip):
    """The kernel arrays of ``n`` collisions, compiled: a ``(14, n)`` float64 array whose
    rows are ``m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w, fn_i, fn_j, e, w_per_u0``
    (the reference: :func:`agglomtool.pair.prepare_pair`)."""
    return _prepare_columns(ins, steps, _EVERY, n, body, particle_slip)
