"""Checks of :func:`agglomtool.maps.sweep`'s options, made before any work."""

from __future__ import annotations

import numpy as np

__all__ = ["check_chunks"]


def check_chunks(chunks) -> None:
    """Refuse block sizes that would otherwise be rounded or read as numbers silently.

    Raises
    ------
    ValueError
        Naming ``chunks`` (or ``chunks[dim]``), the value and the allowed values, for a
        size that is not a whole number >= 1 (0, negative, fractional, boolean, text).
    """
    if chunks is None or (isinstance(chunks, str) and chunks == "auto"):
        return
    items = chunks.items() if isinstance(chunks, dict) else [(None, chunks)]
    for dim, size in items:
        field = "chunks" if dim is None else f"chunks[{dim!r}]"
        if isinstance(size, bool) or not isinstance(size, int | np.integer) or size < 1:
            raise ValueError(
                f"{field} = {size!r} must be a whole number of points >= 1"
                + ("" if dim is not None else ', "auto", None or a {dimension: size} dict'))
