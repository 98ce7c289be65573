"""Plot fixes of issue 31 (item 8): titles that fit, no '-0', the critical speed titled and
marked, sweep axes named with units and one legend beside the panels, and ``railvti plot``
saying why a case gave no figure."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.figure  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from railvti.runner.cli import main  # noqa: E402
from railvti.contact.wheelset_plots import case_title, wrap_title  # noqa: E402
from railvti.vehicle.plots import plot_bifurcation  # noqa: E402


@pytest.fixture
def figures(monkeypatch):
    """The figures saved during a test (their artists, before they are closed)."""
    saved = []
    original = matplotlib.figure.Figure.savefig

    def keep(self, *args, **kwargs):
        self.canvas.draw()
        saved.append(self)
        return original(self, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", keep)
    return saved


class _Group(dict):
    """An HDF5-like group: a name attribute and an 'inputs' mapping."""

    def __init__(self, name, inputs):
        super().__init__(inputs=inputs)
        self.attrs = {"name": name}


def test_case_title_no_negative_zero():
    title = case_title(
        _Group("left_1", {"y": np.float64(-0.0), "yaw": np.float64(-0.0)}),
        (("y", "y", 1e3, " mm"), ("yaw", "yaw", 1e3, " mrad")),
    )
    assert title == "left_1: y 0 mm, yaw 0 mrad"


def test_wrap_title_fits_and_keeps_items():
    text = (
        "wheel on rail, left_1: y 0 mm, yaw 0 mrad, Fz 10 kN, mu 0.3, speed 2 m/s, "
        "a rather long extra item that must wrap somewhere"
    )
    out = wrap_title(text, 5.0, 10)
    chars = int(5.0 * 72 / 6.0) - 2
    assert all(len(line) <= chars for line in out.split("\n"))
    assert out.replace("\n", " ").replace(", ", ",").replace(",", ", ").split() == text.split()
    assert "mu\n0.3" not in out and "mu 0.3" in out.replace("\n", " ")


def test_bifurcation_marks_the_critical_speed(tmp_path, figures):
    sp = np.array([200.0, 250.0, 300.0])
    plot_bifurcation(
        sp,
        np.array([0.0, 1e-3, 3e-3]),
        np.array([0.0, 0.0, 2e-3]),
        320.0,
        tmp_path / "b.png",
        title="crit: critical speed, model RR",
        critical_kmh=250.0,
    )
    ax = figures[-1].axes[0]
    assert ax.get_title() == "crit: critical speed, model RR"
    xs = [
        line.get_xdata()[0]
        for line in ax.get_lines()
        if "critical speed (nonlinear)" in str(line.get_label())
    ]
    assert xs == [250.0]
    plot_bifurcation(
        sp, np.zeros(3), np.zeros(3), float("nan"), tmp_path / "c.png", critical_kmh=float("nan")
    )
    assert any("no critical speed found in 200-300 km/h" in t.get_text() for t in figures[-1].axes[0].texts)


SWEEP = """
&case
  name = 's', type = 'normal'
  nx = 24, ny = 24, dx = 5e-4, dy = 5e-4
  gap_a = 1.0
  sweep_fn = 5e3, 1e4
  sweep_gap_b = 1.5, 3.0
  sweep_poisson = 0.25, 0.3
/
"""


def test_sweep_axes_and_legend(tmp_path, figures, capsys):
    deck = tmp_path / "s.nml"
    deck.write_text(SWEEP)
    assert main(["run", str(deck), "-o", str(tmp_path / "s.h5"), "-q", "--serial"]) == 0
    assert main(["plot", str(tmp_path / "s.h5"), "-o", str(tmp_path / "p"), "--points"]) == 0
    fig = [f for f in figures if f._suptitle is not None and "sweep 's'" in f._suptitle.get_text()][-1]
    axes = fig.axes
    assert axes[-1].get_xlabel() in (
        "normal force (fn), N",
        "gap curvature along y (gap_b), 1/m",
        "Poisson's ratio of wheel and rail (poisson)",
    )
    assert "Hertz semi-axis a, m" in [a.get_ylabel() for a in axes]
    assert all(a.get_legend() is None for a in axes)  # no legend over a panel
    (legend,) = fig.legends
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    r = FigureCanvasAgg(fig).get_renderer()
    assert legend.get_window_extent(r).x0 >= max(a.get_window_extent(r).x1 for a in axes) - 1


TOO_SMALL = """
&case
  name = 'cramped', type = 'normal'
  gap_a = 0.5, gap_b = 0.5
  nx = 10, ny = 10, dx = 0.2e-3, dy = 0.2e-3
  fn = 1.0e4
/
"""


def test_plot_says_why_nothing_was_plotted(tmp_path, capsys):
    deck = tmp_path / "d.nml"
    deck.write_text(TOO_SMALL)
    assert main(["run", str(deck), "-o", str(tmp_path / "d.h5"), "-q"]) == 1
    capsys.readouterr()
    assert main(["plot", str(tmp_path / "d.h5"), "-o", str(tmp_path / "p")]) == 1
    err = capsys.readouterr().err
    assert (
        "001_cramped: not plotted: the case failed (GridTooSmallError" in err and "GridTooSmallError" in err
    )
    assert "no figure written" in err


def test_plot_interrupted_before_any_result(tmp_path, capsys):
    """An interrupted case that kept nothing (its group holds only its inputs): said, exit 1."""
    import h5py

    deck = tmp_path / "d.nml"
    deck.write_text(TOO_SMALL.replace("nx = 10, ny = 10", "nx = 64, ny = 64"))
    assert main(["run", str(deck), "-o", str(tmp_path / "d.h5"), "-q"]) == 0
    with h5py.File(tmp_path / "d.h5", "a") as f:
        g = f["001_cramped"]
        g.attrs["status"] = "interrupted: SIGINT after 0.1 s"
        for k in [k for k in g if k != "inputs"]:
            del g[k]
    capsys.readouterr()
    assert main(["plot", str(tmp_path / "d.h5"), "-o", str(tmp_path / "p")]) == 1
    err = capsys.readouterr().err
    assert "001_cramped: not plotted: interrupted: SIGINT after 0.1 s, before it kept any result" in err
    assert "Traceback" not in err
