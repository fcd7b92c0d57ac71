"""Which quantity decides a map where the collision model has no critical speed to give.

Two regimes leave a map without a finite ``u0*``: a coating no thicker than the asperities
forms no bridge (nothing sticks, ``u0* = 0``), and a liquid viscous enough holds every
bridge up to the ceiling speed (everything sticks, ``u0* = inf``). A map made only of these
is uniform in its colour, and its answer does not depend on temperature, speed or size
within it: what decides is whether a bridge forms at all, the coating thickness against the
asperity heights. :func:`deciding_regime` says so in words for the map's attributes, the
command line and the pictures.
"""

from __future__ import annotations

__all__ = ["deciding_regime"]


def deciding_regime(ds, summary: dict | None = None) -> str:
    """A sentence naming what decides the map ``ds``, or ``""`` where ``u0*`` is finite
    somewhere (the map is then decided by speeds against ``u0*`` as usual).

    ``summary``: the map's ``u_star_flag`` as ``{code: points}`` and the range of
    ``mu_l`` as ``[min, max]``, where known without reading the map (a store's run counts
    them block by block); else they are read from ``ds``."""
    if "u_star_flag" not in ds:
        return ""
    summary = summary or {}
    if "u_star_flag" in summary:
        counts = summary["u_star_flag"]
        n, n_finite = sum(counts.values()), counts.get(0, 0)
        n_none, n_all = counts.get(1, 0), counts.get(2, 0)
    else:  # counted with xarray: a map opened lazily from a store is read chunk by chunk
        flag = ds["u_star_flag"]
        n = flag.size
        n_finite = 1 if n and bool((flag == 0).any()) else 0
        n_none = n_all = 0
        if n and not n_finite:
            n_none, n_all = int((flag == 1).sum()), int((flag == 2).sum())
    if n == 0 or n_finite:
        return ""
    mu = ""
    if "mu_l" in ds and n_all:
        lo, hi = summary.get("mu_l") or (float(ds["mu_l"].min()), float(ds["mu_l"].max()))
        mu = f" (mu_l {lo:.2g}-{hi:.2g} Pa s)"
    ceiling = ""
    if "scene" in ds.attrs:
        import json

        try:
            ceiling = f" of {json.loads(ds.attrs['scene'])['u_ceiling']:g} m/s"
        except (ValueError, KeyError, TypeError):
            ceiling = ""
    decides = ("what decides is whether a bridge forms: the coating thickness h0 against "
               "the asperity heights ha_i, ha_j")
    if n_all == 0:
        return ("No bridge forms anywhere on this map (the coating is no thicker than the "
                f"asperities): nothing sticks, and {decides}, not temperature, speed or size.")
    if n_none == 0:
        return (f"The pair sticks at every impact speed up to the ceiling{ceiling} everywhere "
                f"on this map: the liquid{mu} holds every bridge. Only a coating no thicker "
                f"than the asperities would change the answer: {decides}.")
    return (f"Every point of this map either forms no bridge ({100 * n_none / n:.0f} %) or "
            f"sticks at every speed up to the ceiling{ceiling} ({100 * n_all / n:.0f} %): "
            f"the liquid{mu} holds any bridge that forms, so {decides}; temperature, "
            "speeds and sizes change nothing within this map.")
