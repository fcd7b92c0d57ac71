"""Monte Carlo propagation of input uncertainty to the wet restitution coefficient.

:func:`monte_carlo` draws the uncertain inputs, evaluates ``e_w`` for every draw with one
vectorised :func:`agglomtool.collide` call per chunk, and returns an ``xarray.Dataset``
holding the samples and their summary: the probability of agglomeration, quantiles and
moments of ``e_w``, and a histogram density of the rebounding ``e_w``.

This is the analysis of Shabanian et al. (2024), Heliyon 10:e29397,
doi:10.1016/j.heliyon.2024.e29397, Section 3.4 (normal inputs, 1e6 samples, Figs. 10-11).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import xarray as xr

from .._fields import DEFAULT_MODE
from .._validate import check_int, check_memory_for, check_range
from .._version import __version__
from ..collision.outcome import Stage
from ._inputs import UNCERTAIN_INPUTS, base_inputs, evaluate_e_w
from ._sampling import _DIMLESS, _SAMPLING, _attrs, _ChunkedDraws, _summary, resolve_seed
from ._sampling import _stream as _stream  # re-exported for callers importing it here
from .distributions import Distribution

__all__ = ["monte_carlo", "e_w_density", "draw_inputs", "resolve_seed", "DEFAULT_QUANTILES"]

#: Quantiles of e_w reported by default [-].
DEFAULT_QUANTILES = (0.01, 0.05, 0.1, 0.25, 0.5, 0.75, 0.9, 0.95, 0.99)


def draw_inputs(uncertain: Mapping[str, Distribution], n: int, entropy: int):
    """Draw ``n`` SI values of every uncertain input, truncated to its physical range.

    The draws of :func:`monte_carlo` with seed ``entropy`` (all at once; see
    :class:`_ChunkedDraws` for the streams).

    Returns
    -------
    values : dict of str to numpy.ndarray
        The draws [SI units of each input].
    resampled : dict of str to int
        How many first draws of each input fell outside its range and were replaced.
    dists : dict of str to Distribution
        The distributions converted to SI.
    """
    draws = _ChunkedDraws(uncertain, n, entropy, n)
    values = {name: np.empty(n) for name in draws.dists}
    for _ in draws.chunks(out=values):
        pass
    return values, dict(draws.resampled), draws.dists


def e_w_density(e_w: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Histogram density of the rebounding part of ``e_w`` [-].

    Parameters
    ----------
    e_w : numpy.ndarray
        Samples of e_w [-]; exact zeros (agglomeration) are the point mass at 0 and are
        left out of the histogram.
    edges : numpy.ndarray
        Bin edges [-], increasing.

    Returns
    -------
    numpy.ndarray
        ``counts / (n * width)``: its integral is the rebound probability ``1 - P_agg``
        (for samples inside the edges), so the density plus the point mass is a
        probability law.
    """
    reb = e_w[e_w > 0.0]
    counts, _ = np.histogram(reb, bins=edges)
    return counts / (e_w.size * np.diff(edges))


def check_summary_options(quantiles, bins) -> None:
    """``quantiles`` (a non-empty 1-D sequence in [0, 1]) and ``bins`` (an integer >= 1 or
    increasing, finite bin edges) of a Monte Carlo summary, before any draw: a
    ``ValueError`` naming the option, its value and what is allowed."""
    q = check_range("quantiles", quantiles, 0.0, 1.0)
    if q.ndim != 1:
        raise ValueError(f"quantiles = {quantiles!r} must be a sequence of numbers in [0, 1]")
    if np.ndim(bins) == 0 and not isinstance(bins, float):
        check_int("bins", bins, 1)
        return
    edges = check_range("bins", bins, 0.0, None)
    if edges.ndim != 1 or edges.size < 2 or np.any(np.diff(edges) <= 0.0):
        raise ValueError(f"bins = {bins!r} is not allowed: a positive integer or increasing "
                         "bin edges (two or more)")


def monte_carlo(
    p_i,
    p_j=None,
    *,
    liquid=None,
    gas=None,
    bed=None,
    u0=None,
    uncertain: Mapping[str, Distribution],
    n: int = 1_000_000,
    seed: int | None = None,
    mode: str = DEFAULT_MODE,
    u0_j=None,
    beta_deg=0.0,
    e=0.9,
    body_forces: bool = True,
    drag_slip: str = "emulsion",
    quantiles=DEFAULT_QUANTILES,
    bins=200,
    keep_samples: bool = True,
    chunk_size: int = 1_000_000,
) -> xr.Dataset:
    """Propagate input uncertainty to ``e_w`` by Monte Carlo sampling.

    Two ways to ask. Of a :class:`~agglomtool.Scene` (an operating point), with uncertain
    inputs named as the Scene names them::

        at.monte_carlo(scene, uncertain={"h0": at.Normal(5e-6, 1e-6), "T": ...}, n=10**5)

    every draw's properties are derived as for a map, and ``e_w`` is evaluated at the
    scene's impact speed (see :func:`agglomtool.uncertainty.scene_mc.scene_monte_carlo`).
    Or of the collision core's own inputs (Particle, Liquid, Gas, Bed), named as below.

    Parameters
    ----------
    p_i, p_j, liquid, gas, bed, u0, u0_j, beta_deg, e, body_forces, drag_slip
        A :class:`~agglomtool.Scene` as ``p_i`` (and nothing else of these), or
        The fixed (nominal) collision, as for :func:`agglomtool.collide` (scalars). Inputs
        named in ``uncertain`` replace the matching field.
    uncertain : mapping of str to Distribution
        Input name -> its law (:class:`Normal`, :class:`LogNormal`, :class:`Uniform`). Names
        are the keys of ``UNCERTAIN_INPUTS``: ``d_i``, ``d_j`` [m], ``rho_i``, ``rho_j``
        [kg/m^3], ``h0_i``, ``h0_j``, ``ha_i``, ``ha_j`` [m], ``mu_l`` [Pa s], ``gamma``
        [N/m], ``rho_l`` [kg/m^3], ``theta_deg`` [degree], ``mu_g`` [Pa s], ``rho_g``
        [kg/m^3], ``eps`` [-], ``U`` [m/s], ``u0``, ``u0_j`` [m/s], ``beta_deg`` [degree],
        ``e`` [-]. Draws outside an input's physical range (a diameter > 0, a coating
        >= 0, ...) are resampled from the truncated law; how many is reported.
    n : int
        Number of samples (>= 2: one has no spread; at most what the memory available
        holds, refused before any draw otherwise).
    seed : int, optional
        Seed of the draws (>= 0). Each input has its own streams derived from ``seed`` and
        its name (one for its draws, one for the replacements of draws outside its range),
        so the same seed gives the same draws of an input whatever else is uncertain, and
        whatever ``chunk_size`` or the number of threads. ``None``: fresh entropy, recorded
        in ``attrs["seed"]``.
    mode : str
        Model tier, passed through to :func:`agglomtool.collide` (``agglomtool.MODES``).
    quantiles : sequence of float
        Quantiles of ``e_w`` to report, in [0, 1].
    bins : int or array
        Number of histogram bins on ``[0, max(e, max e_w)]``, or the bin edges [-].
    keep_samples : bool
        Keep the per-sample inputs, ``e_w`` and stage (False keeps only the summary).
    chunk_size : int
        Samples drawn and evaluated at a time. It bounds the working memory (draws,
        ``collide`` and summary temporaries: a few hundred bytes per sample of a chunk);
        beyond it a run keeps 8 bytes per sample (``e_w``, for exact quantiles) and, with
        ``keep_samples``, the returned samples themselves (8 bytes per uncertain input and
        10 for ``e_w``, ``agglomerated`` and ``stage``). The draws do not depend on it.

    Returns
    -------
    xarray.Dataset
        Per sample (dimension ``sample``): ``e_w``, ``agglomerated``, ``stage`` and every
        uncertain input. Summary: ``p_agglomeration`` and its standard error, ``e_w_mean``,
        ``e_w_std``, ``e_w_nominal`` (the point estimate at the inputs' nominal values),
        ``e_w_quantile`` (``quantile``), ``e_w_density`` (``e_w_bin``, with
        ``e_w_bin_bounds``). Every variable and coordinate has ``units`` and ``long_name``;
        ``attrs`` record the agglomtool version, mode, seed, sample count and truncation.

    Notes
    -----
    Shabanian et al. (2024), Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397,
    Section 3.4. ``e_w`` has a point mass at 0 (agglomeration): ``p_agglomeration`` is
    that mass and ``e_w_density`` the density of the rest, so ``e_w_density`` integrates
    to ``1 - p_agglomeration``. With ``Bed(U=None)`` the emulsion velocity (1.1 Umf of the
    larger particle) is recomputed for every sample from its own diameters.

    Numbers changed after agglomtool 0.1.0, for inputs with draws outside their range only:
    those draws are now replaced with uniforms from a stream of their own rather than from
    the end of the input's stream, so that every stream is read in a single pass (before,
    every input was drawn twice: once to count its draws outside the range). The laws are
    the same; inputs that never leave their range (the paper's Table 4 analyses) give
    bitwise the same samples and results as before. The summary's quantiles, histogram and
    agglomeration probability are those of numpy (``numpy.quantile``, linear), computed
    without sorting the samples.
    """
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 2:
        raise ValueError(f"n = {n!r} is not allowed: the number of draws, an integer; "
                         "allowed: n >= 2 (one draw has no spread, no standard error)")
    check_summary_options(quantiles, bins)
    from ..scene import Scene

    if isinstance(p_i, Scene):
        given = [k for k, v in (("p_j", p_j), ("liquid", liquid), ("gas", gas), ("bed", bed),
                                ("u0", u0), ("u0_j", u0_j)) if v is not None]
        if given:
            raise ValueError(f"{given[0]} is given with a Scene: the Scene holds it (use "
                             "scene.replace(...))")
        from .scene_mc import scene_monte_carlo, uncertain_without_effect

        found = uncertain_without_effect(p_i, uncertain)
        if found:
            raise ValueError(found[1])
        return scene_monte_carlo(p_i, uncertain=uncertain, n=int(n), seed=seed,
                                 chunk_size=int(chunk_size), quantiles=quantiles, bins=bins,
                                 keep_samples=keep_samples)
    missing = [k for k, v in (("p_j", p_j), ("liquid", liquid), ("gas", gas), ("u0", u0))
               if v is None]
    if missing:
        raise ValueError(f"{missing[0]} is required (or pass a Scene as the first argument)")
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, int | np.integer) or (
        chunk_size < 1
    ):
        raise ValueError(f"chunk_size = {chunk_size!r} must be a positive integer")
    q = np.asarray(quantiles, dtype=float)
    if q.ndim != 1 or np.any(~((q >= 0.0) & (q <= 1.0))):
        raise ValueError(f"quantiles = {quantiles!r} must be a sequence of numbers in [0, 1]")
    if not isinstance(uncertain, Mapping) or not uncertain:
        raise ValueError(f"uncertain = {uncertain!r} is not allowed: a non-empty mapping of "
                         "input name -> distribution")
    n = int(n)
    chunk = int(min(chunk_size, n))
    base = base_inputs(p_i, p_j, liquid, gas, bed, u0, u0_j, beta_deg, e, body_forces,
                       drag_slip)
    entropy, chosen = resolve_seed(seed)
    draws = _ChunkedDraws(uncertain, n, entropy, chunk)
    resampled, dists = draws.resampled, draws.dists
    if not (np.ndim(bins) == 0 or np.ndim(bins) == 1):
        raise ValueError("bins must be a positive integer or increasing bin edges")

    # Memory: e_w of every sample (8 bytes each, for exact quantiles) and, only when they
    # are kept, the samples; everything else is one chunk at a time.
    check_memory_for("n", n, 8 + (1 + 8 * len(dists) if keep_samples else 0))
    e_w = np.empty(n)
    stage = np.empty(n, dtype=np.int8) if keep_samples else None
    values = {k: np.empty(n) for k in dists} if keep_samples else {}
    e_max = -np.inf if "e" in dists else float(np.max(base["e"]))
    # kept samples are drawn straight into the returned arrays
    for sl, chunk_values in draws.chunks(out=values if keep_samples else None):
        res = evaluate_e_w(base, chunk_values, mode)
        e_w[sl] = res.e_w
        if stage is not None:  # keep_samples
            stage[sl] = res.stage
        if "e" in chunk_values:
            e_max = max(e_max, float(np.max(chunk_values["e"])))
        del res, chunk_values
    nominal = {k: np.atleast_1d(d.nominal) for k, d in dists.items()}
    e_w_nominal = float(evaluate_e_w(base, nominal, mode).e_w[0])

    edges = (np.linspace(0.0, max(e_max, float(e_w.max())), int(bins) + 1)
             if np.ndim(bins) == 0 else np.asarray(bins, dtype=float))
    if edges.ndim != 1 or edges.size < 2 or np.any(np.diff(edges) <= 0.0):
        raise ValueError("bins must be a positive integer or increasing bin edges")

    ds = _summary(e_w, q, edges, e_w_nominal, chunk, scratch=not keep_samples)
    if keep_samples:
        ds["e_w"] = ("sample", e_w, _attrs(_DIMLESS, "wet restitution coefficient (Eq. 31)"))
        ds["agglomerated"] = ("sample", e_w == 0.0,
                              _attrs(_DIMLESS, "the pair sticks (e_w = 0)"))
        ds["stage"] = ("sample", stage, _attrs(
            _DIMLESS, "stage at which the outcome was decided",
            flag_values=np.array([int(s) for s in Stage], dtype=np.int8),
            flag_meanings=" ".join(s.name.lower() for s in Stage)))
        for name, x in values.items():
            spec = UNCERTAIN_INPUTS[name]
            ds[name] = ("sample", x, _attrs(
                spec.units, spec.long_name, distribution=repr(dists[name]),
                physical_range=spec.range_text(), n_resampled=resampled[name]))

    trunc = "; ".join(
        f"{k}: {resampled[k]} of {n} draws outside {UNCERTAIN_INPUTS[k].range_text()}"
        + ("" if dists[k].bounds() == (-np.inf, np.inf) else
           f" or [{dists[k].bounds()[0]:g}, {dists[k].bounds()[1]:g}]")
        + " resampled from the truncated law"
        for k in dists
    )
    ds.attrs.update(
        title="Monte Carlo propagation of input uncertainty to e_w",
        agglomtool_version=__version__,
        mode=str(mode),
        seed=entropy,
        seed_chosen_by_user=int(chosen),
        sampling=_SAMPLING,
        n_samples=n,
        uncertain_inputs=" ".join(dists),
        distributions="; ".join(f"{k} = {dists[k]!r} [{UNCERTAIN_INPUTS[k].units}]"
                                for k in dists),
        truncation=trunc,
        n_resampled_total=int(sum(resampled.values())),
        fixed_inputs=_describe_fixed(base),
        references="Shabanian et al. (2024), Heliyon 10:e29397, "
                   "doi:10.1016/j.heliyon.2024.e29397, Section 3.4",
    )
    return ds


def _describe_fixed(base: dict) -> str:
    def val(x):
        a = np.asarray(x) if x is not None else None
        return "None" if a is None else (f"{float(a):g}" if a.ndim == 0 else f"array{a.shape}")

    parts = []
    for key in ("p_i", "p_j"):
        p = base[key]
        parts.append(f"{key}: d={val(p.d)} m, rho={val(p.rho)} kg/m^3, h0={val(p.h0)} m, "
                     f"ha={val(p.ha)} m")
    liq, gas, bed = base["liquid"], base["gas"], base["bed"]
    parts.append(f"liquid: mu={val(liq.mu)} Pa s, gamma={val(liq.gamma)} N/m, "
                 f"rho={val(liq.rho)} kg/m^3, theta={val(liq.theta_deg)} degree")
    parts.append(f"gas: mu={val(gas.mu)} Pa s, rho={val(gas.rho)} kg/m^3")
    parts.append(f"bed: eps={val(bed.eps)}, U={val(bed.U)} m/s (None = 1.1 Umf)")
    parts.append(f"u0={val(base['u0'])} m/s, u0_j={val(base['u0_j'])} m/s, "
                 f"beta={val(base['beta_deg'])} degree, e={val(base['e'])}, "
                 f"body_forces={base['body_forces']}, drag_slip={base['drag_slip']}")
    return "; ".join(parts)
