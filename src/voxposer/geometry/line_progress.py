"""How far a path went along a line without leaving it (the benchmark's "along the [line]" check
and the programs' ``along`` post-condition read it the same way)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def on_line_progress(along: NDArray[np.float64], lateral: NDArray[np.float64],
                     band: float) -> float:
    """Distance [m] along the line covered without leaving it: the largest span of ``along``
    over a run of consecutive samples within ``band`` [m] of its axis (shapes (T,))."""
    best, start = 0.0, None
    for k, on in enumerate(np.append(np.asarray(lateral) <= band, False)):
        if on and start is None:
            start = k
        elif not on and start is not None:
            run = np.asarray(along)[start:k]
            best, start = max(best, float(np.max(run) - np.min(run))), None
    return best


__all__ = ["on_line_progress"]
