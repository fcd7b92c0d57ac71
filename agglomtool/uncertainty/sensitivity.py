"""Which uncertain input moves ``e_w`` most: Sobol indices and one-at-a-time spreads.

:func:`sobol_indices` estimates first-order and total Sobol indices of ``e_w`` with SALib
(Sobol' quasi-random design, Saltelli 2010 / Jansen estimators, bootstrap confidence
intervals), optionally for groups of inputs such as both particles' diameters.
:func:`spread_by_input` is the one-at-a-time view: the spread of ``e_w`` when only one
input (group) is uncertain and every other sits at its nominal value.

SALib is imported on first use: it is an optional dependency (``agglomtool[uncertainty]``).
"""

from __future__ import annotations

import zlib
from collections.abc import Mapping

import numpy as np
import xarray as xr

from .._fields import DEFAULT_MODE
from .._version import __version__
from ._inputs import UNCERTAIN_INPUTS, base_inputs, check_names, evaluate_e_w
from ._sampling import _attrs, resolve_seed
from .distributions import Distribution, to_si
from .monte_carlo import monte_carlo

__all__ = ["sobol_indices", "spread_by_input"]

_DIMLESS = "dimensionless"


def _group_list(names: list[str], groups: Mapping[str, tuple[str, ...]] | None):
    """Group label of each input, in the order of ``names``; each input in one group."""
    if groups is None:
        return list(names), list(names)
    label: dict[str, str] = {}
    for g, members in groups.items():
        if isinstance(members, str):
            members = (members,)
        for m in members:
            if m not in names:
                raise ValueError(f"groups[{g!r}] names {m!r}, which is not in uncertain")
            if m in label:
                raise ValueError(f"input {m!r} is in two groups: {label[m]!r} and {g!r}")
            label[m] = g
    missing = [m for m in names if m not in label]
    if missing:
        raise ValueError(f"inputs {missing} are in no group; every uncertain input needs one")
    per_input = [label[m] for m in names]
    unique = list(dict.fromkeys(per_input))
    return per_input, unique


def sobol_indices(
    p_i,
    p_j=None,
    *,
    liquid=None,
    gas=None,
    bed=None,
    u0=None,
    uncertain: Mapping[str, Distribution],
    groups: Mapping[str, tuple[str, ...]] | None = None,
    n_base: int = 2**13,
    seed: int | None = None,
    mode: str = DEFAULT_MODE,
    u0_j=None,
    beta_deg=0.0,
    e=0.9,
    body_forces: bool = True,
    drag_slip: str = "emulsion",
    num_resamples: int = 100,
    conf_level: float = 0.95,
    chunk_size: int = 1_000_000,
) -> xr.Dataset:
    """First-order and total Sobol indices of ``e_w`` over the uncertain inputs.

    Parameters
    ----------
    p_i, p_j, liquid, gas, bed, u0, u0_j, beta_deg, e, body_forces, drag_slip, uncertain, mode
        As for :func:`agglomtool.uncertainty.monte_carlo`: a :class:`~agglomtool.Scene` as
        ``p_i`` with uncertain inputs in the Scene's names, or the core's inputs.
    groups : mapping of str to tuple of str, optional
        Group name -> the inputs that vary together as one factor (SALib groups); every
        uncertain input in exactly one group. Default: each input is its own factor.
    n_base : int
        Base sample size, a power of 2. The model runs ``n_base (2 k + 2)`` times for ``k``
        factors.
    seed : int, optional
        Seed of the scrambled Sobol' design and of the bootstrap (>= 0).
    num_resamples, conf_level
        Bootstrap resamples and confidence level of the ``*_conf`` half-widths.

    Returns
    -------
    xarray.Dataset
        Over dimension ``factor``: ``S1`` (first-order index), ``S1_conf``, ``ST`` (total
        index), ``ST_conf``, all [-]; ``e_w_variance`` and ``e_w_mean`` of the design.

    Notes
    -----
    The unit-hypercube design of SALib's ``sobol.sample`` is mapped to each input through
    the inverse CDF of its law truncated to the input's physical range, so these are the
    same laws :func:`monte_carlo` samples. ``e_w`` is discontinuous (0 where the pair
    sticks); Sobol indices need only a finite variance, but the point mass makes the
    estimators noisier: read the confidence half-widths.

    I. M. Sobol' (2001), Math. Comput. Simul. 55:271-280, doi:10.1016/S0378-4754(00)00270-6;
    A. Saltelli et al. (2010), Comput. Phys. Commun. 181:259-270,
    doi:10.1016/j.cpc.2009.09.018; J. Herman and W. Usher (2017), SALib, J. Open Source
    Softw. 2(9):97, doi:10.21105/joss.00097.
    """
    try:
        from SALib.analyze import sobol as salib_analyze
        from SALib.sample import sobol as salib_sample
    except ImportError as exc:  # pragma: no cover - depends on the install
        raise ImportError(
            "sobol_indices needs SALib: pip install 'agglomtool[uncertainty]' (or SALib>=1.5)"
        ) from exc
    if isinstance(n_base, bool) or not isinstance(n_base, int | np.integer) or n_base < 2 or (
        n_base & (n_base - 1)
    ):
        raise ValueError(f"n_base = {n_base!r} must be a power of 2, >= 2")
    from ..scene import Scene
    from . import scene_mc

    if isinstance(p_i, Scene):  # the Scene's names, properties re-derived per run
        given = [k for k, v in (("p_j", p_j), ("liquid", liquid), ("gas", gas), ("bed", bed),
                                ("u0", u0), ("u0_j", u0_j)) if v is not None]
        if given:
            raise ValueError(f"{given[0]} is given with a Scene: the Scene holds it")
        fields, with_assumed = scene_mc.split_uncertain(uncertain)
        if with_assumed:
            raise ValueError("sobol_indices takes a mapping of Scene field -> distribution; "
                             "'assumed' is for monte_carlo, compare and robust maps (which "
                             "name the input that decides a comparison)")
        laws = {k: scene_mc.field_law(k, uncertain[k]) for k in uncertain}
        scene_base = p_i.values()
        mode = scene_base["mode"]

        def model(draws):
            return scene_mc.scene_e_w(scene_base, draws)[0]

        units = {k: scene_mc.FIELD_META[k][0] for k in uncertain}
    else:
        if not isinstance(uncertain, Mapping) or not uncertain:
            raise ValueError("uncertain must be a non-empty mapping of input name -> "
                             "distribution")
        check_names(uncertain)
        missing = [k for k, v in (("p_j", p_j), ("liquid", liquid), ("gas", gas), ("u0", u0))
                   if v is None]
        if missing:
            raise ValueError(f"{missing[0]} is required (or pass a Scene as the first "
                             "argument)")
        base = base_inputs(p_i, p_j, liquid, gas, bed, u0, u0_j, beta_deg, e, body_forces,
                           drag_slip)
        laws = {k: (to_si(k, uncertain[k], UNCERTAIN_INPUTS[k].units), UNCERTAIN_INPUTS[k].lo,
                    UNCERTAIN_INPUTS[k].hi) for k in uncertain}

        def model(draws):
            return evaluate_e_w(base, draws, mode).e_w

        units = {k: UNCERTAIN_INPUTS[k].units for k in uncertain}
    entropy, _ = resolve_seed(seed)
    names = list(uncertain)
    per_input, factors = _group_list(names, groups)
    dists = {k: laws[k][0] for k in names}

    problem = {"num_vars": len(names), "names": names, "bounds": [[0.0, 1.0]] * len(names)}
    if groups is not None:
        problem["groups"] = per_input
    design_rng = np.random.default_rng(
        np.random.SeedSequence(entropy, spawn_key=(zlib.crc32(b"sobol design"),)))
    u = salib_sample.sample(problem, int(n_base), calc_second_order=False, scramble=True,
                            seed=design_rng)
    tiny = np.finfo(float).eps
    u = np.clip(u, tiny, 1.0 - tiny)
    values = {}
    for k, name in enumerate(names):
        lo, hi = laws[name][1], laws[name][2]
        try:
            values[name] = dists[name].ppf(u[:, k], lo, hi)
        except ValueError as exc:
            raise ValueError(f"uncertain[{name!r}] (range [{lo:g}, {hi:g}] {units[name]}): "
                             f"{exc}") from None
    n_runs = u.shape[0]
    y = np.empty(n_runs)
    for start in range(0, n_runs, chunk_size):
        sl = slice(start, min(start + chunk_size, n_runs))
        y[sl] = model({k: v[sl] for k, v in values.items()})
    si = salib_analyze.analyze(problem, y, calc_second_order=False,
                               num_resamples=int(num_resamples), conf_level=float(conf_level),
                               seed=int(entropy % 2**32))
    members = {f: " ".join(m for m, g in zip(names, per_input, strict=True) if g == f)
               for f in factors}
    ds = xr.Dataset(coords={"factor": ("factor", np.array(factors, dtype=str), _attrs(
        _DIMLESS, "uncertain input or input group"))})
    ds["members"] = ("factor", np.array([members[f] for f in factors], dtype=str),
                     _attrs(_DIMLESS, "inputs in the factor"))
    conf = f"{100 * conf_level:g} % bootstrap confidence half-width of "
    ds["S1"] = ("factor", np.asarray(si["S1"], float), _attrs(_DIMLESS,
                "first-order Sobol index of e_w"))
    ds["S1_conf"] = ("factor", np.asarray(si["S1_conf"], float), _attrs(_DIMLESS, conf + "S1"))
    ds["ST"] = ("factor", np.asarray(si["ST"], float), _attrs(_DIMLESS,
                "total Sobol index of e_w"))
    ds["ST_conf"] = ("factor", np.asarray(si["ST_conf"], float), _attrs(_DIMLESS, conf + "ST"))
    ds["e_w_mean"] = ((), float(y.mean()), _attrs(_DIMLESS, "mean of e_w over the design"))
    ds["e_w_variance"] = ((), float(y.var()), _attrs(_DIMLESS, "variance of e_w over the "
                                                     "design"))
    ds.attrs.update(
        title="Sobol sensitivity indices of e_w",
        agglomtool_version=__version__,
        mode=str(mode),
        seed=entropy,
        n_base=int(n_base),
        n_model_runs=int(n_runs),
        design="SALib.sample.sobol (scrambled Sobol' sequence), mapped through the inputs' "
               "truncated inverse CDFs",
        estimator="SALib.analyze.sobol: S1 after Saltelli et al. (2010), ST after Jansen "
                  "(1999)",
        distributions="; ".join(f"{k} = {dists[k]!r} [{units[k]}]" for k in names),
        salib_version=_salib_version(),
        references="Sobol' (2001) doi:10.1016/S0378-4754(00)00270-6; Saltelli et al. "
                   "(2010) doi:10.1016/j.cpc.2009.09.018; SALib doi:10.21105/joss.00097",
    )
    return ds


def _salib_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("SALib")
    except PackageNotFoundError:  # pragma: no cover
        return "unknown"


def spread_by_input(
    p_i,
    p_j,
    *,
    liquid,
    gas,
    bed=None,
    u0,
    uncertain: Mapping[str, Distribution],
    groups: Mapping[str, tuple[str, ...]] | None = None,
    n: int = 100_000,
    seed: int | None = None,
    mode: str = DEFAULT_MODE,
    **kwargs,
) -> xr.Dataset:
    """One-at-a-time spread of ``e_w``: one input (group) uncertain, the rest nominal.

    Parameters
    ----------
    p_i, p_j, liquid, gas, bed, u0, uncertain, mode, kwargs
        As for :func:`agglomtool.uncertainty.monte_carlo`; every input in ``uncertain``
        that is not the varied factor is fixed at its law's nominal value.
    groups : mapping of str to tuple of str, optional
        Factors varied together (default: each input alone).
    n : int
        Samples per factor.
    seed : int, optional
        Seed (>= 0); the same for every factor, and each input has its own stream.

    Returns
    -------
    xarray.Dataset
        Over ``factor``: ``e_w_std``, ``e_w_iqr`` (interquartile range), ``e_w_mean``,
        ``p_agglomeration`` [-]; plus ``e_w_nominal`` (all inputs nominal) and, over the
        same samples with every input uncertain, ``e_w_std_all``.
    """
    if not isinstance(uncertain, Mapping) or not uncertain:
        raise ValueError("uncertain must be a non-empty mapping of input name -> distribution")
    check_names(uncertain)
    names = list(uncertain)
    per_input, factors = _group_list(names, groups)
    entropy, _ = resolve_seed(seed)
    std, iqr, mean, p_agg = [], [], [], []
    common = dict(p_i=p_i, p_j=p_j, liquid=liquid, gas=gas, bed=bed, u0=u0, n=n, seed=entropy,
                  mode=mode, keep_samples=True, **kwargs)
    for f in factors:
        varied = {m: uncertain[m] for m, g in zip(names, per_input, strict=True) if g == f}
        fixed = {m: uncertain[m] for m in names if m not in varied}
        ds_f = monte_carlo(**_with_nominal(common, fixed), uncertain=varied)
        ew = ds_f["e_w"].values
        q25, q75 = np.quantile(ew, [0.25, 0.75])
        std.append(float(ds_f["e_w_std"]))
        iqr.append(float(q75 - q25))
        mean.append(float(ds_f["e_w_mean"]))
        p_agg.append(float(ds_f["p_agglomeration"]))
    full = monte_carlo(**common, uncertain=uncertain)
    ds = xr.Dataset(coords={"factor": ("factor", np.array(factors, dtype=str), _attrs(
        _DIMLESS, "uncertain input or input group varied alone"))})
    ds["e_w_std"] = ("factor", np.array(std), _attrs(_DIMLESS, "standard deviation of e_w"))
    ds["e_w_iqr"] = ("factor", np.array(iqr), _attrs(_DIMLESS, "interquartile range of e_w"))
    ds["e_w_mean"] = ("factor", np.array(mean), _attrs(_DIMLESS, "mean of e_w"))
    ds["p_agglomeration"] = ("factor", np.array(p_agg), _attrs(
        _DIMLESS, "probability of agglomeration"))
    ds["e_w_nominal"] = ((), float(full["e_w_nominal"]), _attrs(
        _DIMLESS, "e_w at the nominal inputs"))
    ds["e_w_std_all"] = ((), float(full["e_w_std"]), _attrs(
        _DIMLESS, "standard deviation of e_w with every input uncertain"))
    ds.attrs.update(title="One-at-a-time spread of e_w", agglomtool_version=__version__,
                    mode=str(mode), seed=full.attrs["seed"], n_samples_per_factor=int(n))
    return ds


def _with_nominal(common: dict, fixed: Mapping[str, Distribution]) -> dict:
    """``common`` with the inputs in ``fixed`` set to their laws' nominal SI values."""
    from dataclasses import replace

    out = dict(common)
    out["bed"] = base_inputs(out["p_i"], out["p_j"], out["liquid"], out["gas"], out["bed"],
                             None, None, 0.0, 0.9, True, "emulsion")["bed"]
    for name, dist in fixed.items():
        spec = UNCERTAIN_INPUTS[name]
        val = to_si(name, dist, spec.units).nominal
        if spec.target == "call":
            out[spec.field] = val
        else:
            out[spec.target] = replace(out[spec.target], **{spec.field: val})
    return out
