"""Metadata of the files agglomtool writes: units, long names and flags of every variable,
and the global attributes, so that a map or a bed file is CF-1.8 netCDF.

Units are strings that both UDUNITS (the CF units library) and pint parse: ``"1"`` for a
dimensionless number (UDUNITS rejects pint's ``"dimensionless"``), ``"m/s"``, ``"Pa*s"``,
``"kg/m**3"``, ``"degree"``. Names (solids, liquids, model tiers, components) carry no units.
Integer codes carry ``flag_values`` (of the variable's own type) and ``flag_meanings``
(blank-separated words), as CF section 3.5 asks. No CF standard name describes these
quantities (a bed's temperature, an impact speed, a coalescence efficiency), so none is set.
"""

from __future__ import annotations

import datetime
import json

import numpy as np

from .._version import __version__
from ..bed.speed_models import SPEED_FLAGS
from ..collision.outcome import Stage
from ..scene import CA_VISCOUS, FIELD_META, U_STAR_FLAGS

__all__ = ["VARIABLE_META", "ANCILLARY", "FIELD_META", "FLAGS", "CONVENTIONS", "REFERENCES",
           "variable_attrs", "field_attrs", "cf_units", "global_attrs", "provenance_attr",
           "call_text", "history_line"]

#: The metadata conventions the files follow.
CONVENTIONS = "CF-1.8"

#: The model's reference (the files' ``references`` attribute).
REFERENCES = ("Shabanian, Duchesne, Syamlal and Runstedtler (2024), Heliyon 10:e29397, "
              "doi:10.1016/j.heliyon.2024.e29397")

#: name -> (units, long_name, description)
VARIABLE_META = {
    "mu_g": ("Pa*s", "gas viscosity", "gas_properties(T, P, gas)"),
    "rho_g": ("kg/m**3", "gas density", "gas_properties(T, P, gas)"),
    "mu_l": ("Pa*s", "coating liquid viscosity", "materials.liquid(liquid, T, P)"),
    "gamma_l": ("N/m", "coating liquid surface tension", "materials.liquid(liquid, T, P)"),
    "rho_l": ("kg/m**3", "coating liquid density", "materials.liquid(liquid, T, P)"),
    "Umf": ("m/s", "minimum fluidization velocity",
            "larger U_mf of the two wet particles (umf_method)"),
    "U_e": ("m/s", "emulsion gas velocity used in the drag", "U_e_Umf * Umf"),
    "U": ("m/s", "superficial gas velocity", "U, or U_Umf * Umf"),
    "u_star": ("m/s", "critical impact speed u0*",
               "smallest head-on impact speed at which the pair rebounds; inf: the pair "
               "sticks at every speed up to the ceiling u_ceiling (u_star_flag = 2); 0: no "
               "bridge forms (u_star_flag = 1)"),
    "u_star_flag": ("1", "what u0* means at this point",
                    "; ".join(f"{k}: {v[1]}" for k, v in U_STAR_FLAGS.items())),
    "Ca_star": ("1", "capillary number at u0*", "mu_l * 2 u0* / gamma_l"),
    "regime": ("1", "regime at u0* (0 capillary-, 1 viscous-limited)",
               f"viscous-limited where Ca_star > {CA_VISCOUS:g}"),
    "u_typical": ("m/s", "typical (median) impact speed", "median of the speed distribution"),
    "St": ("1", "viscous Stokes number at the typical speed",
           "m_r 2 u_typical / (1.5 pi mu_l r**2)"),
    "e_w": ("1", "wet restitution coefficient at the typical speed", "0 where the pair sticks"),
    "agglomerated": ("1", "sticks at the typical speed",
                     "e_w == 0; false also where speed_flag is not 0 (no impact speed: "
                     "neither outcome, e_w is NaN there)"),
    "stage": ("1", "stage where the outcome at the typical speed was decided",
              "agglomtool.Stage code"),
    "propensity": ("1", "agglomeration propensity",
                   "probability that a collision sticks over the impact-speed distribution"),
    "margin": ("1", "speed margin u_typical / u0*",
               "< 1: typical collisions are slower than the critical speed"),
    "speed_flag": ("1", "whether the impact-speed model has an answer at this point",
                   "; ".join(f"{k}: {v[1]}" for k, v in SPEED_FLAGS.items())
                   + "; where nonzero, every output made of the impact speed is NaN, "
                   "stage is -1 and agglomerated is false"),
}

#: The outputs made of the impact speed: their ``ancillary_variables`` (CF section 3.4)
#: name the flag that says where they have no value and why.
ANCILLARY = {name: "speed_flag" for name in ("u_typical", "St", "e_w", "agglomerated",
                                               "stage", "propensity", "margin")}

#: Coded outputs: name -> (values, blank-separated meanings). ``agglomerated`` is a boolean
#: in memory; in a file it is a byte (0 false, 1 true) that xarray reads back as a boolean.
FLAGS = {
    "stage": ([-1] + [s.value for s in Stage],
              " ".join(["no_impact_speed"] + [s.name.lower() for s in Stage])),
    "u_star_flag": (list(U_STAR_FLAGS), " ".join(v[0] for v in U_STAR_FLAGS.values())),
    "speed_flag": (list(SPEED_FLAGS), " ".join(v[0] for v in SPEED_FLAGS.values())),
    "regime": ([0, 1], "capillary_limited viscous_limited"),
    "agglomerated": ([0, 1], "rebounds sticks"),
}


def cf_units(units: str | None) -> str | None:
    """``units`` as CF writes it: pint's ``"dimensionless"`` is UDUNITS' ``"1"``; ``None``
    (a name, which has no units) stays ``None``; other units are spelled alike in both."""
    return "1" if units == "dimensionless" else units


def variable_attrs(name: str) -> dict:
    """``units``, ``long_name``, ``description``, for coded outputs ``flag_values`` (int8,
    the outputs' type) and ``flag_meanings``, and for the outputs made of the impact speed
    ``ancillary_variables`` (``ANCILLARY``) of output variable ``name``."""
    units, long_name, desc = VARIABLE_META[name]
    attrs: dict[str, str | np.ndarray] = {"units": units, "long_name": long_name,
                                          "description": desc}
    if name in FLAGS:
        values, meanings = FLAGS[name]
        attrs["flag_values"] = np.array(values, dtype=np.int8)
        attrs["flag_meanings"] = meanings
    if name in ANCILLARY:
        attrs["ancillary_variables"] = ANCILLARY[name]
    return attrs


def field_attrs(name: str) -> dict:
    """``units`` and ``long_name`` of a swept Scene field (a coordinate); a field holding
    names (a categorical field) has a long name only."""
    if name in FIELD_META:
        units, long_name = FIELD_META[name]
        return {"units": cf_units(units), "long_name": long_name}
    return {"long_name": f"{name.replace('_', ' ')} (name)"}


def global_attrs(title: str, call: str) -> dict:
    """The CF global attributes of a Dataset that ``call`` made: ``Conventions``,
    ``title``, ``source`` (the tool, its version and the call) and ``references``. The
    ``history`` line is written with the file (:func:`history_line`)."""
    return {"Conventions": CONVENTIONS, "title": title,
            "source": f"agglomtool {__version__}: {call}", "references": REFERENCES}


def provenance_attr(prov: dict) -> str:
    """The ``provenance`` attribute: a JSON object ``{input: {"value", "units", "origin",
    "confidence"}}`` from :func:`agglomtool.scene.provenance`-style tuples (units in CF
    spelling; none for a name). JSON keeps every name and text as it is."""
    out = {}
    for name, (value, units, origin, conf) in prov.items():
        item = {"value": value.item() if isinstance(value, np.generic) else value}
        if units not in (None, "name"):
            item["units"] = cf_units(units)
        item.update(origin=origin, confidence=conf)
        out[name] = item
    return json.dumps(out)


def call_text(func: str, grid: dict, args: tuple = ("scene",), **options) -> str:
    """``func(*args, name=[...], ..., option=value)`` with each grid axis summarised: its
    names, its values (up to 3), or its number of values and range."""
    parts = list(args)
    for k, v in grid.items():
        v = np.asarray(v)
        if v.dtype.kind in "US":
            parts.append(f"{k}={[str(x) for x in v]}")
        elif v.size <= 3:
            parts.append(f"{k}={[float(x) for x in v]}")
        else:
            parts.append(f"{k}=[{v.size} values {float(v.min()):g}-{float(v.max()):g}]")
    parts += [f"{k}={v!r}" for k, v in options.items()]
    return f"{func}({', '.join(parts)})"


def history_line(command: str) -> str:
    """One ``history`` line: the UTC time, ``agglomtool <version>:`` and ``command``."""
    now = datetime.datetime.now(datetime.UTC).replace(microsecond=0)
    return f"{now.isoformat()} agglomtool {__version__}: {command}"
