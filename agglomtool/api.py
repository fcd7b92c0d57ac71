"""The public collision API: :func:`collide` and :func:`critical_impact_speed`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit, prange

from ._fields import DEFAULT_MODE
from ._jit import CACHE, parallel_launch
from ._validate import as_float_array, check_field, check_range
from .collision.auto import DEFAULT_TOL, auto_fused
from .collision.critical import critical_speeds, first_rebound_speed
from .collision.fused import (
    INPUT_NAMES,
    SERIAL_BELOW,
    TIER_PAPER,
    TIER_RELATIVE,
    check_speeds,
    flat_inputs,
    fused_batch,
    materialize,
    prepare_flat,
)
from .collision.outcome import (
    DETAIL_NAMES,
    NO_BRIDGE_DESCRIPTION,
    STAGE_DESCRIPTIONS,
    Path,
    Stage,
    path_names,
    stage_names,
)
from .collision.tiers import TAKES_TOL, evaluate, mode_names
from .inputs import Bed, Gas, Liquid, Particle
from .pair import (
    DRAG_SLIP_MODES,
    PairState,
    broadcast_shape,
    check_inputs,
    flatten,
    prepare_pair,
)

__all__ = ["CollisionResult", "collide", "critical_impact_speed", "MODES"]

#: Model tiers available through ``mode=`` (see :mod:`agglomtool.collision.tiers`).
MODES = mode_names()

_DEFAULT_BED = Bed()  # frozen: one instance serves every call without a bed

#: Tiers whose preparation is fused into their compiled loop (:mod:`.collision.fused`).
_FUSED = {"paper": TIER_PAPER, "relative": TIER_RELATIVE}


@dataclass(frozen=True)
class CollisionResult:
    """What one (array of) collision(s) came to.

    Attributes
    ----------
    e_w : numpy.ndarray
        Wet restitution coefficient [-] (Eq. 31, non-negative); 0 where the pair sticks.
    agglomerated : numpy.ndarray of bool
        True where the pair sticks (exactly where ``e_w == 0``).
    stage : numpy.ndarray of int8
        :class:`~agglomtool.collision.outcome.Stage` code: where the outcome was decided.
    path : numpy.ndarray of int8
        :class:`~agglomtool.collision.outcome.Path` bit flags: special-case paths taken.
    w : numpy.ndarray
        Relative normal impact speed ``u_i - u_j`` [m/s].
    details : dict of numpy.ndarray
        Intermediate energies [J], losses [J], gaps [m] and numbers by stage (names in
        :data:`~agglomtool.collision.outcome.DETAIL_NAMES`); NaN marks a quantity of a stage
        the collision never reached. Empty when ``details=False`` was asked.
    mode : str
        The model tier that produced the result.
    """

    e_w: np.ndarray
    agglomerated: np.ndarray
    stage: np.ndarray
    path: np.ndarray
    w: np.ndarray
    details: dict = field(default_factory=dict)
    mode: str = DEFAULT_MODE

    @property
    def stage_name(self) -> np.ndarray:
        """Stage names as strings (e.g. ``"rebound"``, ``"approach_viscous"``)."""
        return stage_names(self.stage)

    def explain(self, index=None) -> str:
        """A short readable account of one collision (``index`` into the result arrays;
        may be omitted when the result holds one collision)."""
        if index is None:
            if np.size(self.e_w) != 1:
                raise ValueError(
                    f"index is required: this result holds {np.size(self.e_w)} collisions"
                )
            index = (0,) * np.ndim(self.e_w)
        st = Stage(int(np.asarray(self.stage)[index]))
        path = int(np.asarray(self.path)[index])
        flags = path_names(path)
        ew = float(np.asarray(self.e_w)[index])
        if path & Path.NO_BRIDGE:  # the stage code says how it ended; no bridge ruptured
            decided = (f"no bridge (stage {st.name.lower()}): {NO_BRIDGE_DESCRIPTION} "
                       + ("A dry collision: the pair rebounds with e_w = e." if ew > 0.0 else
                          "A dry collision with e = 0: the pair stays together."))
        else:
            decided = f"{st.name.lower()}: {STAGE_DESCRIPTIONS[st]}"
        lines = [
            f"outcome: {'agglomerate' if ew == 0.0 else 'rebound'} (e_w = {ew:.6g})",
            f"decided at: {decided}",
            f"special paths: {', '.join(flags) if flags else 'none'}",
        ]
        for name in DETAIL_NAMES:
            if name in self.details:
                val = float(np.asarray(self.details[name])[index]) + 0.0  # no "-0"
                if np.isnan(val):
                    continue
                if name.endswith("_frac") and val > 1.0:
                    # a bound on a term's work over K_ini: above 1 it bounds nothing (it is
                    # taken at the impact speed over the whole gap, ~1/St_app times K_ini
                    # where viscosity stops the pair first); it only says "not negligible"
                    lines.append(f"  {name:14s} > 1: not negligible (its work bound, taken "
                                 f"at the impact speed, is {val:.3g} times K_ini)")
                    continue
                unit = _detail_unit(name)
                lines.append(f"  {name:14s} = {val:.6g}{' ' + unit if unit else ''}")
        return "\n".join(lines)

    def __repr__(self) -> str:
        """Shape, outcome counts and the range of ``e_w`` (not every array)."""
        e_w = np.asarray(self.e_w)
        n = e_w.size
        stuck = int(np.count_nonzero(self.agglomerated))
        rebound = e_w[e_w > 0.0]
        rng = (f", e_w of rebounds {rebound.min():.4g}-{rebound.max():.4g}" if rebound.size
               else "")
        details = f", details: {len(self.details)} quantities" if self.details else ""
        return (f"CollisionResult(mode={self.mode!r}, shape={e_w.shape}, {n} collision"
                f"{'s' if n != 1 else ''}: {stuck} agglomerate, {n - stuck} rebound{rng}"
                f"{details})")


def _detail_unit(name: str) -> str:
    """Unit of a detail quantity: energies and losses [J], gaps [m], speeds [m/s]."""
    if name.startswith(("K_", "L_")):
        return "J"
    if name.startswith(("D_", "h_")):
        return "m"
    if name.startswith("w_"):
        return "m/s"
    return ""  # Ca, St_app and the work fractions are dimensionless


def _check_mode(mode: str) -> None:
    if mode not in MODES:
        raise ValueError(f"mode = {mode!r} is not one of {mode_names()}")


def _lab_speeds(p_i: Particle, p_j: Particle, u0, u0_j):
    """Lab-frame normal speeds of i towards j and of j towards i [m/s]; a plate's is 0."""
    u0 = as_float_array("u0", u0)
    plate_i = np.isinf(p_i.d)
    plate_j = np.isinf(p_j.d)
    if u0_j is None:
        u_i = np.where(plate_i, 0.0, u0)
        u_j = np.where(plate_j, 0.0, u0)
    else:
        u0_j = as_float_array("u0_j", u0_j)
        if np.any(plate_j & (u0_j != 0.0)):
            raise ValueError("u0_j must be 0 (or None) when p_j is a plate: a plate is fixed")
        if np.any(plate_i & (u0 != 0.0)):
            raise ValueError(
                "u0 must be 0 when p_i is a plate and u0_j is given: a plate is fixed"
            )
        u_i, u_j = u0, u0_j
    w = u_i + u_j
    if np.any(~(w > 0.0)):
        bad = float(np.broadcast_to(w, np.shape(w))[~(w > 0.0)].flat[0])
        k = np.flatnonzero(~(np.broadcast_to(w, np.shape(w)) > 0.0).reshape(-1))[0]
        pick = [float(np.broadcast_to(x, np.shape(w)).reshape(-1)[k]) for x in (u0, u_j)]
        raise ValueError(
            f"the particles are not approaching: u0 + u0_j = {bad!r} m/s is outside the "
            f"allowed range (0, inf) (u0 = {pick[0]!r}, u0_j = {pick[1]!r}); e_w is defined "
            "for approaching pairs only"
        )
    if np.any(np.isinf(w)):
        raise ValueError(
            "u0 = inf (or u0_j = inf) is outside the allowed range: finite speeds [m/s]"
        )
    return u_i, u_j, w


def _evaluate(state: PairState, w, mode: str, details: bool, tol=None):
    """Run the kernel of ``mode`` on ``state`` broadcast with ``w``; arrays of one shape."""
    shape = np.broadcast_shapes(state.shape, np.shape(w))
    flat = flatten(state, shape)
    w_flat = np.ascontiguousarray(np.broadcast_to(w, shape), dtype=np.float64).reshape(-1)
    e_w, stage, path, det = evaluate(
        mode, flat.m_i, flat.m_j, flat.r, flat.H0, flat.Ha, flat.mu_l, flat.gamma, flat.cos_t,
        flat.theta, w_flat, flat.fn_i, flat.fn_j, flat.e, details=details, tol=tol,
    )
    return _shaped(e_w, stage, path, det, shape, details)


def _shaped(e_w, stage, path, det, shape, details):
    out_details = {}
    if details:
        out_details = {name: det[:, k].reshape(shape) for k, name in enumerate(DETAIL_NAMES)}
    return e_w.reshape(shape), stage.reshape(shape), path.reshape(shape), out_details, shape


#: The results :func:`collide` writes into ``out=``, with their dtypes.
_OUT_DTYPES = {"e_w": np.dtype(np.float64), "stage": np.dtype(np.int8),
               "agglomerated": np.dtype(np.bool_)}


def _check_out(out, shape) -> dict:
    """``out`` of :func:`collide` checked: a ``ValueError`` naming the key, what it got and
    what is allowed."""
    if out is None:
        return {}
    if not isinstance(out, dict):
        raise ValueError(f"out = a {type(out).__name__} is not allowed: a dict of arrays "
                         f"keyed {list(_OUT_DTYPES)}")
    for key, a in out.items():
        if key not in _OUT_DTYPES:
            raise ValueError(f"out[{key!r}] is not allowed: out takes {list(_OUT_DTYPES)}")
        if not (isinstance(a, np.ndarray) and a.dtype == _OUT_DTYPES[key]
                and a.shape == tuple(shape) and a.flags.c_contiguous and a.flags.writeable):
            got = (f"{a.dtype} {a.shape}" if isinstance(a, np.ndarray) else type(a).__name__)
            raise ValueError(f"out[{key!r}] = {got} is not allowed: a writable C-contiguous "
                             f"{_OUT_DTYPES[key]} array of the inputs' broadcast shape "
                             f"{tuple(shape)}")
    return out


def _flat(a):
    """A C-contiguous array as 1-D (a view), or None."""
    return None if a is None else a.reshape(-1)


def _check_tol_mode(tol, mode) -> None:
    if tol is not None:
        check_range("tol", tol, 1e-6, 0.5, unit="-")  # (auto's own range)
    if tol is not None and mode not in TAKES_TOL:
        raise ValueError(
            f"tol = {tol!r} was given but mode = {mode!r} takes no tolerance; "
            f"only {sorted(TAKES_TOL)} do"
        )


def _check_flags(body_forces, drag_slip, details) -> None:
    for name, val in (("body_forces", body_forces), ("details", details)):
        if not isinstance(val, (bool, np.bool_)):
            raise ValueError(f"{name} = {val!r} is not allowed: True or False")
    if drag_slip not in DRAG_SLIP_MODES:
        raise ValueError(f"drag_slip = {drag_slip!r} is not one of {DRAG_SLIP_MODES}")


def _speed_error(code, index, ins, steps, shape=()):
    """The ``ValueError`` of :func:`_lab_speeds` for the rule ``code`` failing at the flat
    ``index`` of the broadcast ``shape`` (named in the message when there is more than one
    collision)."""
    at = ""
    if int(np.prod(shape)) > 1:
        at = f" at index {tuple(int(i) for i in np.unravel_index(index, shape))}"
    if code == 1:
        return ValueError(f"u0_j must be 0 (or None) when p_j is a plate{at}: a plate is fixed")
    if code == 2:
        return ValueError(
            f"u0 must be 0 when p_i is a plate and u0_j is given{at}: a plate is fixed")

    def val(name):
        q = INPUT_NAMES.index(name)
        return float(ins[q][index * steps[q]])

    u_i = 0.0 if np.isinf(val("p_i.d")) else val("u0")
    u0_j = val("u0_j")
    u_j = (0.0 if np.isinf(val("p_j.d")) else val("u0")) if np.isnan(u0_j) else u0_j
    if code == 3:
        return ValueError(
            f"the particles are not approaching: u0 + u0_j = {u_i + u_j!r} m/s{at} is outside "
            f"the allowed range (0, inf) (u0 = {val('u0')!r}, u0_j = {u_j!r}); e_w is defined "
            "for approaching pairs only"
        )
    return ValueError(
        f"u0 = inf (or u0_j = inf){at} is outside the allowed range: finite speeds [m/s]")


def _fused_inputs(p_i, p_j, liquid, gas, bed, beta_deg, e, u0, u0_j, speeds=True,
                  check=True, lazy=False):
    """Validated raw inputs in the order of :data:`INPUT_NAMES`, their broadcast shape, the
    flat arrays and steps of the fused kernels. ``speeds=False``: ``u0`` and ``u0_j`` are
    ignored (zero speed, no speed checks). ``check=False``: the lab-speed rules are left to
    the caller (``fused_batch(check=True)`` applies them in its own pass). ``lazy=True``
    (with ``check=False``): broadcast inputs are not copied (:func:`.collision.fused.
    flat_inputs`), and a fifth item is returned, their layout (for ``fused_batch``)."""
    if speeds:
        u0 = check_field("u0", u0, key="collide.u0")
        u0_j = np.nan if u0_j is None else check_field("u0_j", u0_j, key="collide.u0_j")
    else:
        u0, u0_j = 0.0, np.nan
    values = (
        p_i.d, p_i.rho, p_i.h0, p_i.ha, p_j.d, p_j.rho, p_j.h0, p_j.ha, liquid.mu,
        liquid.gamma, liquid.rho, liquid.theta_deg, gas.mu, gas.rho, bed.eps,
        np.nan if bed.U is None else bed.U,
        check_field("beta_deg", beta_deg, key="collide.beta_deg"),
        check_field("e", e, key="collide.e"), u0, u0_j,
    )
    shape = broadcast_shape(INPUT_NAMES, values)
    if lazy:
        ins, steps, layout = flat_inputs(values, shape, lazy=True)
        return shape, ins, steps, math.prod(shape), layout
    ins, steps = flat_inputs(values, shape)
    n = 1
    for s in shape:
        n *= s
    if not speeds or not check:
        return shape, ins, steps, n
    code, index = check_speeds(
        ins[0], ins[4], ins[18], ins[19][:0] if u0_j is np.nan else ins[19], n
    )
    if code:
        raise _speed_error(code, index, ins, steps, shape)
    return shape, ins, steps, n


def collide(
    p_i: Particle,
    p_j: Particle,
    *,
    liquid: Liquid,
    gas: Gas,
    bed: Bed | None = None,
    u0,
    u0_j=None,
    beta_deg=0.0,
    e=0.9,
    mode: str = DEFAULT_MODE,
    body_forces: bool = True,
    drag_slip: str = "emulsion",
    details: bool = True,
    tol: float | None = None,
    out: dict | None = None,
) -> CollisionResult:
    """Outcome of a binary collision between two wet particles (or a particle and a plate).

    Parameters
    ----------
    p_i, p_j : Particle
        The target particle (at the origin) and its neighbour. Either may be a plate.
    liquid : Liquid
        The coating liquid (the bridge).
    gas : Gas
        The fluidizing gas at bed conditions.
    bed : Bed, optional
        Local voidage and emulsion gas velocity; default ``Bed(eps=0.55, U=None)``.
    u0 : float or array
        Lab-frame speed of i towards j [m/s]. With a plate as p_i and ``u0_j=None``, the
        speed of p_j towards the plate.
    u0_j : float or array, optional
        Lab-frame speed of j towards i [m/s]; ``None`` = ``u0`` (head-on, the paper's
        convention), or 0 for a plate. ``u0 + u0_j`` must be > 0.
    beta_deg : float or array
        Collision angle [deg] of the axis i -> j from the horizontal towards +Z (Fig. 5).
    e : float or array
        Dry restitution coefficient [-], in [0, 1].
    mode : str
        Model tier; ``"paper"``: the published model (docs/model.md, "The tiers").
    body_forces : bool
        False switches weight, buoyancy and drag off (the paper's earlier identical-particle
        model, its ref. 31, for identical particles).
    drag_slip : {"emulsion", "particle"}
        Slip velocity of the drag law: ``U_e / eps`` (the paper's) or ``U_e / eps - u0``.
    details : bool
        Return the intermediate energies in ``result.details``.
    tol : float, optional
        Tolerance in ``e_w`` [-] of ``mode="auto"`` (default 0.01); other modes refuse it.
    out : dict, optional
        Arrays to write results into, keyed ``"e_w"`` (float64), ``"stage"`` (int8) and
        ``"agglomerated"`` (bool), each C-contiguous with the inputs' broadcast shape (any
        of the three may be left out): e.g. the blocks of a map's result, written once with
        no array in between (modes ``"paper"`` and ``"relative"`` write ``e_w`` and
        ``stage`` from the compiled loop itself). The result's fields are these arrays.

    Returns
    -------
    CollisionResult

    Notes
    -----
    Shabanian et al. (2024), Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397.
    All inputs broadcast together; results have the broadcast shape.
    """
    _check_mode(mode)
    bed = _DEFAULT_BED if bed is None else bed
    check_inputs(p_i, p_j, liquid, gas, bed)
    _check_flags(body_forces, drag_slip, details)
    _check_tol_mode(tol, mode)
    in_kernel = mode in _FUSED or (mode == "auto" and not details)  # checks speeds itself
    layout = None
    if mode in _FUSED:  # broadcast inputs read in place by the parallel loop, not copied
        shape, ins, steps, n, layout = _fused_inputs(p_i, p_j, liquid, gas, bed, beta_deg, e,
                                                     u0, u0_j, check=False, lazy=True)
    else:
        shape, ins, steps, n = _fused_inputs(p_i, p_j, liquid, gas, bed, beta_deg, e, u0,
                                             u0_j, check=not in_kernel)
    into = _check_out(out, shape)
    particle = drag_slip == "particle"
    if mode in _FUSED:
        # The speed rules are checked in the kernel's own pass (no separate scan).
        e_w, stage, path, w, det, (code, index) = fused_batch(
            ins, steps, n, _FUSED[mode], body=body_forces, particle_slip=particle,
            details=details, check=True,
            into=(_flat(into.get("e_w")), _flat(into.get("stage"))), layout=layout,
            shape=shape)
        if code:
            full_ins, full_steps = materialize(ins, steps, layout, shape)
            raise _speed_error(code, index, full_ins, full_steps, shape)
    elif mode == "auto" and not details:
        e_w, stage, path, w, (code, index) = auto_fused(
            ins, steps, n, body=body_forces, particle_slip=particle,
            tol=DEFAULT_TOL if tol is None else tol, check=True)
        if code:
            raise _speed_error(code, index, ins, steps, shape)
        det = None
    else:
        k = prepare_flat(ins, steps, n, body_forces, particle)
        w = k[9].copy()
        e_w, stage, path, det = evaluate(mode, *k[:13], details=details, tol=tol)
    e_w, stage, path, det, shape = _shaped(e_w, stage, path, det, shape, details)
    for name, value in (("e_w", e_w), ("stage", stage)):
        target = into.get(name)
        if target is not None and not np.may_share_memory(target, value):
            np.copyto(target, value)  # a tier that made its own array
    if into:
        e_w, stage = into.get("e_w", e_w), into.get("stage", stage)
    return CollisionResult(
        e_w=e_w,
        agglomerated=_agglomerated(e_w, into.get("agglomerated")),
        stage=stage,
        path=path,
        w=w.reshape(shape),
        details=det,
        mode=mode,
    )


@njit(parallel=True, cache=CACHE)
def _agglomerated_pass(e_w, out):  # pragma: no cover - compiled
    """``out = (e_w == 0)`` of 1-D arrays on every thread (each a contiguous share: a loop
    the compiler vectorizes, as fast as numpy's on one thread)."""
    for i in prange(e_w.shape[0]):
        out[i] = e_w[i] == 0.0


def _agglomerated(e_w, out=None):
    """``np.equal(e_w, 0.0, out=out)``: where the pair sticks (``out``: a C-contiguous
    bool array of ``e_w``'s shape, or None); many collisions (a map's block) in one
    compiled pass on every thread, the same comparison per element."""
    if (e_w.size < SERIAL_BELOW or not e_w.flags.c_contiguous
            or (out is not None and not out.flags.c_contiguous)):
        return np.equal(e_w, 0.0, out=out)
    if out is None:
        out = np.empty(e_w.shape, dtype=np.bool_)
    parallel_launch(_agglomerated_pass, e_w.reshape(-1), out.reshape(-1))
    return out


def critical_impact_speed(
    p_i: Particle,
    p_j: Particle,
    *,
    liquid: Liquid,
    gas: Gas,
    bed: Bed | None = None,
    beta_deg=0.0,
    e=0.9,
    mode: str = DEFAULT_MODE,
    body_forces: bool = True,
    drag_slip: str = "emulsion",
    rtol: float = 1e-6,
    tol: float | None = None,
    u_max: float | None = None,
) -> np.ndarray:
    """Critical impact speed ``u0*`` [m/s]: the smallest head-on ``u0`` at which the pair
    rebounds (the paper's Section 3.1 definition).

    Head-on means both particles move towards each other at ``u0`` in the lab frame (the
    relative speed is ``2 u0``); with a plate, the particle moves at ``u0``.

    Parameters
    ----------
    p_i, p_j : Particle
        The target particle and its neighbour, as in :func:`collide`. Either may be a plate.
    liquid : Liquid
        The coating liquid (the bridge).
    gas : Gas
        The fluidizing gas at bed conditions.
    bed : Bed, optional
        Local voidage [-] and emulsion gas velocity [m/s]; default ``Bed(eps=0.55, U=None)``.
    beta_deg : float or array
        Collision angle [deg] of the axis i -> j from the horizontal towards +Z.
    e : float or array
        Dry restitution coefficient [-], in [0, 1].
    mode : str
        Model tier, as in :func:`collide` (default ``"relative"``).
    body_forces : bool
        False switches weight, buoyancy and drag off.
    drag_slip : {"emulsion", "particle"}
        Slip velocity of the drag law, as in :func:`collide`.
    rtol : float
        Relative tolerance [-] of the answer: it lies within ``rtol`` above a switch from
        sticking to rebounding.
    tol : float, optional
        Tolerance in ``e_w`` [-] of ``mode="auto"``, as in :func:`collide`.
    u_max : float, optional
        A ceiling on the answer [m/s]. Where ``u0*`` exceeds it the result is ``inf``,
        exactly as if the full answer had been cut there; the search stops as soon as
        every speed up to ``u_max`` is known to stick, so pairs that rebound only at high
        speed (or never) cost a few evaluations.

    Returns
    -------
    numpy.ndarray
        ``u0*`` with the broadcast shape of the inputs. ``inf`` where the pair sticks at every
        speed (``e = 0``, or zero total asperity height, whose lubrication loss is infinite);
        0 where no bridge forms (coatings no thicker than the asperities) and ``e > 0``.

    Notes
    -----
    In mode ``"relative"`` u0* comes from the tier's near-closed form (the stages' energy
    balances are quadratics in the speed; only the rupture distance's dependence on ``Ca``
    is iterated; the model page of the documentation derives it), in mode ``"paper"``
    without body forces from the same value (the tiers then agree); each answer ``u`` is
    checked with the tier's kernel (it rebounds at ``u`` and sticks at ``u (1 - rtol)``),
    and where the check fails (and in mode ``"paper"`` with body forces) the search below
    runs instead. Everywhere the answer is within ``rtol`` above a switch from
    sticking to rebounding.

    The search (the other modes, and the fallback): near the threshold ``e_w(u0)`` need not
    be monotonic (the paper's Fig. 6b: one particle stops first, body forces matter). The
    search therefore starts below the smallest speed that can possibly rebound (the viscous
    bound of the approach, ``m_r w = c Delta_app``), doubles the speed until a rebound,
    scans the last doubling on 16 geometric points, and bisects between the last sticking
    and the first rebounding point to ``rtol`` (compiled and run per collision in modes
    ``"paper"`` and ``"relative"``, stepped over the whole batch in the other modes; either
    way each collision converges on its own, so its ``u0*`` does not depend on the rest of
    the batch). The result is the first rebound found this way: a rebound window
    narrower than a factor ``2^(1/16)`` (4.4 %) below it can be missed. Above ``u0*`` the
    pair may stick again in a narrow window; :func:`collide` on a grid shows it.
    """
    _check_mode(mode)
    if np.ndim(check_range("rtol", rtol, 0.0, 0.1, lo_open=True, hi_open=True)):
        raise ValueError(f"rtol = {rtol!r} must be one number in (0, 0.1)")
    rtol = float(rtol)
    if u_max is None:
        ceiling = math.inf
    else:
        ceiling = float(check_field("u_max", u_max, key="u_ceiling", scalar=True))
    bed = Bed() if bed is None else bed
    check_inputs(p_i, p_j, liquid, gas, bed)
    _check_flags(body_forces, drag_slip, False)
    _check_tol_mode(tol, mode)
    if mode in _FUSED:
        shape, ins, steps, n = _fused_inputs(p_i, p_j, liquid, gas, bed, beta_deg, e, None,
                                             None, speeds=False)
        u_star = critical_speeds(ins, steps, n, _FUSED[mode], body=body_forces,
                                 particle_slip=drag_slip == "particle", rtol=rtol,
                                 u_max=ceiling)
        return u_star.reshape(shape)[()]
    return _critical_vectorised(p_i, p_j, liquid, gas, bed, beta_deg, e, mode, body_forces,
                                drag_slip, rtol, tol, ceiling)


def _critical_vectorised(p_i, p_j, liquid, gas, bed, beta_deg, e, mode, body_forces,
                         drag_slip, rtol, tol, ceiling):
    """u0* by :func:`~.collision.critical.first_rebound_speed` over the numpy preparation,
    every step on the elements still searching, each to its own convergence: the tiers
    without a compiled solver, and the reference the compiled solver is tested against."""
    state = prepare_pair(p_i, p_j, liquid, gas, bed, beta_deg, e, body_forces, drag_slip)
    shape = state.shape
    flat = flatten(state)
    depends_on_speed = body_forces and drag_slip == "particle"

    def sticks(w_rel, idx):
        """True where the pair sticks at relative speed ``w_rel`` (flat elements ``idx``)."""
        sub = _subset(flat, idx)
        if depends_on_speed:
            u = w_rel / sub.w_per_u0
            u_i = np.where(np.isinf(sub.m_i), 0.0, u)
            u_j = np.where(np.isinf(sub.m_j), 0.0, u)
            full = prepare_pair(
                _take(p_i, idx, shape), _take(p_j, idx, shape), _take(liquid, idx, shape),
                _take(gas, idx, shape), _take(bed, idx, shape), _take_arr(beta_deg, idx, shape),
                sub.e, True, drag_slip, u_i=u_i, u_j=u_j,
            )
            sub.fn_i = np.broadcast_to(full.fn_i, sub.shape)
            sub.fn_j = np.broadcast_to(full.fn_j, sub.shape)
        e_w, _, _, _, _ = _evaluate(sub, w_rel, mode, False, tol)
        return e_w == 0.0

    w_per_u0 = np.broadcast_to(state.w_per_u0, shape)
    w_star = first_rebound_speed(flat, sticks, rtol, w_max=ceiling * w_per_u0.ravel())
    u_star = w_star.reshape(shape) / w_per_u0
    return np.where(u_star > ceiling, math.inf, u_star)[()]


def _subset(flat: PairState, idx) -> PairState:
    """The elements ``idx`` of a flattened ``PairState``."""
    vals = {name: val[idx] for name, val in flat.__dict__.items() if name != "shape"}
    return PairState((len(idx),), **vals)


def _take_arr(value, idx, shape):
    return np.broadcast_to(np.asarray(value, dtype=float), shape).ravel()[idx]


def _take(obj, idx, shape):
    """A copy of an input dataclass holding only the flat elements ``idx``."""
    kwargs = {}
    for name, val in obj.__dict__.items():
        if isinstance(val, np.ndarray):
            kwargs[name] = _take_arr(val, idx, shape)
        else:
            kwargs[name] = val
    return type(obj)(**kwargs)

