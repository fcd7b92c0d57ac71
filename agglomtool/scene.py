"""A scene: one operating point of a fluidized bed, and everything derived from it.

A :class:`Scene` holds what a person knows about the bed (temperature, pressure, gas, how
hard it is fluidized, the two bed materials and their sizes, the coating, the collision
angle and the impact speed, a value or a distribution). Every property the collision core
needs (gas and liquid properties, densities, asperity heights, ``U_mf``, the emulsion gas
velocity) is derived from it through :mod:`agglomtool.properties` and
:mod:`agglomtool.materials`: nothing is typed twice. This module is the only place where
the property layer meets the collision core.

:func:`evaluate` turns a mapping of field values (scalars, or numpy arrays that broadcast
together, typically with singleton axes as a grid block has them) into the derived arrays.
Properties are evaluated on the unique values of their inputs and broadcast back.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numba import njit, prange, vectorize

from . import materials
from ._fields import (
    CATEGORICAL_FIELDS,
    DEFAULTS,
    FIELD_META,
    FIELD_RANGES,
    NUMERIC_FIELDS,
    SPEED_LAW_NEEDS,
    U_CEILING,
    short_unit,
)
from ._jit import CACHE, parallel_launch
from ._validate import check_range, check_typed, suggestion, unknown_name
from .api import _FUSED, MODES, _fused_inputs, collide, critical_impact_speed
from .bed.hydrodynamics import MAP_PASS_MIN
from .bed.speed_models import IMPACT_SPEED_MODELS, mixed_law, speed_law
from .bed.speeds import _LN2, SPEED_FAMILIES, SpeedModel, sticking_probability
from .inputs import Bed, Liquid, Particle
from .pair import DRAG_SLIP_MODES, wet_mass
from .plausibility import PlausibilityWarning, scene_findings, warn_findings
from .properties import gas_properties, umf, umf_methods
from .properties.fluidization import umf_coated
from .units import to_si

__all__ = ["Scene", "evaluate", "provenance", "assumed_inputs", "impact_speed_methods",
           "CATEGORICAL_FIELDS", "NUMERIC_FIELDS", "CA_VISCOUS", "U_CEILING", "U_STAR_FLAGS"]

#: Capillary number at ``u0*`` above which the outcome is called viscous-limited.
CA_VISCOUS = 1.0

#: Values of the ``u_star_flag`` output and their meanings.
U_STAR_FLAGS = {
    0: ("rebounds_above_u_star", "the pair sticks below u0* and rebounds at u0*"),
    1: ("no_bridge", "the coating is no thicker than the asperities: no bridge, never sticks "
                     "(u0* = 0)"),
    2: ("sticks_up_to_ceiling", "the pair sticks at every speed up to the ceiling u_ceiling "
                                "(u0* reported as inf)"),
}


@dataclass(frozen=True)
class Scene:
    """One operating point of a bubbling fluidized bed with coated particles.

    Parameters
    ----------
    T : float
        Bed temperature [K].
    P : float
        Absolute pressure [Pa].
    gas : str
        Fluidizing gas, a name of the materials database (``materials.names("gas")``).
    U : float, optional
        Superficial gas velocity [m/s]. ``None`` takes ``U_Umf * U_mf``.
    U_Umf : float
        Fluidization number ``U / U_mf`` [-], used when ``U`` is ``None``.
    eps : float
        Local voidage around the pair [-] (the paper's 0.55, emulsion phase).
    U_e_Umf : float
        Emulsion gas velocity over ``U_mf`` [-] for the drag (the paper's 1.1).
    solid_i, solid_j : str
        Bed solids of particles i and j (database names); ``solid_j=None`` = ``solid_i``.
    d_i, d_j : float
        Solid diameters [m]; ``d_j=None`` = ``d_i``.
    liquid : str
        Coating liquid or melt (database name); its properties follow ``T`` (and ``P``).
    h0, h0_j : float
        Coating thicknesses of i and j [m]; ``h0_j=None`` = ``h0``.
    ha_i, ha_j : float, optional
        Asperity heights [m]; ``None`` = the solid's database value.
    e : float, optional
        Dry restitution coefficient [-]; ``None`` = the mean of the two solids' values.
    theta_deg : float, optional
        Contact angle [deg]; ``None`` = the liquid's database value.
    beta_deg : float
        Collision angle [deg] of the axis i -> j from the horizontal (the paper's Fig. 5).
    u0 : float, optional
        Impact speed [m/s], head-on in the lab frame (relative speed ``2 u0``): the value
        for ``speed="fixed"``, the median for ``speed="lognormal"``.
    speed : str, optional
        Impact-speed distribution (``"fixed"``, ``"lognormal"``, ``"maxwellian"``: see
        :mod:`agglomtool.bed.speeds`) or model (``"excess-gas"``, ``"bubble-darton"``,
        ``"bubble-mori-wen"``, ``"collisional-balance"``: see
        :mod:`agglomtool.bed.speed_models` and :func:`impact_speed_methods`). ``None`` picks
        ``"fixed"`` when ``u0`` is given, ``"maxwellian"`` when ``granular_temperature``
        is, and otherwise the default estimate ``"excess-gas"``. A model named here is
        given: ``uncertain="assumed"`` draws the model only where ``speed`` is ``None``.
    sigma_ln : float
        Shape (standard deviation of ``ln u0``) of the lognormal [-].
    granular_temperature : float, optional
        Granular temperature [m2/s2] of the Maxwellian.
    fluctuation_ratio : float
        For ``"excess-gas"``: r.m.s. particle velocity per component over ``U - U_mf`` [-].
    bed_height : float
        Static (settled) bed height [m] (the bubble models; default 0.3 m).
    column_diameter : float
        Column diameter [m] (the bubble models: slugging, wall effect, Mori and Wen's
        maximum bubble; default 0.3 m).
    orifice_area : float
        Distributor area per orifice [m2], the column's cross-section over the number of
        orifices; 0 (the default) for a porous plate.
    height : float, optional
        Height above the distributor where the collisions are evaluated [m], in
        ``(0, bed_height]``; ``None`` takes half the bed height.
    wake_fraction : float
        Bubble wake volume over bubble volume [-] for the bubble models (default 0.25: an
        assumed value, see the speed models' docs page).
    mode : str
        Model tier (``agglomtool.MODES``).
    body_forces : bool
        Weight, buoyancy and drag on (the paper's generalized model) or off.
    drag_slip : {"emulsion", "particle"}
        Slip velocity of the drag law (see :func:`agglomtool.collide`).
    umf_method : str
        Minimum fluidization correlation (:func:`agglomtool.properties.umf_methods`).
    u_ceiling : float
        Ceiling on the critical impact speed [m/s] (default :data:`U_CEILING`, 10 m/s):
        where ``u0*`` exceeds it the pair sticks at every speed a bed can give it, and
        ``u0*`` is reported as ``inf`` (flag ``u_star_flag = 2``) rather than as a number
        from physics extrapolated far beyond any bed.

    Notes
    -----
    ``U_mf`` is the larger of the two particles' values, each with the wet diameter and
    the wet particle's mean density, as the paper's Section 3.1 does (Shabanian et al.
    2024, Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397).
    """

    T: float = DEFAULTS["T"]
    P: float = DEFAULTS["P"]
    gas: str = DEFAULTS["gas"]
    U: float | None = DEFAULTS["U"]
    U_Umf: float = DEFAULTS["U_Umf"]
    eps: float = DEFAULTS["eps"]
    U_e_Umf: float = DEFAULTS["U_e_Umf"]
    solid_i: str = DEFAULTS["solid_i"]
    d_i: float = DEFAULTS["d_i"]
    solid_j: str | None = DEFAULTS["solid_j"]
    d_j: float | None = DEFAULTS["d_j"]
    liquid: str = DEFAULTS["liquid"]
    h0: float = DEFAULTS["h0"]
    h0_j: float | None = DEFAULTS["h0_j"]
    ha_i: float | None = DEFAULTS["ha_i"]
    ha_j: float | None = DEFAULTS["ha_j"]
    e: float | None = DEFAULTS["e"]
    theta_deg: float | None = DEFAULTS["theta_deg"]
    beta_deg: float = DEFAULTS["beta_deg"]
    u0: float | None = DEFAULTS["u0"]
    speed: str | None = DEFAULTS["speed"]
    sigma_ln: float = DEFAULTS["sigma_ln"]
    granular_temperature: float | None = DEFAULTS["granular_temperature"]
    fluctuation_ratio: float = DEFAULTS["fluctuation_ratio"]
    bed_height: float = DEFAULTS["bed_height"]
    column_diameter: float = DEFAULTS["column_diameter"]
    orifice_area: float = DEFAULTS["orifice_area"]
    height: float | None = DEFAULTS["height"]
    wake_fraction: float = DEFAULTS["wake_fraction"]
    mode: str = DEFAULTS["mode"]
    body_forces: bool = DEFAULTS["body_forces"]
    drag_slip: str = DEFAULTS["drag_slip"]
    umf_method: str = DEFAULTS["umf_method"]
    u_ceiling: float = DEFAULTS["u_ceiling"]

    def __post_init__(self) -> None:
        for name in NUMERIC_FIELDS:  # Quantities and unit strings -> SI, once, here
            value = getattr(self, name)
            if value is None and DEFAULTS[name] is None:  # type: ignore[literal-required]
                continue  # derived (see DERIVED)
            if not isinstance(value, int | float) and value is not None:
                unit, long_name = FIELD_META[name]
                object.__setattr__(self, name, to_si(name, value, unit, long_name))
            try:  # one number in the field's physical range (a grid sweeps several)
                check_typed(name, value, getattr(self, name), scalar=True)
            except ValueError as exc:
                if isinstance(value, list | tuple | np.ndarray) and np.size(value) > 1:
                    raise ValueError(f"{exc}; to evaluate several values, sweep them: "
                                     f"at.sweep(scene, {name}=[...])") from None
                raise
        # whether the user named the speed law or model: a model named is given, one
        # derived from the default is an assumption (uncertain="assumed" may draw it)
        object.__setattr__(self, "_speed_given", self.speed is not None)
        if self.speed is None:
            if self.u0 is not None:
                chosen = "fixed"
            elif self.granular_temperature is not None:
                chosen = "maxwellian"
            else:
                chosen = "excess-gas"
            object.__setattr__(self, "speed", chosen)
        validate(self.values())
        # a finding about a value the user never typed (a field at its default) is said
        # where the value is used (collide, evaluate, a map or Monte Carlo that does not
        # sweep or draw it), not here: a map sweeping that field never uses it
        found = scene_findings(self.values())
        deferred = tuple(f for f in found if _about_default(f[0], self.values()))
        object.__setattr__(self, "_deferred_findings", deferred)
        warn_findings([f for f in found if f not in deferred], stacklevel=3)

    def values(self) -> dict:
        """The fields as a plain dict (the form :func:`evaluate` and sweeps take)."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}

    def replace(self, **changes) -> Scene:
        """A copy with some fields changed (validated)."""
        unknown = sorted(set(changes) - {f.name for f in dataclasses.fields(self)})
        if unknown:
            raise ValueError(f"{unknown[0]!r} is not a Scene field"
                             f"{suggestion(unknown[0], field_names(), material=False)}; "
                             f"fields: {field_names()}")
        new = dataclasses.replace(self, **changes)
        if "speed" not in changes:  # the speed as this scene has it: named or derived
            object.__setattr__(new, "_speed_given", getattr(self, "_speed_given", True))
        return new

    def evaluate(self, *, nodes: int = 16) -> dict:
        """Derived numbers of this scene (see :func:`evaluate`), as 0-d arrays."""
        warn_findings(deferred_findings(self), stacklevel=3)
        return evaluate(self.values(), nodes=nodes)

    def provenance(self) -> dict:
        """Every resolved input: ``{name: (value, units, origin, confidence)}``.

        ``origin`` is ``"given"`` (differs from the default), ``"default"`` (the Scene's
        default), ``"database: <entry>"`` or ``"derived: <rule>"``; ``confidence`` is
        ``"assumed"`` where the database marks the value as an assumption, ``"database"``
        for its other values, ``"user"`` or ``"default"``.
        """
        return provenance(self.values())

    def describe(self) -> str:
        """A table of every resolved input with its unit and origin (see
        :meth:`provenance`); assumed values are marked."""
        rows = []
        for name, (value, units, origin, conf) in self.provenance().items():
            shown = f"{value:.6g}" if isinstance(value, float) else str(value)
            flag = "  <- assumed" if conf == "assumed" else ""
            rows.append(f"  {name:20s} {shown:>14s} {units:14s} {origin}{flag}")
        return "resolved inputs (value, unit, origin):\n" + "\n".join(rows)

    def collide(self, u0=None, *, details: bool = True):
        """:func:`agglomtool.collide` at this scene; ``u0=None`` = the typical speed."""
        warn_findings(deferred_findings(self), stacklevel=3)
        r = Resolved(self.values())
        return r.collide(r.u_typical if u0 is None else u0, details=details)


#: The key of a Scene's values under which drawn melt compositions (oxide -> wt % arrays)
#: reach :class:`Resolved`: set by the Monte Carlo over a melt's assumed composition
#: (:mod:`agglomtool.uncertainty.assumed`), not a Scene field.
COMPOSITION_KEY = "_composition_wt"


#: A derived field (None) takes its value from this field (see the Scene's docstring).
_DERIVED_FROM = {"d_j": "d_i", "h0_j": "h0"}


def _about_default(field_name: str, values: dict) -> bool:
    """Whether a plausibility finding that blames ``field_name`` is about a value the
    user left at the Scene's default (a derived field: the one it follows)."""
    if values.get(field_name) is None and field_name in _DERIVED_FROM:
        field_name = _DERIVED_FROM[field_name]
    value = values.get(field_name)
    default: Any = dict(DEFAULTS).get(field_name)
    return (field_name in NUMERIC_FIELDS and value is not None
            and isinstance(default, int | float) and not isinstance(default, bool)
            and np.ndim(value) == 0 and float(value) == float(default))


def deferred_findings(scene: Scene, used=None) -> list:
    """The plausibility findings of ``scene`` about values left at their defaults, which it
    did not say when it was made (:class:`Scene`): those that hold where the scene is used
    with ``used`` (``{field: values}`` that a map sweeps or a Monte Carlo draws, replacing
    the scene's; None: the scene's own values)."""
    deferred = getattr(scene, "_deferred_findings", ())
    if not deferred or not used:
        return list(deferred)
    return [f for f in scene_findings({**scene.values(), **used}) if f in deferred]


def field_names() -> list[str]:
    """Names of the :class:`Scene` fields."""
    return [f.name for f in dataclasses.fields(Scene)]


def _check_name(field_name, value, allowed):
    if not isinstance(value, str) or value not in allowed:
        raise ValueError(f"{field_name} = {value!r} is not one of {sorted(allowed)}"
                         f"{suggestion(value, allowed)}")


def validate(values: dict) -> None:
    """Check a mapping of field values; the ``ValueError`` names the field."""
    unknown = sorted(set(values) - set(field_names()))
    if unknown:
        raise ValueError(f"{unknown[0]!r} is not a Scene field"
                         f"{suggestion(unknown[0], field_names(), material=False)}; "
                         f"fields: {field_names()}")
    for name in ("gas", "solid_i", "solid_j", "liquid"):
        v = values.get(name)
        if v is None and name == "solid_j":
            continue
        kind = "solid" if name.startswith("solid") else name
        known = materials.names(kind)
        if not isinstance(v, str) or materials._key(v) not in known:
            raise unknown_name(name, v, kind, known)
    _check_name("speed", values.get("speed"), SPEED_FAMILIES)
    _check_name("mode", values.get("mode"), MODES)
    _check_name("drag_slip", values.get("drag_slip"), DRAG_SLIP_MODES)
    _check_name("umf_method", values.get("umf_method"), umf_methods())
    if not isinstance(values.get("body_forces"), bool | np.bool_):
        raise ValueError(f"body_forces = {values.get('body_forces')!r} must be true or false")
    for name, (lo, hi, lo_open, hi_open) in FIELD_RANGES.items():
        v = values.get(name)
        if v is None:
            continue
        check_range(name, v, lo, hi, lo_open=lo_open, hi_open=hi_open, unit=short_unit(name))
    _check_geometry(values)
    speed = values["speed"]
    needed = SPEED_LAW_NEEDS.get(speed)
    if needed is not None and values.get(needed) is None:
        what = " (the value, or the median)" if needed == "u0" else ""
        raise ValueError(f"speed = {speed!r} needs {needed} [{short_unit(needed)}]{what}")


def _check_geometry(values: dict) -> None:
    """The bed's geometry against itself and the particles, where the speed model uses it:
    a bed no deeper than its particles, a height of interest above the bed, fewer than one
    orifice: a ``ValueError`` naming the fields. (A model that ignores the geometry leaves
    it unchecked: a unit slip in ``d_i`` is then the plausibility check's to name.)"""
    model = IMPACT_SPEED_MODELS.get(values.get("speed") or "")
    if model is None or "height" not in model.needs:
        return

    def extreme(name, how):
        v = values.get(name)
        return None if v is None else float(how(np.asarray(v, dtype=float)))

    H = extreme("bed_height", np.min)
    if H is None:
        return
    d = max(x for x in (extreme("d_i", np.max), extreme("d_j", np.max), 0.0)
            if x is not None)
    if H <= d:
        raise ValueError(f"bed_height = {H:g} m is not above the particle size (d = {d:g} "
                         "m): no bed; bed_height is the static bed height in m")
    h = extreme("height", np.max)
    if h is not None and h > H:
        raise ValueError(f"height = {h:g} m is above the bed (bed_height = {H:g} m): the "
                         "height of interest must lie in (0, bed_height]")
    D = extreme("column_diameter", np.min)
    a0 = extreme("orifice_area", np.max)
    if D is not None and a0 is not None and a0 > 0.25 * math.pi * D * D:
        raise ValueError(f"orifice_area = {a0:g} m2 is larger than the column's cross-"
                         f"section (column_diameter = {D:g} m): fewer than one orifice")


#: The Scene's fields that only an impact-speed law or model reads (nothing else of a map or
#: a bed does). The laws' parameters are read by their laws; the others by the models whose
#: registry entry needs them (``bed_height`` through its default height of interest).
_SPEED_ONLY = ("fluctuation_ratio", "column_diameter", "orifice_area", "height",
               "wake_fraction")


def _speed_readers() -> dict[str, tuple[str, ...]]:
    """Each field of :data:`_SPEED_ONLY` and the laws' parameters -> the speeds that read it."""
    readers: dict[str, tuple[str, ...]] = {"sigma_ln": ("lognormal",)}
    for law, name in SPEED_LAW_NEEDS.items():
        readers[name] = readers.get(name, ()) + (law,)
    for name in _SPEED_ONLY:
        readers[name] = tuple(k for k, m in IMPACT_SPEED_MODELS.items() if name in m.needs)
    readers["bed_height"] = readers["height"]
    return readers


#: Why ``U_Umf`` beside a given ``U`` does nothing (said for a typed and a swept ``U_Umf``).
_U_UMF_RULE = "U_Umf sets U (U_Umf x U_mf) only where U is not given"


def swept_without_effect(values: dict, swept, drawn=(), *, what: str = "grid ",
                         act: str = "sweep") -> tuple[str, str] | None:
    """The first field of ``swept`` (``{name: values}`` a map, a bed or a comparison
    sweeps) that no speed computing on it reads at the scene ``values``, and why, as
    ``(field, message)``; ``None`` if each is read. The speeds that compute: the swept
    ``speed`` values, else the scene's ``speed``, and ``drawn`` (the models that draws of a
    robust map or a comparison may take). A field only a speed law or model reads is
    refused where none of them does, and ``U_Umf`` where ``U`` is given or swept: a map
    axis along which nothing changes is no answer to what it asks. ``what`` begins the
    message (``"grid "``: a map's or a bed's axis; ``"uncertain "``: a law of a Monte Carlo,
    a robust map or a comparison, with ``act="draw"``)."""
    done = {"sweep": "the sweep replaces", "draw": "the draws replace"}.get(act)
    own = ([str(v) for v in np.ravel(swept["speed"])] if "speed" in swept
           else [values["speed"]])
    speeds = tuple(dict.fromkeys([*own, *drawn]))
    shown = speeds[0] if len(speeds) == 1 else list(speeds)
    if "U_Umf" in swept and ("U" in swept or values.get("U") is not None):
        by = ("the grid sweeps U" if "U" in swept
              else f"the scene gives U = {float(values['U']):g} m/s")
        return "U_Umf", (f"{what}U_Umf has no effect: {by}, and {_U_UMF_RULE}; leave U "
                         f"unset to {act} U_Umf")
    readers = _speed_readers()
    for name in swept:
        read_by = readers.get(name)
        if read_by is None:
            continue
        if not set(read_by) & set(speeds):
            first = np.ravel(swept[name])[0]
            one = f"{name}={first:g}" if isinstance(first, float | np.floating) else (
                f"{name}={first!r}")
            fix = (f"set the scene's speed to one of {list(read_by)}"
                   + (f" and give {name} one value there, which {done} (e.g. "
                      f"at.Scene(..., speed={read_by[0]!r}, {one})"
                      if done and name in SPEED_LAW_NEEDS.values() else "")
                   + ("" if done else f", or leave {name} out"))
            return name, f"{what}{name} has no effect with speed = {shown!r}: {fix}"
        if (name == "bed_height" and values.get("height") is not None
                and "height" not in swept):
            return name, (f"{what}bed_height has no effect: the height of interest is given "
                          f"(height = {values['height']:g} m) and bed_height only sets its "
                          "default (half of it); sweep height, or leave height unset")
    return None


def typed_unread(scene: Scene, typed, speeds=(), drawn=()) -> tuple[str, str] | None:
    """``(field, message)`` for a field typed in a configuration's ``[scene]`` (``typed``:
    the names it gave) that only impact-speed laws or models read and none of those that
    compute reads: ``speeds`` where the file sets them (a ``[grid]`` or ``[compare]`` of
    speeds), else the scene's, and ``drawn`` (the models the draws may take). A bed's
    ``bed_height`` beside ``speed = "excess-gas"`` changed nothing, unsaid. ``None`` if
    each is read; as :func:`swept_without_effect` for an axis."""
    values = scene.values()
    readers = _speed_readers()
    fields = {k: [values[k]] for k in typed if k in readers and values.get(k) is not None}
    if not fields:
        return None
    swept: dict = {"speed": [str(v) for v in speeds]} if len(speeds) else {}
    swept.update(fields)
    return swept_without_effect(values, swept, drawn, what="", act="type")


def typed_without_effect(scene: Scene, typed) -> tuple[str, str] | None:
    """``(field, message)`` for a field typed (``typed``: the names a configuration's table
    or a command line gave) that another typed field overrides in ``scene``: ``U_Umf``
    beside ``U``. ``None`` if none is. A Scene built in Python cannot tell a value typed
    from its default, so this is for those that can."""
    if "U" in typed and "U_Umf" in typed and scene.U is not None:
        return "U_Umf", (f"U_Umf = {scene.U_Umf:g} has no effect where U is given (U = "
                         f"{scene.U:g} m/s): {_U_UMF_RULE}; give one of them")
    return None


def impact_speed_methods(scene: Scene, *, calibrated: bool = True) -> list[str]:
    """The ``speed`` names usable at ``scene``, in the order of the registry.

    The distributions given by their own parameters come first where the scene gives them
    (``"fixed"`` and ``"lognormal"`` with ``u0``, ``"maxwellian"`` with
    ``granular_temperature``); then every model of
    :data:`agglomtool.bed.speed_models.IMPACT_SPEED_MODELS` that evaluates at the scene
    without a ``ValueError`` (outside its domain: a bed that is not fluidized, a
    restitution of 1, ...) and, with ``calibrated`` (the default), without a
    :class:`~agglomtool.PlausibilityWarning` (outside the data its correlations were
    fitted to: the Geldart group, the column, a slugging bed).
    """
    values = scene.values()
    out = []
    if values.get("u0") is not None:
        out += ["fixed", "lognormal"]
    if values.get("granular_temperature") is not None:
        out.append("maxwellian")
    r = Resolved(values)
    get = r._speed_inputs()
    for name, model in IMPACT_SPEED_MODELS.items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PlausibilityWarning)  # the scene's own, said
            inputs = {k: get[k]() for k in model.needs}
        with warnings.catch_warnings():
            warnings.simplefilter("error" if calibrated else "ignore", PlausibilityWarning)
            try:
                speed_law(name, inputs)
            except (ValueError, PlausibilityWarning):
                continue
        out.append(name)
    return out


def provenance(values: dict) -> dict:
    """Origin of every input a scene resolves (see :meth:`Scene.provenance`)."""
    v = dict(values)
    out = {}
    unit = {k: FIELD_META[k][0] for k in FIELD_META}
    for name, default in DEFAULTS.items():
        value = v.get(name)
        if value is None:
            continue
        if isinstance(value, np.ndarray | list | tuple):
            continue  # swept: the map's coordinates say it
        if name == "speed" and default is None:
            out[name] = (value, "name", "derived: fixed with u0, maxwellian with "
                         "granular_temperature, else excess-gas", "derived")
            continue
        given = not (value == default)
        out[name] = (value if not isinstance(value, np.generic) else value.item(),
                     unit.get(name, "name"), "given" if given else "default",
                     "user" if given else "default")
    si_name = str(v["solid_i"])
    sj_name = str(v["solid_j"] or v["solid_i"])
    si, sj = materials.solid(si_name), materials.solid(sj_name)
    entry = materials.liquid_entry(str(v["liquid"]))

    def db(entry_obj, kind, field):
        conf = "assumed" if field in entry_obj.assumed else "database"
        return f"database: {kind} {entry_obj.name}.{field}", conf

    if v.get("solid_j") is None:
        out["solid_j"] = (sj_name, "name", "derived: solid_i", "derived")
    if v.get("d_j") is None:
        out["d_j"] = (float(v["d_i"]), "m", "derived: d_i", "derived")
    if v.get("h0_j") is None:
        out["h0_j"] = (float(v["h0"]), "m", "derived: h0", "derived")
    for side, sol in (("i", si), ("j", sj)):
        if v.get(f"ha_{side}") is None:
            out[f"ha_{side}"] = (sol.asperity_height, "m", *db(sol, "solid",
                                                                "asperity_height"))
        out[f"rho_{side}"] = (sol.density, "kg/m**3", *db(sol, "solid", "density"))
    if v.get("e") is None:
        conf = ("assumed" if {"restitution_dry"} & (set(si.assumed) | set(sj.assumed))
                else "database")
        out["e"] = (0.5 * (si.restitution_dry + sj.restitution_dry), "dimensionless",
                    f"database: mean of solid {si.name}.restitution_dry and "
                    f"{sj.name}.restitution_dry", conf)
    if v.get("theta_deg") is None:
        out["theta_deg"] = (entry.theta_deg, "degree", *db(entry, "liquid", "theta_deg"))
    if entry.model == "melt" and "composition_wt" in entry.assumed:
        out["liquid composition"] = (", ".join(f"{k} {w:g}" for k, w in
                                               (entry.composition_wt or {}).items()), "wt %",
                                     f"database: liquid {entry.name}.composition_wt",
                                     "assumed")
    return out


def assumed_inputs(values: dict) -> list[str]:
    """``"<entry> <field> = <value>"`` for every database value a scene uses that the database
    marks as an assumption (and the scene does not override)."""
    si = materials.solid(str(values["solid_i"]))
    sj = materials.solid(str(values.get("solid_j") or values["solid_i"]))
    liquid = materials.liquid_entry(str(values["liquid"]))
    overridden: dict[str, tuple[Any, ...]] = {
        "asperity_height": ("ha_i", "ha_j"), "restitution_dry": ("e",),
        "theta_deg": ("theta_deg",)}
    shown = {"asperity_height": lambda x: f"{x * 1e6:g} um", "density": lambda x: f"{x:g} kg/m3",
             "theta_deg": lambda x: f"{x:g} deg"}
    out = []
    for entry, which in ((si, "ha_i"), (sj, "ha_j"), (liquid, None)):
        for field_name in entry.assumed:
            keys = overridden.get(field_name, ())
            if field_name == "asperity_height":
                keys = (which,)
            if keys and all(values.get(k) is not None for k in keys):
                continue  # the user gave the value
            val = getattr(entry, field_name)
            text = shown.get(field_name, lambda x: f"{x:g}" if isinstance(x, float) else
                             ", ".join(f"{k} {w:g}" for k, w in dict(x).items()))(val)
            item = f"{entry.name} {field_name} = {text}"
            if item not in out:
                out.append(item)
    return out


def _on_unique(func, *arrays):
    """Evaluate ``func`` on the unique rows of the broadcast ``arrays``; broadcast back.

    ``func`` takes 1-D arrays and returns a tuple of 1-D arrays of the same length.
    """
    b = np.broadcast_arrays(*[np.asarray(a, dtype=float) for a in arrays])
    shape = b[0].shape
    cols = [x.reshape(-1) for x in b]
    # a column that holds one value (a fixed P beside uncertain T's) is no part of the key:
    # one column left is deduplicated by a plain sort, several by numpy's row-wise unique
    # (several times slower: a Monte Carlo over T spent most of its time there)
    varying = [k for k, c in enumerate(cols) if c.size and not np.all(c == c[0])]
    if len(varying) <= 1:
        key = cols[varying[0]] if varying else cols[0][:1]
        uniq1, inverse = np.unique(key, return_inverse=True)
        if not varying:
            inverse = np.zeros(cols[0].size, dtype=np.intp)
        args = [uniq1 if k in varying else np.full(uniq1.size, c[0]) if c.size else c
                for k, c in enumerate(cols)]
        out = func(*args)
    else:
        stacked = np.stack(cols, axis=1)
        uniq, inverse = np.unique(stacked, axis=0, return_inverse=True)
        out = func(*uniq.T)
    inverse = inverse.reshape(-1)
    return tuple(np.asarray(o)[inverse].reshape(shape) for o in out)


def _same_particle(p, q) -> bool:
    """True where two particles have the same diameter, density and coating arrays (the
    default ``solid_j``, ``d_j`` and ``h0_j`` of a scene: one ``U_mf`` serves both)."""
    return all(a is b or (np.shape(a) == np.shape(b) and np.array_equal(a, b))
               for a, b in ((p.d, q.d), (p.rho, q.rho), (p.h0, q.h0)))


def _compact(a):
    """``a`` as an array whose size-1-everywhere-it-is-constant shape is kept."""
    return np.asarray(a, dtype=float)


class Resolved:
    """Lazily derived numbers of a mapping of field values (arrays that broadcast).

    ``Umf`` [m/s], if given, is used instead of the pair's own minimum fluidization velocity
    (a bed's, shared by all its pairs: see :func:`agglomtool.bed.bed_propensity`); the gas
    velocity, the emulsion velocity and the speed distribution then follow it.
    """

    def __init__(self, values: dict, *, Umf=None):
        v = dict(values)
        for name in CATEGORICAL_FIELDS:
            if name in v and v[name] is not None:
                arr = np.asarray(v[name])
                if (name == "speed" and arr.size > 1
                        and set(arr.ravel().tolist()) <= IMPACT_SPEED_MODELS.keys()):
                    v[name] = arr  # a model drawn per element (uncertain="assumed")
                else:
                    v[name] = str(arr.reshape(-1)[0])
        v["body_forces"] = bool(np.asarray(v["body_forces"]).reshape(-1)[0])
        self.v = v
        if Umf is not None:
            self.__dict__["Umf"] = np.asarray(Umf, dtype=float)  # pre-sets the cached property

    def _default_hint(self, exc: Exception, *names) -> str:
        """``"; T = ... is the Scene's default ..."`` for the fields among ``names`` that the
        message of ``exc`` blames and that still hold the Scene's default (a value the user
        may never have typed)."""
        defaults = DEFAULTS
        hints = []
        for name in (n for n in names if f"{n} = " in str(exc)):
            val = np.asarray(self.v.get(name)).reshape(-1)
            if val.size == 1 and val.dtype.kind == "f" and float(val[0]) == defaults.get(name):
                unit = FIELD_META[name][0]
                hints.append(f"{name} = {defaults.get(name):g} {unit} is the Scene's default: "
                             f"set {name}")
        return ("; " + "; ".join(hints)) if hints else ""

    def num(self, name, default=None):
        """A numeric field as a float array (``default`` when it is ``None``)."""
        val = self.v.get(name)
        if val is None:
            return default
        return _compact(val)

    # --- materials --------------------------------------------------------------------
    @cached_property
    def solids(self):
        si = materials.solid(self.v["solid_i"])
        sj = materials.solid(self.v["solid_j"] or self.v["solid_i"])
        return si, sj

    @cached_property
    def sources(self) -> dict:
        """Where the materials came from: ``{"solid <name>": text, ...}`` (database entries
        and, for the liquid and gas, the property models used)."""
        si, sj = self.solids
        _ = self._gas_arrays
        name_l, name_g = self.v["liquid"], self.v["gas"]
        return {
            f"solid {si.name}": si.source,
            f"solid {sj.name}": sj.source,
            f"liquid {name_l}": f"{materials.liquid_entry(name_l).source} Models: "
                                f"{self.liquid.source}",
            f"gas {name_g}": f"{materials.gas(name_g).source} Models: {self._gas_source}",
        }

    # --- properties on unique (T, P) ---------------------------------------------------
    @cached_property
    def _gas_arrays(self):
        src = {}

        def f(T, P):
            g = gas_properties(T, P, materials.gas(self.v["gas"]).composition)
            src["s"] = g.source
            return g.mu, g.rho

        try:
            mu, rho = _on_unique(f, self.num("T"), self.num("P"))
        except ValueError as exc:  # a Scene cannot extrapolate: no remedy offered
            raise ValueError(f"gas {self.v['gas']!r}: {getattr(exc, 'problem', exc)}"
                             + self._default_hint(exc, "T", "P")) from None
        self._gas_source = src["s"]
        return mu, rho

    @property
    def mu_g(self):
        return self._gas_arrays[0]

    @property
    def rho_g(self):
        return self._gas_arrays[1]

    @cached_property
    def gas(self):
        from .inputs import Gas

        return Gas(mu=self.mu_g, rho=self.rho_g, name=self.v["gas"])

    @cached_property
    def liquid(self) -> Liquid:
        entry = materials.liquid_entry(self.v["liquid"])
        src = {}
        composition = self.v.get(COMPOSITION_KEY)
        if composition is not None:
            return self._drawn_melt(entry, composition)

        def f(T, P):
            liq = materials.liquid(self.v["liquid"], T=T, P=P)
            src["s"] = liq.source
            n = T.shape
            return (np.broadcast_to(liq.mu, n), np.broadcast_to(liq.gamma, n),
                    np.broadcast_to(liq.rho, n))

        if entry.model == "fixed":
            liq = materials.liquid(self.v["liquid"])
            mu, gamma, rho, src["s"] = liq.mu, liq.gamma, liq.rho, liq.source
        else:
            try:
                mu, gamma, rho = _on_unique(f, self.num("T"), self.num("P"))
            except ValueError as exc:
                raise ValueError(f"liquid {entry.name!r} ({entry.model} properties): {exc}"
                                 + self._default_hint(exc, "T", "P")) from None
        theta = self.num("theta_deg", entry.theta_deg)
        return Liquid(mu=mu, gamma=gamma, rho=rho, theta_deg=theta, name=entry.name,
                      source=src["s"])

    def take_properties(self, whole: Resolved, cut) -> None:
        """The gas's and the liquid's properties from ``whole``, the same scene over axes
        that hold this one's ``T`` and ``P`` values, each array cut to this one's elements
        by ``cut``: a map computes them once over its whole T and P axes instead of once
        per block (the same values: the property models are evaluated element by
        element, :func:`_on_unique`)."""
        mu, rho = whole._gas_arrays
        self.__dict__["_gas_arrays"] = (cut(mu), cut(rho))
        self._gas_source = whole._gas_source
        liq = whole.liquid
        entry = materials.liquid_entry(self.v["liquid"])
        self.__dict__["liquid"] = Liquid(
            mu=cut(liq.mu), gamma=cut(liq.gamma), rho=cut(liq.rho),
            theta_deg=self.num("theta_deg", entry.theta_deg), name=liq.name,
            source=liq.source)

    def _drawn_melt(self, entry, composition) -> Liquid:
        """The melt at drawn compositions (oxide -> wt % arrays, broadcast against ``T``):
        one vectorised pass of the melt models, no table of unique states."""
        from .properties.melt import melt_liquid

        if entry.model != "melt":
            raise ValueError(f"liquid {entry.name!r} is not a melt: it has no composition "
                             "to draw")
        try:
            liq = melt_liquid(composition, self.num("T"), viscosity_model=entry.viscosity_model,
                              name=entry.name)
        except ValueError as exc:
            raise ValueError(f"liquid {entry.name!r} at its drawn compositions: {exc}") from None
        theta = self.num("theta_deg", entry.theta_deg)
        return Liquid(mu=liq.mu, gamma=liq.gamma, rho=liq.rho, theta_deg=theta,
                      name=entry.name, source=f"{liq.source} (at drawn compositions)")

    # --- particles, fluidization, bed ----------------------------------------------------
    @cached_property
    def particles(self):
        si, sj = self.solids
        d_i = self.num("d_i")
        d_j = self.num("d_j", d_i)
        h0 = self.num("h0")
        h0_j = self.num("h0_j", h0)
        p_i = Particle(d=d_i, rho=si.density, h0=h0, ha=self.num("ha_i", si.asperity_height))
        p_j = Particle(d=d_j, rho=sj.density, h0=h0_j, ha=self.num("ha_j", sj.asperity_height))
        return p_i, p_j

    @cached_property
    def e(self):
        si, sj = self.solids
        return self.num("e", 0.5 * (si.restitution_dry + sj.restitution_dry))

    @cached_property
    def Umf(self):
        """The larger ``U_mf`` of the two wet particles [m/s]; computed once where the two
        are the same particle (same diameter, density and coating)."""
        p_i, p_j = self.particles
        u_i = self._umf_of(p_i)
        if _same_particle(p_i, p_j):
            return u_i  # np.maximum(u_i, u_i) is u_i
        return np.maximum(u_i, self._umf_of(p_j))

    def _umf_of(self, p):
        """``U_mf`` of one wet particle [m/s]: :func:`.properties.umf_coated` (one compiled
        pass), or the numpy route :meth:`_umf_reference` where that does not apply."""
        out = umf_coated(p.d, p.rho, p.h0, self.liquid.rho, self.gas.mu, self.gas.rho,
                         self.v["umf_method"])
        return self._umf_reference(p) if out is None else out

    def _umf_reference(self, p):
        """``U_mf`` of one wet particle by the numpy route [m/s]: :func:`.properties.umf`
        of the wet diameter and the wet particle's mean density (:func:`.pair.wet_mass`)."""
        d_wet = p.d + 2.0 * p.h0
        vol = (math.pi / 6.0) * d_wet**3
        rho_p = wet_mass(p, self.liquid.rho) / vol
        return umf(d_wet, rho_p, self.gas, self.v["umf_method"])

    @cached_property
    def U_e(self):
        return self.num("U_e_Umf") * self.Umf

    @cached_property
    def U(self):
        U = self.num("U")
        return self.num("U_Umf") * self.Umf if U is None else U * np.ones_like(self.Umf)

    def U_into(self, target) -> None:
        """Compute :attr:`U` into ``target`` (a float64 array, e.g. a map's result block),
        where it is not computed yet and has exactly ``target``'s shape: the same product,
        written once where the map keeps it instead of copied there afterwards."""
        U_Umf = self.num("U_Umf")
        if ("U" in self.__dict__ or self.v.get("U") is not None or U_Umf is None
                or target.dtype != np.float64 or not target.flags.writeable):
            return
        Umf = self.Umf
        shape = target.shape
        if np.broadcast_shapes(np.shape(U_Umf), np.shape(Umf)) != shape:
            return
        if target.size < MAP_PASS_MIN or len(shape) > 4:
            self.__dict__["U"] = np.multiply(U_Umf, Umf, out=target)
            return
        # a map's block: the same product per element, on every thread
        parallel_launch(_product_pass, _as_4d(U_Umf, len(shape)), _as_4d(Umf, len(shape)),
                        target.reshape((1,) * (4 - len(shape)) + shape))
        self.__dict__["U"] = target

    @cached_property
    def bed(self) -> Bed:
        return Bed(eps=self.num("eps"), U=self.U_e)

    # --- speeds ------------------------------------------------------------------------
    @cached_property
    def speeds(self) -> SpeedModel:
        family = self.v["speed"]
        if isinstance(family, np.ndarray):  # a model drawn per element (uncertain="assumed")
            get = self._speed_inputs()
            return mixed_law(family, lambda name: {k: get[k]() for k in
                                                   IMPACT_SPEED_MODELS[name].needs})
        if family in IMPACT_SPEED_MODELS:
            get = self._speed_inputs()
            return speed_law(family, {k: get[k]() for k in IMPACT_SPEED_MODELS[family].needs})
        return SpeedModel(family, u0=self.num("u0"), sigma_ln=self.num("sigma_ln"),
                          granular_temperature=self.num("granular_temperature"))

    def _speed_inputs(self) -> dict:
        """How to get each input of the impact-speed models (computed only when a model
        needs it): the bed's hydrodynamics use particle i's solid and size."""
        H = self.num("bed_height")
        return {
            "U": lambda: self.U, "Umf": lambda: self.Umf, "d_p": lambda: self.num("d_i"),
            "rho_p": lambda: np.asarray(self.solids[0].density, dtype=float),
            "rho_g": lambda: self.rho_g, "eps": lambda: self.num("eps"), "e": lambda: self.e,
            "fluctuation_ratio": lambda: self.num("fluctuation_ratio"),
            "column_diameter": lambda: self.num("column_diameter"),
            "orifice_area": lambda: self.num("orifice_area"),
            "height": lambda: self.num("height", 0.5 * H),
            "wake_fraction": lambda: self.num("wake_fraction"),
        }

    @property
    def u_typical(self):
        """Typical (median) impact speed [m/s]."""
        return self.speeds.median()

    # --- collisions ------------------------------------------------------------------
    def _common(self):
        p_i, p_j = self.particles
        return dict(liquid=self.liquid, gas=self.gas, bed=self.bed,
                    beta_deg=self.num("beta_deg"), e=self.e, mode=self.v["mode"],
                    body_forces=self.v["body_forces"], drag_slip=self.v["drag_slip"])

    def collide(self, u0, *, details: bool = False, out=None):
        """:func:`agglomtool.collide` of the scene's pair at ``u0``; ``out``: arrays to
        write ``e_w``, ``stage`` and ``agglomerated`` into, as there, used only where they
        have the collision's shape (:meth:`collide_shape`)."""
        p_i, p_j = self.particles
        common = self._common()
        if out:
            shape = self.collide_shape(u0)
            out = {k: a for k, a in out.items() if a is not None and a.shape == shape
                   and a.flags.c_contiguous} or None
        return collide(p_i, p_j, u0=u0, details=details, out=out, **common)

    def collide_shape(self, u0) -> tuple:
        """The broadcast shape of :meth:`collide`'s inputs at ``u0`` (its results')."""
        p_i, p_j = self.particles
        c = self._common()
        arrays = (p_i.d, p_i.rho, p_i.h0, p_i.ha, p_j.d, p_j.rho, p_j.h0, p_j.ha,
                  c["liquid"].mu, c["liquid"].gamma, c["liquid"].rho, c["liquid"].theta_deg,
                  c["gas"].mu, c["gas"].rho, c["bed"].eps, c["bed"].U, c["beta_deg"], c["e"],
                  u0)
        return np.broadcast_shapes(*[np.shape(a) for a in arrays])

    def collide_on(self, mask):
        """``f(u0)``: :meth:`collide` on the elements where ``mask`` (a boolean array of the
        block's shape) is true, ``u0`` given there only (1-D). The inputs are cut once, so
        a loop over speeds pays for the masked elements alone; each collision is the same
        arithmetic as in :meth:`collide` (bitwise the same result)."""
        shape = np.shape(mask)

        def cut(x):
            return None if x is None else np.broadcast_to(np.asarray(x, float), shape)[mask]

        def cut_fields(obj, names):
            return dataclasses.replace(obj, **{k: cut(getattr(obj, k)) for k in names})

        p_i, p_j = (cut_fields(p, ("d", "rho", "h0", "ha")) for p in self.particles)
        common = self._common()
        common["liquid"] = cut_fields(common["liquid"], ("mu", "gamma", "rho", "theta_deg"))
        common["gas"] = cut_fields(common["gas"], ("mu", "rho"))
        common["bed"] = cut_fields(common["bed"], ("eps", "U"))
        common["beta_deg"], common["e"] = cut(common["beta_deg"]), cut(common["e"])
        return lambda u0: collide(p_i, p_j, u0=u0, details=False, **common)

    def sticking_pair(self, u_star):
        """The collisions of this scene as the fused kernels take them, for the compiled
        sticking set of :func:`~agglomtool.bed.speeds.sticking_probability` (its ``pair``):
        ``(ins, steps, shape, tier, body, particle_slip)`` over the broadcast of the
        inputs and ``u_star``; ``tier`` the fused tier's code, or the mode's name where it
        has no fused kernel."""
        mode = self.v["mode"]
        p_i, p_j = self.particles
        c = self._common()
        shape, ins, steps, _ = _fused_inputs(
            p_i, p_j, c["liquid"], c["gas"], c["bed"], c["beta_deg"], c["e"],
            np.zeros(np.shape(u_star)), None, check=False)
        return (ins, steps, shape, _FUSED.get(mode, mode), c["body_forces"],
                c["drag_slip"] == "particle")

    @cached_property
    def u_star(self):
        """Critical impact speed ``u0*`` [m/s] (shape of the inputs it depends on); ``inf``
        above the ceiling ``u_ceiling``, where the search stops early."""
        p_i, p_j = self.particles
        ceiling = float(np.max(self.num("u_ceiling")))
        return critical_impact_speed(p_i, p_j, u_max=ceiling, **self._common())

    def stokes_parts(self) -> tuple:
        """``(2 m_r, 1.5 pi mu_l r^2)`` of :meth:`stokes`: ``St = (2 m_r u0) / that``."""
        p_i, p_j = self.particles
        m_i = wet_mass(p_i, self.liquid.rho)
        m_j = wet_mass(p_j, self.liquid.rho)
        m_r = m_i * m_j / (m_i + m_j)
        r = 2.0 / (2.0 / p_i.d + 2.0 / p_j.d)
        return m_r * 2.0, 1.5 * math.pi * self.liquid.mu * r * r

    def stokes(self, u0, out=None):
        """Viscous Stokes number of the pair at head-on speed ``u0`` [-]:
        ``St = m_r w / (1.5 pi mu_l r^2)`` with the wet reduced mass ``m_r``, relative
        speed ``w = 2 u0`` and harmonic radius ``r``; for identical particles it is the
        paper's ``St = 2 m v0 / (3 pi mu_l r^2)`` (Eq. 77) with ``v0 = u0``. ``out``: a
        float64 array of the result's shape to write it into (then returned)."""
        # the formula's operations in its order, in one array divided in place where its
        # shape is the result's (a new array costs more than the arithmetic)
        m2, den = self.stokes_parts()
        shape = np.broadcast_shapes(np.shape(m2), np.shape(u0), np.shape(den))
        if not (out is not None and out.dtype == np.float64 and out.shape == shape):
            out = None
        st = np.multiply(m2, u0, out=out)
        if isinstance(st, np.ndarray) and st.shape == shape:
            return np.divide(st, den, out=st)
        return st / den


@vectorize(cache=CACHE)
def _margin_of(u_typ, u_star):  # pragma: no cover - compiled
    """The margin ``u_typ / u0*`` of one element, 0 where ``u0*`` is infinite (no
    collision sticks there): ``np.where(np.isinf(u_star), 0.0, u_typ / u_star)`` in one
    pass, written where the caller says (``out``)."""
    return _margin_one(u_typ, u_star)


@njit(inline="always", cache=CACHE)
def _margin_one(u_typ, u_star):  # pragma: no cover - compiled
    """The margin's rule, written once for :func:`_margin_of` and :func:`_typical_pass`."""
    if math.isinf(u_star):
        return 0.0
    return u_typ / u_star


@njit(parallel=True, cache=CACHE)
def _typical_pass(base, median_of, ln2, u_star, m2, den, u_typ, margin, st):
    """One pass over a map's block (4-D outputs of one shape; each input 4-D, of length 1
    or the block's on each axis, broadcast here): the typical speed ``u_typ``
    (``sqrt(base ln 2)``, the Maxwellian median, where ``median_of``, else ``base``), the
    margin (:func:`_margin_of`) and ``St = (m2 u_typ) / den`` (:meth:`Resolved.stokes`),
    each written into its array with the arithmetic of the numpy passes it replaces. The
    inputs are read row by row with a step of 0 or 1 (a loop the compiler vectorizes)."""
    a, b, c, d = margin.shape
    for row in prange(a * b * c):  # pragma: no cover - compiled
        i, j, k = _row_index(row, b, c)
        rb, sb = _row(base, i, j, k)
        ru, su = _row(u_star, i, j, k)
        rm, sm = _row(m2, i, j, k)
        rd, sd = _row(den, i, j, k)
        o_typ = u_typ[i, j, k]
        o_margin = margin[i, j, k]
        o_st = st[i, j, k]
        for m in range(d):
            u = rb[m * sb]
            if median_of:
                u = math.sqrt(u * ln2)
            o_typ[m] = u
            o_margin[m] = _margin_one(u, ru[m * su])
            o_st[m] = (rm[m * sm] * u) / rd[m * sd]


@njit(parallel=True, cache=CACHE)
def _product_pass(a, b, out):
    """``out = a * b`` (numpy's multiply, element by element) over a map's block: ``out``
    4-D, ``a`` and ``b`` 4-D of length 1 or ``out``'s on each axis, read row by row with a
    step of 0 or 1 (as :func:`_typical_pass` reads its inputs)."""
    p, q, r, d = out.shape
    for row in prange(p * q * r):  # pragma: no cover - compiled
        i, j, k = _row_index(row, q, r)
        ra, sa = _row(a, i, j, k)
        rb, sb = _row(b, i, j, k)
        o = out[i, j, k]
        for m in range(d):
            o[m] = ra[m * sa] * rb[m * sb]


@njit(inline="always", cache=CACHE)
def _row(a, i, j, k):  # pragma: no cover - compiled
    """``(values, step)``: the last axis of the 4-D ``a`` at the block's row ``(i, j, k)``
    (0 where ``a``'s axis has length 1: broadcast), and the step to read it by along the
    block's last axis (0 where it has one value, broadcast; else 1)."""
    r = a[i if a.shape[0] > 1 else 0, j if a.shape[1] > 1 else 0,
          k if a.shape[2] > 1 else 0]
    return r, 1 if r.shape[0] > 1 else 0


@njit(inline="always", cache=CACHE)
def _row_index(row, b, c):  # pragma: no cover - compiled
    """``(i, j, k)``: the block's row number ``row`` (C order over its first three axes,
    of lengths ``(., b, c)``) as indices."""
    return row // (b * c), (row // c) % b, row % c


def _as_4d(a, ndim: int):
    """``a`` (of at most ``ndim`` axes, broadcasting to the block's) as a C-contiguous
    float64 4-D array of its own values (no copy where it is one already), leading axes of
    length 1 added: the block's axes at the end, as the outputs'."""
    a = np.ascontiguousarray(a, dtype=np.float64)
    return a.reshape((1,) * (4 - a.ndim) + a.shape) if a.ndim <= ndim else None


def _typical_in_one_pass(r: Resolved, u_star, into: dict):
    """The typical speed, margin and ``St`` of a map's block written by
    :func:`_typical_pass` into ``into``'s arrays (the block's result), the typical speed
    returned as :func:`collision_outputs` passes it to the collision; None (nothing
    written) where ``into`` lacks one of them or they are not float64 arrays of one shape
    of at most 4 axes to which the inputs broadcast."""
    targets: list[np.ndarray] = []
    for k in ("u_typical", "margin", "St"):
        t = into.get(k)
        if t is None or t.dtype != np.float64 or not t.flags.writeable:
            return None
        targets.append(t)
    shape = targets[0].shape
    if len(shape) > 4 or any(t.shape != shape for t in targets):
        return None
    speeds = r.speeds
    # The Maxwellian median computed in the pass where it is the block's own array (as
    # SpeedModel.median writes it into its ``out``); else as before, then read here.
    median_of = speeds.family == "maxwellian" and speeds.theta.shape == shape
    u_typ = targets[0] if median_of else speeds.median()
    m2, den = r.stokes_parts()
    try:
        if np.broadcast_shapes(np.shape(u_typ), np.shape(u_star), np.shape(m2),
                               np.shape(den)) != shape:
            return None
    except ValueError:
        return None
    base = speeds.theta if median_of else u_typ
    ins = [_as_4d(x, len(shape)) for x in (base, u_star, m2, den)]
    if any(x is None for x in ins):
        return None
    four = [t.reshape((1,) * (4 - len(shape)) + shape) for t in targets]
    parallel_launch(_typical_pass, ins[0], median_of, _LN2, ins[1], ins[2], ins[3], *four)
    return u_typ


def capillary_number(mu_l, gamma, u_star):
    """Capillary number at the critical speed, ``Ca = mu_l (2 u0*) / gamma`` [-], as the
    paper evaluates it (Section 3.1: 8.3e-4 for case I, 31.9 for case II); ``inf`` where
    ``u0* = inf``."""
    return mu_l * 2.0 * u_star / gamma


def evaluate(values: dict, *, nodes: int = 16, u_star=None) -> dict:
    """Every derived number of a scene (or a block of a grid of scenes).

    Parameters
    ----------
    values : dict
        Field values (see :class:`Scene`); numeric fields may be arrays that broadcast.
    nodes : int
        Quadrature nodes of the impact-speed distribution (see
        :func:`agglomtool.bed.speeds.sticking_probability`).
    u_star : array, optional
        ``u0*`` [m/s] if already known (it is then not recomputed).

    Returns
    -------
    dict of numpy.ndarray
        ``mu_g`` [Pa s], ``rho_g`` [kg/m3], ``mu_l`` [Pa s], ``gamma_l`` [N/m], ``rho_l``
        [kg/m3], ``Umf``, ``U``, ``U_e``, ``u_typical``, ``u_star`` [m/s], ``Ca_star``,
        ``regime`` (0 capillary-, 1 viscous-limited), ``St``, ``e_w``, ``agglomerated``,
        ``stage``, ``propensity``, ``margin`` [-].
    """
    r = Resolved(values)
    out = critical_outputs(r, u_star)
    out.update(collision_outputs(r, out["u_star"], nodes))
    out.update(property_outputs(r))
    return out


def property_outputs(r: Resolved) -> dict:
    """Gas and liquid properties, ``U_mf`` and the emulsion velocity."""
    return {"mu_g": r.mu_g, "rho_g": r.rho_g, "mu_l": r.liquid.mu, "gamma_l": r.liquid.gamma,
            "rho_l": r.liquid.rho, "Umf": r.Umf, "U_e": r.U_e}


def critical_outputs(r: Resolved, u_star=None) -> dict:
    """``u0*`` (``inf`` above the ceiling), its flag (:data:`U_STAR_FLAGS`), the capillary
    number at ``u0*`` and the regime it implies."""
    us = r.u_star if u_star is None else np.asarray(u_star, dtype=float)
    ceiling = r.num("u_ceiling")
    flag = np.where(us == 0.0, 1, np.where(us > ceiling, 2, 0)).astype(np.int8)
    us = np.where(flag == 2, np.inf, us)
    ca = capillary_number(r.liquid.mu, r.liquid.gamma, us)
    regime = np.where(ca > CA_VISCOUS, 1, 0).astype(np.int8)
    return {"u_star": us, "u_star_flag": flag, "Ca_star": ca, "regime": regime}


def collision_outputs(r: Resolved, u_star, nodes: int, out=None) -> dict:
    """Outcome at the typical speed, Stokes number, propensity and margin. ``out``: an
    optional ``{name: array of the block's shape}`` (a map's result, in memory) into which
    the margin is computed, with no temporaries of the block's size; the other outputs
    are returned as views, for the caller to write once."""
    into = {} if out is None else out
    # A map's block: the typical speed, margin and St in one compiled pass, written into
    # its result (the same arithmetic as the numpy passes below, element by element).
    u_typ = _typical_in_one_pass(r, u_star, into)
    done = u_typ is not None
    if not done:
        u_typ = r.speeds.median(out=into.get("u_typical"))  # r.u_typical, in its block
    res = r.collide(u_typ, out={k: into.get(k) for k in ("e_w", "stage", "agglomerated")})
    # The block's shape: names (solids, mode, ...) reach the kernel as one scalar each, so
    # the collision's shape alone can miss their (size-1) axes and those of u0*.
    shape = np.broadcast_shapes(res.e_w.shape, np.shape(u_star), np.shape(r.U),
                                np.shape(u_typ))
    prop = sticking_probability(r.speeds, u_star, r.collide, nodes=nodes, shape=shape,
                                collide_on=r.collide_on, pair=r.sticking_pair,
                                out=into.get("propensity"))
    b = np.broadcast_to
    target = None if out is None else out.get("margin")
    u_typ_f, u_star_f = np.asarray(u_typ, dtype=float), np.asarray(u_star, dtype=float)
    with np.errstate(divide="ignore"):
        if done:
            margin = target
        elif (target is not None and target.shape == tuple(shape)
                and target.dtype == np.float64):
            margin = target  # written once into the result
            _margin_of(u_typ_f, u_star_f, out=target)
        else:
            margin = b(_margin_of(u_typ_f, u_star_f), shape)
    st = into["St"] if done else r.stokes(u_typ, out=into.get("St"))
    if done:
        u_typ = into["u_typical"]

    def view(name, a):  # an output already in its block of ``out`` is that block
        return a if a is into.get(name) else b(a, shape)

    return {
        "u_typical": view("u_typical", u_typ), "U": view("U", r.U), "e_w": view("e_w", res.e_w),
        "agglomerated": view("agglomerated", res.agglomerated),
        "stage": view("stage", res.stage),
        "St": view("St", st), "propensity": view("propensity", prop),
        "margin": margin,
    }
