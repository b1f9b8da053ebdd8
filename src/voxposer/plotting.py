"""PNG figures: matplotlib on its file-only backend (Agg), and one way to save a figure.

Every chart the package writes (the benchmark's success chart and error breakdown, the
learning curves, the U-Net's loss curve) gets ``pyplot`` from :func:`pyplot` and is written by
:func:`save_figure`. A base module: it imports no pipeline stage, so any stage may use it.
"""

from __future__ import annotations

from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

from voxposer.errors import VoxPoserError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: resolution of a saved figure unless a caller asks for another [dots per inch].
DEFAULT_DPI = 110


def pyplot(needed_by: str) -> ModuleType:
    """``matplotlib.pyplot``, with the Agg backend selected (no display needed).

    Args:
        needed_by: what asks for it, for the error message (e.g. "the report chart").

    Raises:
        VoxPoserError: matplotlib is missing (it is a dependency: reinstall the package).
    """
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - a declared dependency
        raise VoxPoserError(f"{needed_by} needs matplotlib: pip install matplotlib") from exc
    return plt


def save_figure(fig: Figure, path: Path, dpi: int = DEFAULT_DPI) -> Path:
    """Lay ``fig`` out tightly, write it to ``path`` (a PNG; missing folders are made) and close
    it.

    Args:
        fig: the finished figure; it is closed afterwards, so it cannot be drawn on again.
        path: the file to write.
        dpi: resolution [dots per inch].

    Returns:
        ``path``.
    """
    import matplotlib.pyplot as plt

    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path


__all__ = ["DEFAULT_DPI", "pyplot", "save_figure"]
