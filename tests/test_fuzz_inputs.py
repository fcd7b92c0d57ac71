"""Bad input refused, at every public entry point.

A fuzz of generated bad inputs (fixed seed: the same cases on every run): empty arrays, NaN
and infinities, absurd magnitudes, values just outside a field's range, wrong types, lists
where one number is meant, unknown names, absurd-but-finite unit conversions ("5 parsec"
for a coating), duplicate size classes, bad option values, a sweep without a grid. Each
case is one test id. A case passes when the call raises a ``ValueError`` (or a
``TypeError``) whose message names the field, shows the value and says what is allowed;
on the command line, when the command exits non-zero with one line ``agglomtool: error:
...`` naming the field, and no traceback.

``python tests/test_fuzz_inputs.py`` prints the counts per entry point (clear, unclear,
accepted).
"""

from __future__ import annotations

import contextlib
import functools
import io
import math
import re
import sys
import tempfile
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest

SEED = 20240424
NAN, INF = math.nan, math.inf
MAX_CORE_SPEED = 1e12  # where the collision core's speeds end (docs/inputs.md)

#: Words a message uses to say what is allowed.
ALLOWED_WORDS = ("allowed", "range", "one of", "must", "known", "needs", "expected",
                 "give ", "is in ", "is not a", "not in", "instead", "write ", "only",
                 "choose from", "invalid float value", "invalid int value", "no such file",
                 "does not exist")


@dataclass(frozen=True)
class Case:
    entry: str  # the public entry point
    field: str  # the field the message must name
    label: str  # what is wrong, for the test id
    value: Any  # the bad value (the message must show it)
    call: Callable[[], Any]
    cli: bool = False


def _value_tokens(value) -> list[str]:
    """Spellings of ``value`` a message may use."""
    if isinstance(value, str):
        try:  # a number typed on the command line, as Python writes it back
            return [value, repr(float(value)), f"{float(value):g}"]
        except ValueError:
            return [value]
    if value is None:
        return ["None"]
    if isinstance(value, bool):
        return [str(value), str(value).lower()]
    if isinstance(value, float | int):
        if math.isnan(value):
            return ["nan"]
        return [repr(value), f"{value:g}", str(value)]
    if isinstance(value, dict):
        return ["{", "dict", *[repr(k) for k in value]]
    arr = np.asarray(value, dtype=object)
    if arr.size == 0:
        return ["empty", "[]"]
    flat = [v for v in arr.ravel() if isinstance(v, float) and math.isnan(v)]
    if flat:
        return ["nan"]
    elements = [t for v in arr.ravel() if isinstance(v, float | int)
                for t in (repr(float(v)), f"{float(v):g}")]  # a list's bad element, named
    return [repr(value), str(list(value)) if isinstance(value, tuple) else str(value),
            "list", "array", "one value", "single", "twice", "duplicate", *elements]


def _names_field(msg: str, field: str) -> bool:
    return re.search(r"(?<![\w])" + re.escape(field) + r"(?![\w])", msg) is not None


def judge(case: Case) -> tuple[str, str]:
    """``("clear" | "unclear" | "accepted", detail)`` for one case."""
    if case.cli:
        return _judge_cli(case)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a warning alone is not a refusal
        try:
            case.call()
        except (ValueError, TypeError) as exc:
            msg = str(exc)
        except Exception as exc:  # noqa: BLE001 - anything else is unclear by definition
            return "unclear", f"{type(exc).__name__}: {exc}"
        else:
            return "accepted", "no error"
    return _judge_message(case, msg)


def _judge_message(case: Case, msg: str) -> tuple[str, str]:
    missing = []
    if not _names_field(msg, case.field):
        missing.append(f"the field {case.field!r}")
    if not any(t in msg for t in _value_tokens(case.value)):
        missing.append(f"the value {case.value!r}")
    if not any(w in msg for w in ALLOWED_WORDS):
        missing.append("what is allowed")
    if missing:
        return "unclear", f"{msg!r} does not name {', '.join(missing)}"
    return "clear", msg


def _judge_cli(case: Case) -> tuple[str, str]:
    from agglomtool.cli import main

    out, err = io.StringIO(), io.StringIO()
    with warnings.catch_warnings(), contextlib.redirect_stdout(out), \
            contextlib.redirect_stderr(err):
        warnings.simplefilter("ignore")
        try:
            rc = main(case.call())
        except BaseException as exc:  # noqa: BLE001 - an escape is a traceback
            return "unclear", f"escaped main(): {type(exc).__name__}: {exc}"
    lines = [ln for ln in err.getvalue().splitlines()
             if ln.strip() and not ln.startswith("agglomtool: warning:")]
    if rc == 0:
        return "accepted", f"exit 0; stderr {err.getvalue()!r}"
    errors = [ln for ln in lines if "error" in ln]
    if "Traceback" in err.getvalue() or len(errors) != 1:
        return "unclear", f"exit {rc}; stderr {err.getvalue()!r}"
    verdict, detail = _judge_message(case, errors[0])
    return verdict, f"exit {rc}: {detail}"


# --- the bad values ------------------------------------------------------------------------

def _numeric_bad(lo, hi, lo_open, hi_open, *, inf_ok=False, required=True, length=False,
                 rng=None) -> list[tuple[str, Any]]:
    """Bad values of a numeric field with the range (lo, hi)."""
    out = [("empty-list", []), ("empty-array", np.array([])), ("nan", NAN),
           ("nan-in-array", [1e-3, NAN]), ("-inf", -INF), ("huge", 1e300),
           ("-huge", -1e300), ("string", "x"), ("dict", {}), ("bool", True)]
    if not inf_ok:
        out.append(("inf", INF))
    if required:
        out.append(("None", None))
    if lo is not None:
        out.append(("below", float(lo) if lo_open else float(lo) - 1.0))
        out.append(("negative-random", -float(rng.uniform(1.0, 1e6))))
    if hi is not None and math.isfinite(hi):
        out.append(("above", float(hi) if hi_open else float(hi) + max(1.0, 1e-3 * hi)))
    if length:
        out.append(("parsec", "5 parsec"))
        out.append(("wrong-unit", "5 kg"))
    return out


def _core_cases(rng) -> list[Case]:
    import agglomtool as at

    ok = {
        "Particle": (at.Particle, dict(d=5e-4, rho=2650.0, h0=1e-5, ha=1e-6)),
        "Liquid": (at.Liquid, dict(mu=1e-3, gamma=0.07, rho=1000.0, theta_deg=0.0)),
        "Gas": (at.Gas, dict(mu=1.8e-5, rho=1.2)),
        "Bed": (at.Bed, dict(eps=0.55, U=0.1)),
    }
    ranges = {  # (lo, hi, lo_open, hi_open, inf allowed, a length): docs/inputs.md
        "Particle.d": (0.0, 1e10, True, False, True, True),
        "Particle.rho": (0.0, 1e5, True, False, True, False),
        "Particle.h0": (0.0, 1e10, False, False, False, True),
        "Particle.ha": (0.0, 1e10, False, False, False, True),
        "Liquid.mu": (0.0, 1e30, True, False, False, False),
        "Liquid.gamma": (0.0, 10.0, True, False, False, False),
        "Liquid.rho": (0.0, 1e5, True, False, False, False),
        "Liquid.theta_deg": (0.0, 90.0, False, True, False, False),
        "Gas.mu": (0.0, 1.0, True, False, False, False),
        "Gas.rho": (0.0, 1e5, True, False, False, False),
        "Bed.eps": (0.0, 1.0, True, True, False, False),
        "Bed.U": (0.0, MAX_CORE_SPEED, False, False, False, False),
    }
    cases = []
    for full, (lo, hi, lo_open, hi_open, inf_ok, length) in ranges.items():
        cls_name, name = full.split(".")
        cls, good = ok[cls_name]
        for label, bad in _numeric_bad(lo, hi, lo_open, hi_open, inf_ok=inf_ok, length=length,
                                       required=full != "Bed.U", rng=rng):
            kw = {**good, name: bad}
            cases.append(Case(cls_name, full, label, bad,
                              functools.partial(lambda c, k: c(**k), cls, kw)))
    return cases


def _pair():
    import agglomtool as at

    p = at.Particle(d=5e-4, rho=2650.0, h0=1e-5, ha=1e-6)
    return dict(p_i=p, p_j=p, liquid=at.Liquid(mu=1e-3, gamma=0.07, rho=1000.0),
                gas=at.Gas(mu=4.4e-5, rho=0.33), bed=at.Bed(eps=0.55, U=0.1))


def _collide_cases(rng) -> list[Case]:
    import agglomtool as at

    cases = []

    def add(entry, func, field, label, bad, **extra):
        def call():
            kw = {**_pair(), **extra, field: bad}
            return func(kw.pop("p_i"), kw.pop("p_j"), **kw)
        cases.append(Case(entry, field, label, bad, call))

    numeric = {"u0": (0.0, MAX_CORE_SPEED, True, False),
               "u0_j": (-MAX_CORE_SPEED, MAX_CORE_SPEED, False, False),
               "beta_deg": (-3600.0, 3600.0, False, False), "e": (0.0, 1.0, False, False)}
    for field, (lo, hi, lo_open, hi_open) in numeric.items():
        for label, bad in _numeric_bad(lo, hi, lo_open, hi_open, required=field != "u0_j",
                                       rng=rng):
            add("collide", at.collide, field, label, bad,
                **({} if field == "u0" else {"u0": 0.5}))
    for field, bads in {"mode": ["nope", None, 3, ["paper"]],
                        "drag_slip": ["nope", None, 1],
                        "body_forces": ["yes", None, 1.5],
                        "details": ["yes", None, 2.0],
                        "tol": ["x", NAN, -1.0, 1e300, [], {}]}.items():
        for bad in bads:
            extra = {"u0": 0.5, "mode": "auto"} if field == "tol" else {"u0": 0.5}
            add("collide", at.collide, field, f"{type(bad).__name__}-{bad!r}", bad, **extra)
    for field, bads in {"p_i": ["x", None, 1.0], "p_j": [{}, None],
                        "liquid": ["water", None], "gas": ["air", 1.2], "bed": ["x", 0.55]}.items():
        for bad in bads:
            add("collide", at.collide, field, f"{type(bad).__name__}", bad, u0=0.5)
    crit = {"rtol": ["x", NAN, -1.0, 0.0, 1e300, [], {}, None, [1e-6, 1e-5]],
            "u_max": ["x", NAN, -1.0, 0.0, 1e300, [], {}, [1.0, 2.0]],
            "tol": ["x", NAN, -1.0, []],
            "beta_deg": [NAN, 1e300, "x", [], 3601.0],
            "e": [NAN, 1e300, -0.5, "x", []],
            "mode": ["nope", None]}
    for field, bads in crit.items():
        for bad in bads:
            extra = {"mode": "auto"} if field == "tol" else {}
            add("critical_impact_speed", at.critical_impact_speed, field,
                f"{type(bad).__name__}-{bad!r}", bad, **extra)
    return cases


#: The physical range of each numeric Scene field, as the documentation states it
#: (docs/inputs.md): (lo, hi, lo_open, hi_open). Values just outside are refused.
SCENE_RANGES = {
    "T": (0.0, 1e4, True, False), "P": (0.0, 1e9, True, False),
    "U": (0.0, 1e3, False, False), "U_Umf": (0.0, 1e4, True, False),
    "eps": (0.0, 1.0, True, True), "U_e_Umf": (0.0, 1e4, False, False),
    "d_i": (0.0, 1e3, True, False), "d_j": (0.0, 1e3, True, False),
    "h0": (0.0, 1e3, False, False), "h0_j": (0.0, 1e3, False, False),
    "ha_i": (0.0, 1e3, False, False), "ha_j": (0.0, 1e3, False, False),
    "e": (0.0, 1.0, False, False), "theta_deg": (0.0, 90.0, False, True),
    "beta_deg": (-90.0, 90.0, False, False), "u0": (0.0, 1e3, True, False),
    "sigma_ln": (0.0, 10.0, True, False), "granular_temperature": (0.0, 1e6, True, False),
    "fluctuation_ratio": (0.0, 1e3, True, False), "u_ceiling": (0.0, 1e3, True, False),
    "bed_height": (0.0, 1e3, True, False), "column_diameter": (0.0, 1e3, True, False),
    "orifice_area": (0.0, 1e6, False, False), "height": (0.0, 1e3, True, False),
    "wake_fraction": (0.0, 10.0, True, False),
}


def _scene_ranges():
    return SCENE_RANGES


def _scene_cases(rng) -> list[Case]:
    import agglomtool as at
    from agglomtool._fields import DEFAULTS, FIELD_META

    cases = []
    derived = {k for k, v in DEFAULTS.items() if v is None}
    ranges = _scene_ranges()
    for field, (lo, hi, lo_open, hi_open) in ranges.items():
        length = FIELD_META[field][0] == "m"
        bads = _numeric_bad(lo, hi, lo_open, hi_open, required=field not in derived,
                            length=length, rng=rng)
        bads += [("list-for-scalar", [1.0, 2.0]), ("tuple-for-scalar", (0.5, 0.6))]
        for label, bad in bads:
            cases.append(Case("Scene", field, label, bad,
                              functools.partial(lambda k: at.Scene(**k), {field: bad})))
    for field in ("gas", "solid_i", "solid_j", "liquid", "speed", "mode", "drag_slip",
                  "umf_method"):
        for bad in ("nope", 3, ["air"], {}) + ((None,) if field not in derived else ()):
            cases.append(Case("Scene", field, f"{type(bad).__name__}", bad,
                              functools.partial(lambda k: at.Scene(**k), {field: bad})))
    for bad in ("yes", 1, None, [True]):
        cases.append(Case("Scene", "body_forces", f"{type(bad).__name__}", bad,
                          functools.partial(lambda k: at.Scene(**k), {"body_forces": bad})))
    # unit strings a person types: absurd conversions, wrong dimensions
    units = {"h0": ["5 parsec", "5 km", "5 kg", "1e400 m", "-5 um"],
             "d_i": ["5 parsec", "1e400 m", "5 s", "-500 um"],
             "T": ["5 kg", "-300 degC", "1e9 K", "-5 K"],
             "P": ["-1 bar", "1e20 bar", "5 m"],
             "U": ["1e9 m/s", "5 kg", "-1 m/s"],
             "u0": ["1e9 km/s", "-1 m/s"],
             "ha_i": ["5 parsec"], "column_diameter": ["5 parsec"], "bed_height": ["3 lightyear"]}
    for field, texts in units.items():
        for text in texts:
            cases.append(Case("Scene (units)", field, text, text,
                              functools.partial(lambda k: at.Scene(**k), {field: text})))
    cases.append(Case("Scene.replace", "nope", "unknown-field", "nope",
                      lambda: at.Scene().replace(nope=1.0)))
    return cases


def _sweep_cases(rng) -> list[Case]:
    import agglomtool as at

    scene = functools.cache(lambda: at.Scene())
    cases = []

    def add(field, label, bad, **kw):
        cases.append(Case("sweep", field, label, bad,
                          functools.partial(lambda k: at.sweep(scene(), **k), kw)))

    grid = {"T": [1000.0, 1100.0]}
    for field, bads in {"nodes": [1.5, 0, -1, "x", None, 1e300, [4]],
                        "compute": ["x", None, 2],
                        "client": ["abc", 1, {}],
                        "chunks": ["x", -1, 0, 1.5, {"nope": 1}, [1]],
                        "progress": ["x", 2],
                        "overwrite": ["x"],
                        "store": [123, {}]}.items():
        for bad in bads:
            add(field, f"{type(bad).__name__}-{bad!r}", bad, **{**grid, field: bad})
    robust = {"uncertain": {"h0": at.LogNormal(2e-7, 5e-8)}}
    for field, bads in {"samples": [1, 0, 1.5, "x", None], "threshold": [1.0, -0.1, NAN, "x"],
                        "seed": ["x", -1, 1.5]}.items():
        for bad in bads:
            add(field, f"{type(bad).__name__}-{bad!r}", bad, **{**grid, **robust, field: bad})
    for field, shown, bad in (("uncertain", "x", "x"),
                              ("nope", "nope", {"nope": at.Normal(1.0, 0.1)}),
                              ("h0", 5.0, {"h0": 5.0}), ("uncertain", 3, 3)):
        add(field, f"uncertain-{type(bad).__name__}", shown, **{**grid, "uncertain": bad})
    cases.append(Case("sweep", "grid", "no-grid", "grid", lambda: at.sweep(scene())))
    axes = {"T": 1e300, "d_i": -1.0, "h0": 5.0 * 3.0857e16, "U": 1e300, "eps": 1.5,
            "P": 0.0, "u0": NAN}
    for field, bad in axes.items():
        for label, values in (("empty", []), ("one-bad", [bad]), ("bad-among-good", None),
                              ("string", "x"), ("dict", {}), ("duplicate", "dup"),
                              ("nested", [[1.0, 2.0]])):
            if values is None:
                good = getattr(scene(), field) or 0.1
                values = [good, bad]
            if values == "dup":
                good = getattr(scene(), field) or 0.1
                values = [good, good]
            shown = bad if label in ("one-bad", "bad-among-good") else values
            add(field, label, shown, **{field: values})
    for field, values in (("gas", ["air", "nope"]), ("mode", ["paper", "nope"]),
                          ("solid_j", []), ("nope", [1.0, 2.0]), ("liquid", ["water", "water"])):
        shown = {"gas": "nope", "mode": "nope", "nope": "nope"}.get(field, values)
        add(field, "names", shown, **{field: values})
    return cases


def _bed_cases(rng) -> list[Case]:
    import agglomtool as at

    cases = []
    good = dict(solid="silica-sand", fraction=1.0, d50=500e-6, gsd=1.5, classes=3)
    for field, bads in {"fraction": [NAN, -0.1, 1.5, "x", [], None, [0.5, 0.5]],
                        "d50": [NAN, -1.0, 0.0, 1e300, "x", [], "5 parsec", INF],
                        "gsd": [NAN, 0.5, 11.0, "x", [], INF],
                        "classes": [0, 1.5, "x", 1000, None, [3]],
                        "h0": [NAN, -1.0, 1e300, "x", [], "5 parsec", INF],
                        "ha": [NAN, -1.0, 1e300, "x", "5 parsec"],
                        "solid": ["nope", None, 3, ["silica-sand"]]}.items():
        for bad in bads:
            kw = {**good, field: bad}
            cases.append(Case("Component", field, f"{type(bad).__name__}-{bad!r}", bad,
                              functools.partial(lambda k: at.Component(**k), kw)))
    explicit = dict(solid="silica-sand", fraction=1.0)
    for field, bads in {"d": [[], np.array([]), [NAN], [-1e-4], [1e300], "x",
                              [4e-4, 4e-4], [4e-4, 5e-4, 4e-4], [[4e-4]], ["5 parsec"], INF],
                        "d_fractions": [[], [NAN], [0.5], [1.5, -0.5], "x", [0.5, 0.6]]}.items():
        for bad in bads:
            kw = {**explicit, "d": [4e-4, 6e-4] if field == "d_fractions" else bad}
            if field == "d_fractions":
                kw["d_fractions"] = bad
            cases.append(Case("Component", field, f"{type(bad).__name__}-{bad!r}", bad,
                              functools.partial(lambda k: at.Component(**k), kw)))
    comp = functools.cache(lambda: at.Component(solid="silica-sand", fraction=1.0, d50=5e-4))
    half = functools.cache(lambda: at.Component(solid="ilmenite", fraction=0.5, d50=2e-4))
    scene = functools.cache(lambda: at.Scene())

    def add(entry, func, field, label, bad, *, components=None, **kw):
        def call():
            comps = comp() if components == "bare" else (
                [comp()] if components is None else components())
            return func(scene(), comps, **kw)
        cases.append(Case(entry, field, label, bad, call))

    for entry, func in (("bed_propensity", at.bed_propensity), ("bed_sweep", at.bed_sweep)):
        grid = {"T": [1000.0, 1100.0]} if entry == "bed_sweep" else {}
        add(entry, func, "components", "bare-component", "Component", components="bare",
            **grid)
        add(entry, func, "components", "empty", [], components=lambda: [], **grid)
        add(entry, func, "components", "not-components", "x", components=lambda: ["x"], **grid)
        add(entry, func, "fraction", "fractions-sum", 0.5, components=lambda: [half()], **grid)
        add(entry, func, "components", "duplicate", "component 1",
            components=lambda: [half(), half()], **grid)
        for field, bads in {"nodes": [0, 1.5, "x", -3], "directions": [0, 1.5, "x", -1]}.items():
            for bad in bads:
                add(entry, func, field, f"{type(bad).__name__}-{bad!r}", bad,
                    **{**grid, field: bad})
    for bad in ("nope", 5, 1.5):
        add("bed_sweep", at.bed_sweep, "mix", f"{type(bad).__name__}", bad,
            fraction=[0.2, 0.4], mix=bad)
    for field, values in (("T", []), ("T", [NAN]), ("h0", ["5 parsec"]), ("d_i", [1e-4, 2e-4]),
                          ("fraction", [0.2, 1.5]), ("U_Umf", [1e300]), ("T", [1000.0, 1000.0])):
        shown = {"d_i": "d_i", "fraction": 1.5}.get(field, values[0] if values and values[0]
                                                    != 1000.0 else values)
        add("bed_sweep", at.bed_sweep, field, f"grid-{values!r}", shown,
            **({field: values} if field != "fraction" else {field: values, "mix": 0}))
    return cases


def _uncertainty_cases(rng) -> list[Case]:
    import agglomtool as at

    cases = []
    scene = functools.cache(lambda: at.Scene())
    law = functools.cache(lambda: at.LogNormal(2e-7, 5e-8))

    def mc(**kw):
        base = {"uncertain": {"h0": law()}, "n": 16, "seed": 0}
        return at.monte_carlo(scene(), **{**base, **kw})

    for field, bads in {"n": [0, -1, 1.5, "x", None, 1e300],
                        "seed": ["x", -1, 1.5, [1, 2]],
                        "uncertain": [{}, {"nope": at.Normal(1.0, 0.1)}, {"h0": 5.0}, "x", None,
                                      {"h0": "x"}],
                        "quantiles": [[1.5], [NAN], "x", []],
                        "bins": [0, -1, "x", [], [NAN, 1.0]]}.items():
        for bad in bads:
            shown = bad if field != "uncertain" or not isinstance(bad, dict) else (
                next(iter(bad), "uncertain") if bad else {})
            fld = field
            if field == "uncertain" and isinstance(bad, dict) and bad:
                fld = next(iter(bad))
                shown = fld if fld == "nope" else bad[fld]
            cases.append(Case("monte_carlo", fld, f"{type(bad).__name__}-{bad!r}", shown,
                              functools.partial(lambda k: mc(**k), {field: bad})))
    for name, call, field, bad in (
            ("Normal", lambda: at.Normal(NAN, 1.0), "mean", NAN),
            ("Normal", lambda: at.Normal(1.0, -1.0), "sd", -1.0),
            ("Normal", lambda: at.Normal("x", 1.0), "mean", "x"),
            ("LogNormal", lambda: at.LogNormal(-1.0, 0.5), "mean", -1.0),
            ("LogNormal", lambda: at.LogNormal(1.0, NAN), "sd", NAN),
            ("LogNormal", lambda: at.LogNormal([], 0.5), "mean", []),
            ("Uniform", lambda: at.Uniform(2.0, 1.0), "high", 1.0),
            ("Uniform", lambda: at.Uniform(NAN, 1.0), "low", NAN),
            ("Uniform", lambda: at.Uniform(1.0, INF), "high", INF),
            ("Normal", lambda: at.Normal(1.0, 0.1, units="parsecs of nothing"), "units",
             "parsecs of nothing")):
        cases.append(Case(name, field, f"{field}-{bad!r}", bad, call))

    def cmp(**kw):
        return at.compare(scene(), **{"n": 16, "seed": 0, **kw})

    for label, field, bad, kw in (
            ("no-option", "option", "option", {}),
            ("two-fields", "h0", "h0", {"h0": [1e-7, 2e-7], "T": [1000.0, 1100.0]}),
            ("one-option", "h0", [1e-7], {"h0": [1e-7]}),
            ("unknown-field", "nope", "nope", {"nope": [1, 2]}),
            ("unknown-name", "solid_j", "nope", {"solid_j": ["silica-sand", "nope"]}),
            ("nan-option", "h0", NAN, {"h0": [1e-7, NAN]}),
            ("parsec-option", "h0", "5 parsec", {"h0": [1e-7, "5 parsec"]}),
            ("duplicate-options", "h0", [1e-7, 1e-7], {"h0": [1e-7, 1e-7]}),
            ("n-zero", "n", 0, {"h0": [1e-7, 2e-7], "n": 0}),
            ("n-string", "n", "x", {"h0": [1e-7, 2e-7], "n": "x"}),
            ("n-float", "n", 1.5, {"h0": [1e-7, 2e-7], "n": 1.5}),
            ("seed-string", "seed", "x", {"h0": [1e-7, 2e-7], "seed": "x"}),
            ("bins-one", "bins", 1, {"h0": [1e-7, 2e-7], "bins": 1}),
            ("uncertain-string", "uncertain", "x", {"h0": [1e-7, 2e-7], "uncertain": "x"}),
            ("scene-not-scene", "scene", "x", None)):
        if kw is None:
            cases.append(Case("compare", field, label, bad,
                              lambda: at.compare("x", h0=[1e-7, 2e-7])))
        else:
            cases.append(Case("compare", field, label, bad,
                              functools.partial(lambda k: cmp(**k), kw)))
    return cases


def _materials_cases(rng) -> list[Case]:
    from agglomtool import materials

    cases = []
    for func, kind in ((materials.solid, "solid"), (materials.gas, "gas"),
                       (materials.liquid_entry, "liquid")):
        for bad in ("nope", 3, None, ["x"]):
            cases.append(Case(f"materials.{func.__name__}", kind, f"{kind}-{bad!r}", bad,
                              functools.partial(func, bad)))
    for bad in ("nope", 3, None):
        cases.append(Case("materials.names", "kind", f"{bad!r}", bad,
                          functools.partial(materials.names, bad)))
    for field, bads in {"T": [NAN, -1.0, 1e300, "x", [], {}, [1000.0, NAN]],
                        "P": [NAN, -1.0, 1e300, "x", []],
                        "theta_deg": [NAN, 95.0, "x"]}.items():
        for bad in bads:
            kw = {"T": 300.0, field: bad}
            cases.append(Case("materials.liquid", field, f"{type(bad).__name__}-{bad!r}", bad,
                              functools.partial(lambda k: materials.liquid("water", **k), kw)))
    for bad in (NAN, -1.0, 1e300, "x", []):
        cases.append(Case("materials.liquid", "T", f"melt-{bad!r}", bad,
                          functools.partial(lambda b: materials.liquid("hypothetical-slag", T=b),
                                            bad)))
    return cases


def _units_cases(rng) -> list[Case]:
    from agglomtool.units import to_si, to_si_array

    cases = []
    for text in ("5 foo", "five um", "", "5 kg", "um 5", "5 um um", "--5 um"):
        cases.append(Case("units.to_si", "h0", repr(text), text,
                          functools.partial(to_si, "h0", text, "m")))
    for values in (["5 um", "5 kg"], ["5 foo"]):
        bad = values[-1]
        cases.append(Case("units.to_si_array", "d_i", repr(values), bad,
                          functools.partial(to_si_array, "d_i", values, "m")))
    return cases


@functools.cache
def _small_map():
    """A two-point map in memory and in a netCDF file (for the map and plot entry points)."""
    import agglomtool as at

    ds = at.sweep(at.Scene(), T=[1000.0, 1100.0], h0=[1e-7, 2e-7])
    path = Path(_tmp()) / "small.nc"
    at.write_map(ds, path)
    return ds, path


@functools.cache
def _tmp() -> str:
    return tempfile.mkdtemp(prefix="agglomtool-fuzz-")


def _map_cases(rng) -> list[Case]:
    import agglomtool as at
    from agglomtool import plots

    cases = []
    for bad in ("x", None, {}, 3):
        cases.append(Case("write_map", "ds", f"{type(bad).__name__}", bad,
                          functools.partial(lambda b: at.write_map(b, Path(_tmp()) / "w.nc"),
                                            bad)))
    for bad in (-1, 10, "x", 1.5, None):
        cases.append(Case("write_map", "complevel", f"{bad!r}", bad,
                          functools.partial(lambda b: at.write_map(
                              _small_map()[0], Path(_tmp()) / "c.nc", complevel=b), bad)))
    for bad in (None, 3, {}):
        cases.append(Case("write_map", "path", f"{type(bad).__name__}", bad,
                          functools.partial(lambda b: at.write_map(_small_map()[0], b), bad)))
    missing = str(Path(_tmp()) / "missing.nc")
    not_nc = Path(_tmp()) / "not-a-map.nc"
    for label, bad in (("missing", missing), ("none", None), ("int", 3),
                       ("not-netcdf", str(not_nc))):
        def call(b=bad):
            not_nc.write_text("not a netCDF file")
            return plots.open_map(b)
        # a file is named by its path
        cases.append(Case("open_map", bad if isinstance(bad, str) else "ds", label, bad, call))
    for field, bad in (("var", "nope"), ("x", "nope"), ("y", "nope"), ("col", "nope"),
                       ("sel", {"nope": 1.0}), ("sel", {"T": 1e300}), ("sel", {"T": "x"}),
                       ("var", 3), ("x", ["T"])):
        shown = bad if not isinstance(bad, dict) else next(iter(bad)) if "nope" in bad \
            else next(iter(bad.values()))
        fld = field if not (isinstance(bad, dict) and "nope" in bad) else "nope"
        if isinstance(bad, dict) and "T" in bad:
            fld = "T"
        for entry, func in (("plots.operating_window", plots.operating_window),
                            ("plots.plan_layout", plots.plan_layout)):
            def call(f=func, fl=field, b=bad):
                return f(_small_map()[0], **{fl: b})
            cases.append(Case(entry, fld, f"{field}-{bad!r}", shown, call))
    return cases


def _cli_cases(rng) -> list[Case]:
    cases = []
    tmp = Path(_tmp())

    def add(entry, field, label, value, argv):
        cases.append(Case(f"cli {entry}", field, label, value, lambda a=argv: list(a),
                          cli=True))

    flags = {"T": ["nan", "-1", "1e300", "5 parsec", "x", "-300 degC"],
             "d-i": ["nan", "-1", "1e300", "5 parsec", "x", "inf"],
             "h0": ["5 parsec", "1e300", "-1e-6", "nan"],
             "u0": ["1e300", "-1", "nan", "x"],
             "P": ["0", "-1 bar", "x"],
             "eps": ["1.5", "0", "nan"],
             "e": ["2", "-1"],
             "beta-deg": ["1e300", "91"],
             "u-ceiling": ["0", "1e300", "-1"],
             "solid-i": ["nope"], "gas": ["nope"], "liquid": ["nope"]}
    for flag, values in flags.items():
        field = flag.replace("-", "_")
        for v in values:
            add("collide", field, f"--{flag}={v}", v if field not in (
                "solid_i", "gas", "liquid") else v, ["collide", f"--{flag}={v}"])
    for v in ("1e300", "nan", "-91", "x", "inf"):
        add("reference", "beta", f"--beta={v}", v, ["reference", "--beta", v])
    add("reference", "mode", "--mode=nope", "nope", ["reference", "--mode", "nope"])
    configs = {
        "no-grid": ('[scene]\nT = 1000.0\n', "grid", "grid"),
        "empty-axis": ('[grid]\nT = []\n', "T", "[]"),
        "huge-axis": ('[grid]\nT = [1e300]\n', "T", "1e+300"),
        "parsec": ('[scene]\nh0 = "5 parsec"\n[grid]\nT = [1000.0, 1100.0]\n', "h0",
                   "5 parsec"),
        "nodes": ('[grid]\nT = [1000.0]\n[options]\nnodes = 1.5\n', "nodes", 1.5),
        "dup": ('[grid]\nT = [1000.0, 1000.0]\n', "T", "1000"),
        "list-scene": ('[scene]\nU = [1.0, 2.0]\n[grid]\nT = [1000.0]\n', "U", "[1.0, 2.0]"),
    }
    for label, (text, field, value) in configs.items():
        path = tmp / f"map-{label}.toml"
        path.write_text(text)
        add("map", field, label, value, ["map", str(path), "-o", str(tmp / f"{label}.nc")])
    add("map", str(tmp / "none.toml"), "missing-config", str(tmp / "none.toml"),
        ["map", str(tmp / "none.toml"), "-o", str(tmp / "none.nc")])
    beds = {
        "bare-component": ('[component]\nsolid = "silica-sand"\nfraction = 1.0\nd50 = 5e-4\n',
                           "component", "component"),
        "dup-classes": ('[[component]]\nsolid = "silica-sand"\nfraction = 1.0\n'
                        'd = [4e-4, 4e-4]\n', "d", "0.0004"),
        "sum": ('[[component]]\nsolid = "silica-sand"\nfraction = 0.5\nd50 = 5e-4\n',
                "fraction", "0.5"),
        "parsec": ('[[component]]\nsolid = "silica-sand"\nfraction = 1.0\nd50 = "5 parsec"\n',
                   "d50", "5 parsec"),
        "empty-d": ('[[component]]\nsolid = "silica-sand"\nfraction = 1.0\nd = []\n', "d",
                    []),
    }
    for label, (text, field, value) in beds.items():
        path = tmp / f"bed-{label}.toml"
        path.write_text(text)
        add("bed", field, label, value, ["bed", str(path), "-o", str(tmp / f"bed-{label}.nc")])

    def plot_argv(*extra):
        return ["plot", "@MAP@", "-o", str(tmp / "p.png"), *extra]
    for label, field, value, extra in (("var", "var", "nope", ["--var", "nope"]),
                                       ("x", "x", "nope", ["--x", "nope"]),
                                       ("sel", "nope", "nope", ["--sel", "nope=1"]),
                                       ("sel-huge", "T", "1e+300", ["--sel", "T=1e300"]),
                                       ("sel-form", "sel", "T", ["--sel", "T"])):
        argv = plot_argv(*extra)
        cases.append(Case("cli plot", field, label, value,
                          lambda a=argv: [str(_small_map()[1]) if x == "@MAP@" else x
                                          for x in a], cli=True))
    add("plot", str(tmp / "none.nc"), "missing-map", str(tmp / "none.nc"),
        ["plot", str(tmp / "none.nc"), "-o", str(tmp / "p.png")])
    cmp_path = tmp / "cmp.toml"
    cmp_path.write_text('[compare]\nh0 = [1e-7, 2e-7]\n')
    for v in ("0", "-1"):
        add("compare", "n", f"-n {v}", v, ["compare", str(cmp_path), "-n", v])
    return cases


@functools.cache
def all_cases() -> tuple[Case, ...]:
    rng = np.random.default_rng(SEED)
    out = []
    for make in (_core_cases, _collide_cases, _scene_cases, _sweep_cases, _bed_cases,
                 _uncertainty_cases, _materials_cases, _units_cases, _map_cases, _cli_cases):
        out += make(rng)
    return tuple(out)


def _case_id(case: Case) -> str:
    text = f"{case.entry}:{case.field}:{case.label}"
    return re.sub(r"[^\w.:=+\-\[\]]+", "_", text)[:90]


def _ids():
    seen = {}
    out = []
    for c in all_cases():
        k = _case_id(c)
        seen[k] = seen.get(k, 0) + 1
        out.append(k if seen[k] == 1 else f"{k}#{seen[k]}")
    return out


def test_the_fuzz_has_600_cases_over_every_entry_point():
    entries = {c.entry.split(" ")[0] if c.cli else c.entry for c in all_cases()}
    assert len(all_cases()) >= 600, len(all_cases())
    for needed in ("Particle", "Liquid", "Gas", "Bed", "collide", "critical_impact_speed",
                   "Scene", "sweep", "Component", "bed_propensity", "bed_sweep", "monte_carlo",
                   "compare", "write_map", "open_map", "plots.operating_window", "cli"):
        assert needed in entries, needed


@pytest.mark.parametrize("index", range(len(all_cases())), ids=_ids())
def test_bad_input_is_refused_clearly(index):
    case = all_cases()[index]
    verdict, detail = judge(case)
    assert verdict == "clear", f"{case.entry} {case.field} = {case.value!r}: {verdict}: {detail}"


def summary() -> dict:
    """``{entry: {"clear": n, "unclear": n, "accepted": n}}`` over every case."""
    counts: dict = {}
    for case in all_cases():
        verdict, detail = judge(case)
        row = counts.setdefault(case.entry, {"clear": 0, "unclear": 0, "accepted": 0})
        row[verdict] += 1
        if verdict != "clear":
            print(f"  {verdict}: {case.entry} {case.field} {case.label}: {detail[:200]}",
                  file=sys.stderr)
    return counts


if __name__ == "__main__":
    totals = {"clear": 0, "unclear": 0, "accepted": 0}
    for entry, row in summary().items():
        print(f"{entry:28s} {sum(row.values()):4d}  clear {row['clear']:4d}  "
              f"unclear {row['unclear']:3d}  accepted {row['accepted']:3d}")
        for k in totals:
            totals[k] += row[k]
    print(f"{'total':28s} {sum(totals.values()):4d}  clear {totals['clear']:4d}  "
          f"unclear {totals['unclear']:3d}  accepted {totals['accepted']:3d}")
