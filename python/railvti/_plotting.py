"""matplotlib for the library's plots: pyplot on the file-only Agg backend.

matplotlib is imported on the first plot only (half a second): importing a module that can
plot costs nothing until it does.
"""

from __future__ import annotations

from typing import Any


def pyplot() -> Any:
    """``matplotlib.pyplot`` with the Agg backend (PNG files, no window)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


__all__ = ["pyplot"]
