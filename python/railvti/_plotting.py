"""matplotlib for the library's plots: pyplot on the file-only Agg backend.

matplotlib is imported on the first plot only (half a second): importing a module that can
plot costs nothing until it does.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any


def pyplot() -> Any:
    """``matplotlib.pyplot`` with the Agg backend (PNG files, no window)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig: Any, path: Path, dpi: int = 110) -> list[Path]:
    """Lay out ``fig``, write it to ``path`` (PNG), close it; returns ``[path]``, the list a
    case type's plot function hands back."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return [path]


__all__ = ["pyplot", "save_figure"]
