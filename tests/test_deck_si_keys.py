"""One unit convention in decks: the SI key and its mm / mrad alias give the same case.

The geometry and wheel-rail keys are SI (m, rad, rad/m); ``y_min_mm``, ``gauge_mm``,
``yaw_mrad``... are documented aliases converted into them when the deck is read. A deck
written with the SI keys and one written with the aliases (the same values in mm) must give
bitwise the same results, and a case that names one quantity twice is refused."""

import h5py
import numpy as np
import pytest

from railvti.runner.cli import main
from railvti.runner.deck import parse_deck
from railvti.errors import InputError

# The same two cases twice: SI keys, then the mm / mrad aliases (values x 1000; each
# mm value times 1e-3 is exactly the SI value, so the inputs are bitwise equal).
GEOMETRY_SI = """
&case
  type = 'geometry_table', name = 'table'
  y_min = -0.004, y_max = 0.004, n = 9, yaw_per_y = 0.5
  gauge = 1.435, gauge_depth = 0.014, back_to_back = 1.36, radius = 0.46, amplitude = 0.003
/
"""
GEOMETRY_MM = """
&case
  type = 'geometry_table', name = 'table'
  y_min_mm = -4.0, y_max_mm = 4.0, n = 9, yaw_mrad_per_mm = 0.5
  gauge_mm = 1435.0, gauge_depth_mm = 14.0, back_to_back_mm = 1360.0, radius_mm = 460.0, amplitude_mm = 3.0
/
"""
WHEELSET_SI = """
&case
  type = 'loaded_wheelset', name = 'sweep'
  y_min = 0.0, y_max = 0.006, n = 2, yaw_per_y = 2.4, mu = 0.3, speed = 2.0
  dx = 0.5e-3, field_at = 0.006, gauge = 1.435, radius = 0.46
/
"""
WHEELSET_MM = """
&case
  type = 'loaded_wheelset', name = 'sweep'
  y_min_mm = 0.0, y_max_mm = 6.0, n = 2, yaw_mrad_per_mm = 2.4, mu = 0.3, speed = 2.0
  dx_mm = 0.5, field_at_mm = 6.0, gauge_mm = 1435.0, radius_mm = 460.0
/
"""


def _run(tmp_path, name, text):
    deck = tmp_path / f"{name}.nml"
    deck.write_text(text)
    out = tmp_path / f"{name}.h5"
    assert main(["run", str(deck), "-o", str(out), "-q"]) == 0
    with h5py.File(out, "r") as f:
        (g,) = f.values()
        assert g.attrs["status"] == "ok"
        res = {k: v[()] for k, v in g.items() if isinstance(v, h5py.Dataset)}
        inputs = {k: (v[()], v.attrs["units"]) for k, v in g["inputs"].items()}
    return res, inputs


@pytest.mark.parametrize(
    "si, mm",
    [(GEOMETRY_SI, GEOMETRY_MM), (WHEELSET_SI, WHEELSET_MM)],
    ids=["geometry_table", "loaded_wheelset"],
)
def test_si_keys_and_mm_aliases_give_identical_results(tmp_path, si, mm):
    a, inp_a = _run(tmp_path, "si", si)
    b, inp_b = _run(tmp_path, "mm", mm)
    assert sorted(a) == sorted(b) and len(a) > 5
    for k in a:
        np.testing.assert_array_equal(a[k], b[k], err_msg=k)
    # the stored inputs are the SI keys, in m, whichever name the deck used
    assert sorted(inp_a) == sorted(inp_b)
    assert not [k for k in inp_a if k.endswith("_mm") or "mrad" in k]
    assert inp_a["gauge"] == inp_b["gauge"] == (1.435, "m")


def test_shift_sweep_is_in_metres(tmp_path):
    """Independent of the alias: the stored shifts are the SI key's values (m)."""
    res, _ = _run(tmp_path, "si", GEOMETRY_SI)
    np.testing.assert_allclose(res["y"], np.linspace(-4e-3, 4e-3, 9), rtol=0, atol=1e-18)
    np.testing.assert_allclose(res["yaw"], 0.5 * res["y"], rtol=1e-15)


@pytest.mark.parametrize(
    "text, key, alias",
    [
        (GEOMETRY_SI.replace("n = 9", "n = 9, y_min_mm = -4.0"), "y_min", "y_min_mm"),
        (WHEELSET_SI.replace("mu = 0.3", "mu = 0.3, yaw_mrad_per_mm = 2.4"), "yaw_per_y", "yaw_mrad_per_mm"),
        ("&case\n type = 'wheel_rail', name = 'wr'\n yaw = 0.001, yaw_mrad = 1.0\n/\n", "yaw", "yaw_mrad"),
    ],
)
def test_key_and_its_alias_in_one_case_is_an_error_naming_both(text, key, alias):
    with pytest.raises(InputError) as err:
        parse_deck(text)
    assert f"'{key}'" in str(err.value) and f"'{alias}'" in str(err.value)


def test_alias_bounds_are_the_keys_converted():
    """An alias is checked as its key: 60 mm is outside the shift's [-0.05, 0.05] m; the
    message names the key as the deck wrote it, with the converted value."""
    with pytest.raises(
        InputError,
        match=r"key 'y_max_mm' = 60\.0 \(y_max = 0\.06 m\) is outside "
        r"\[-0\.05, 0\.05\] m",
    ):
        parse_deck(GEOMETRY_MM.replace("y_max_mm = 4.0", "y_max_mm = 60.0"))


@pytest.mark.parametrize(
    "text, written",
    [
        (
            GEOMETRY_MM.replace("y_min_mm = -4.0, y_max_mm = 4.0", "y_min_mm = 4.0, y_max_mm = 2.0"),
            ["y_min_mm = 4.0", "y_max_mm = 2.0"],
        ),
        (
            GEOMETRY_MM.replace("y_min_mm = -4.0, y_max_mm = 4.0", "y_min = 0.004, y_max_mm = 2.0"),
            ["y_max_mm = 2.0"],
        ),
        (WHEELSET_MM.replace("field_at_mm = 6.0", "field_at_mm = 9.0"), ["field_at_mm = 9.0"]),
    ],
)
def test_a_consistency_error_names_the_alias_the_deck_wrote(text, written):
    """y_min_mm > y_max_mm (or field_at_mm beyond them): the consistency check runs on the
    SI values, and its message names the keys as written, with their values as written."""
    with pytest.raises(InputError) as err:
        parse_deck(text)
    msg = str(err.value)
    assert "(the case gave " in msg
    for w in written:
        assert w in msg


def test_track_arc_step_is_metres_with_an_mm_alias():
    """arc_step (m) and arc_step_mm give the same case; an old deck's mm value is refused."""
    base = "&case\n type = 'track_element', name = 't'\n n_sleepers = 16\n {}\n/\n"
    (si,) = parse_deck(base.format("arc_step = 0.015"))
    (mm,) = parse_deck(base.format("arc_step_mm = 15.0"))
    assert si.params == mm.params and si.params["arc_step"] == 0.015
    with pytest.raises(InputError, match=r"key 'arc_step' = 8.*arc_step_mm takes mm"):
        parse_deck(base.format("arc_step = 8.0"))


def test_track_api_arc_step_is_metres_with_a_deprecated_mm_alias():
    """RingTrack's and rail_section's arc_step is in m, as the deck key: arc_step_mm (mm)
    gives the same section with a DeprecationWarning; both together, or an old mm value
    given as m, are refused with the way to write it."""
    from railvti.track import RingTrack, rail_section

    si = rail_section(4e-4, arc_step=0.012)
    with pytest.warns(DeprecationWarning, match="arc_step_mm is deprecated"):
        mm = rail_section(4e-4, arc_step_mm=12.0)
    assert np.array_equal(si.nodes, mm.nodes) and si.n_nodes > 20
    # the arcs' spacing is what the argument says: a finer step puts more nodes on the outline
    assert rail_section(4e-4, arc_step=0.004).n_nodes > si.n_nodes
    with pytest.raises(InputError, match=r"arc_step = 8 m is above 0\.05 m.*arc_step = 0\.008"):
        rail_section(4e-4, arc_step=8.0)
    with pytest.raises(InputError, match="not both"):
        rail_section(4e-4, arc_step=0.008, arc_step_mm=8.0)
    with pytest.raises(InputError, match=r"arc_step = 12 m is above"):
        RingTrack(8, arc_step=12.0)
    with pytest.raises(InputError, match="not both"):
        RingTrack(8, arc_step=0.012, arc_step_mm=12.0)
    with pytest.warns(DeprecationWarning), pytest.raises(InputError, match="arc_step_mm"):
        RingTrack(8, arc_step_mm=-1.0)
