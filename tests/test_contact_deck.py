"""CONTACT's wheel-rail decks (.inp, module 1): the reader, its errors, and the Manchester
benchmark A-2.2 run through `railvti run`.

The runs use the reduced decks of the regression suite (tests/regression/decks/
mbench_a22_small_*.inp: 5 of the 21 positions, y = 0, 3, 5, 6.5 and 8 mm, on a 0.4 mm grid
instead of 0.2 mm); validation/contact_a22.py runs the whole decks of inputs/.
"""

from pathlib import Path

import h5py
import numpy as np
import pytest

from railvti.runner.cli import main
from railvti.contact.contact_deck import read_contact_deck
from railvti.runner.deck import read_deck
from railvti.errors import InputError

ROOT = Path(__file__).resolve().parent.parent
INPUTS = ROOT / "inputs"
SMALL = ROOT / "tests" / "regression" / "decks"
PROFILES = ROOT / "python" / "railvti" / "data" / "profiles"

CASE = """\
% one case of module 1
  1 MODULE
 0203100    C-P-B-T-N-F-S
 0022033    V-L-D-C-M-Z-E
 0000321    H-G-I-A-O-W-R
  999  100  30  1  1e-5            MAXGS, MAXIN, MAXNR, MAXOUT, EPS
  0.30  0.30                      FSTAT, FKIN
  0.28  0.28  82000.  82000.      POISS 1,2, GG 1,2
  0.5  0.5  1.0  90d  8.0  4.0    DX, DS, DQREL, A_SEP, D_SEP, D_COMB
  14.0  0  1435.0  0.0            GAUGHT, GAUGSQ, GAUGWD, CANT
  'RAIL'  0  1.0  0.0             RFNAME, MIRRORY, SCALE, SMOOTH
  0.0  0.0  0.0  0.0  0.0  0.0    DY, DZ, ROLL, VY, VZ, VROLL
  1360.0  -70.0  460.0            FBDIST, FBPOS, NOMRAD
  'WHEEL'  0  1.0  0.0            WFNAME, MIRRORY, SCALE, SMOOTH
  0.0  3.0  10000.  -0.00018030  0.0072  0.0     S, Y, FZ, ROLL, YAW, PITCH
  2000.  0.0  0.0  0.0  0.0  -4.34515030         VS, VY, VZ, VROLL, VYAW, VPITCH
  0 MODULE
"""


def _deck(tmp_path, text=CASE, name="case.inp"):
    text = text.replace("'RAIL'", f"'{PROFILES / 'MBench_UIC60_v3.prr'}'")
    text = text.replace("'WHEEL'", f"'{PROFILES / 'MBench_S1002_v3.prw'}'")
    p = tmp_path / name
    p.write_text(text)
    return p


def test_a22_decks_read_as_the_benchmark_defines_them():
    """The 21 positions of each deck, converted to railvti's frame (y and yaw to the left,
    omega > 0 forward), with what the first case set kept by the later ones."""
    for side in ("left", "right"):
        cases = read_deck(INPUTS / f"mbench_a22_{side}.inp")
        assert len(cases) == 21
        assert {c.case_type.name for c in cases} == {"wheel_rail"}
        for k, c in enumerate(cases):
            p = c.params
            assert p["side"] == side
            assert p["y"] == pytest.approx(-0.5e-3 * k)
            assert p["yaw"] == pytest.approx(-1.2e-3 * k)
            assert p["fz"] == 1.0e4 and p["mu"] == 0.3 and p["speed"] == 2.0
            assert (
                p["shear_modulus"] == 82.0e9
                and p["poisson"] == 0.28
                and p["dx"] == 0.2e-3
                and p["dy"] == 0.2e-3
            )
            assert p["gauge"] == 1.435 and p["gauge_depth"] == 0.014
            assert p["back_to_back"] == 1.36 and p["contact_offset"] == 0.07 and p["radius"] == 0.46
            assert Path(p["rail"]).name == "MBench_UIC60_v3.prr" and Path(p["rail"]).is_file()
        # position 13 (y = 6 mm), as the deck gives it
        p = cases[12].params
        assert p["roll"] == pytest.approx(-0.6272e-3) and p["omega"] == pytest.approx(4.3293718)
        assert [c.params["store_fields"] for c in cases].count(1) == 3


def test_angles_in_degrees_and_comments(tmp_path):
    """'90d' is 90 degrees; '%' starts a comment anywhere; commas separate values."""
    text = CASE.replace("0.0072  0.0", "0.0072d, 0.0  % yaw in degrees").replace(
        "  0.30  0.30 ", "0.30,0.30 "
    )
    p = read_contact_deck(_deck(tmp_path, text))[0].params
    assert p["yaw"] == pytest.approx(-np.radians(0.0072))
    assert p["mu"] == 0.3


@pytest.mark.parametrize(
    "old, new, words",
    [
        ("  1 MODULE", "  3 MODULE", r"case.inp:2: MODULE 3 is not supported"),
        (" 0203100 ", " 0201100 ", r"case.inp:3: T \(TANG\) = 1 .* not supported"),
        (" 0203100 ", " 4203100 ", r"C \(CONFIG\) = 4"),
        (" 0022033 ", " 0022133 ", r"M \(MATER\) = 1"),
        (" 0022033 ", " 1022033 ", r"V \(VARFRC\) = 1"),
        (" 0000321 ", " 0000121 ", r"O \(OUTPUT\) = 1"),
        (" 0000321 ", " 10000321 ", r"X \(XFLOW\) = 1"),
        (" 0022033 ", " 0012033 ", r"D \(DISCNS\) = 1 keeps the grid of a previous case"),
        (
            "'RAIL'",
            "'no_such_rail.prr'",
            r"case.inp:11: rail profile file RFNAME = 'no_such_rail.prr' not found",
        ),
        ("'WHEEL'", "'wheel.whl'", r"WFNAME 'wheel.whl': .whl profiles are not supported"),
        ("  0.30  0.30 ", "  0.30  0.25 ", r"FSTAT = 0.3 and FKIN = 0.25 differ"),
        ("  14.0  0  1435.0  0.0 ", "  -1.0  0  0.0  0.0 ", r"GAUGHT = -1.0"),
        ("'RAIL'  0  1.0  0.0 ", "'RAIL'  0  1.0  2.0 ", r"SMOOTH = 2.0"),
        (
            "  0.0  0.0  0.0  0.0  0.0  0.0 ",
            "  0.0  1.5  0.0  0.0  0.0  0.0 ",
            r"DZRAIL = 1.5: rail deviations",
        ),
        ("  2000.  0.0", "  -2000.  0.0", r"VS = -2000.0"),
        ("-4.34515030", "4.34515030", r"VPITCH = 4.3451503"),
        ("  10000.  ", "  abc  ", r"case.inp:15: expected a number for FZ, got 'abc'"),
        ("  0 MODULE\n", "", r"ends without '0 MODULE'"),
        ("  0.28  0.28  82000.  82000. ", "  0.28  0.30  82000.  82000. ", r"quasi-identical"),
        ("  8.0  4.0 ", "  4.0  8.0 ", r"0 < D_COMB < D_SEP, got 8.0, 4.0"),
    ],
)
def test_bad_decks_name_the_flag_line_or_file(tmp_path, old, new, words):
    assert old in CASE
    with pytest.raises(InputError, match=words):
        read_contact_deck(_deck(tmp_path, CASE.replace(old, new, 1)))


def test_unreadable_and_empty_decks(tmp_path):
    with pytest.raises(InputError, match="cannot read CONTACT deck"):
        read_deck(tmp_path / "missing.inp")
    with pytest.raises(InputError, match="holds no case"):
        read_contact_deck(_deck(tmp_path, "  0 MODULE\n"))


def test_profile_name_resolves_relative_to_the_deck(tmp_path):
    """A profile's file name is taken relative to the deck's folder, not the working one."""
    sub = tmp_path / "decks"
    sub.mkdir()
    rel = Path("..") / "profiles"
    (tmp_path / "profiles").mkdir()
    for name in ("MBench_UIC60_v3.prr", "MBench_S1002_v3.prw"):
        (tmp_path / "profiles" / name).write_bytes((PROFILES / name).read_bytes())
    text = CASE.replace("'RAIL'", f"'{rel / 'MBench_UIC60_v3.prr'}'").replace(
        "'WHEEL'", f"'{rel / 'MBench_S1002_v3.prw'}'"
    )
    (sub / "case.inp").write_text(text)
    p = read_contact_deck(sub / "case.inp")[0].params
    assert Path(p["rail"]).resolve() == (tmp_path / "profiles" / "MBench_UIC60_v3.prr").resolve()


@pytest.fixture(scope="module")
def a22_small(tmp_path_factory):
    """Both reduced A-2.2 decks run through `railvti run`: {side: (h5 path, stdout)}."""
    out = {}
    tmp = tmp_path_factory.mktemp("a22")
    for side in ("left", "right"):
        h5 = tmp / f"{side}.h5"
        assert main(["run", str(SMALL / f"mbench_a22_small_{side}.inp"), "-o", str(h5), "-q"]) == 0
        out[side] = h5
    return out


def _cases(h5):
    with h5py.File(h5, "r") as f:
        return {
            k: (
                {q: g[q][()] for q in g if isinstance(g[q], h5py.Dataset)},
                dict(g["inputs"].attrs),
                g.attrs["summary"],
            )
            for k, g in f.items()
        }


def test_a22_one_patch_per_wheel_and_balanced_with_tangential_forces(a22_small):
    """Each wheel of each position: one patch (the tread, or at 6.5 and 8 mm the right wheel's
    flange, contact angle > 0.9 rad); its vertical force Fn cos(d) + s Fy sin(d) equals the
    deck's 10 kN to 1e-5; the creepage of the centred wheelset follows from the deck's pitch
    velocity."""
    for side, h5 in a22_small.items():
        w = 0 if side == "left" else 1
        s = 1.0 if side == "left" else -1.0
        for name, (r, inp, summary) in _cases(h5).items():
            fn, fy, ang = r["fn"][w], r["fy"][w], r["contact_angle"][w]
            assert np.isfinite(fn[0]) and np.all(np.isnan(fn[1:])), name  # one patch
            assert np.all(np.isnan(r["fn"][1 - w])), name  # the other wheel not solved
            fz = np.nansum(fn * np.cos(ang) + s * fy * np.sin(ang))
            assert fz == pytest.approx(1.0e4, rel=1e-5), name
            assert r["fz"][w] == pytest.approx(1.0e4, rel=1e-5)
            assert r["omega"] == inp["omega"]
            if inp["y"] == 0.0:
                # the centred wheelset: CONTACT's CKSI = -xi at its contact reference point
                # (examples/mbench_a22_*.ref_out: -5.665e-5, both wheels; 0.4 mm grid here)
                assert -r["xi"][w, 0] == pytest.approx(-5.665e-5, rel=0.03)
            assert "FN" in summary and "CKSI" in summary and "PEN" in summary and "elements" in summary
            if side == "right" and inp["y"] <= -6.5e-3:
                assert ang[0] > 0.9 and abs(fn[0] * np.cos(ang[0]) / 1.0e4 - 1) > 0.2  # the flange


def test_a22_stores_fields_where_matfil_is_set(a22_small):
    cases = _cases(a22_small["left"])
    with_fields = [k for k, (r, _, _) in cases.items() if "field_left0_pressure" in r]
    assert len(with_fields) == 2  # y = 0 and 5 mm (MATFIL = 1)
    r = cases[with_fields[0]][0]
    p = r["field_left0_pressure"]
    assert p.shape == (r["field_left0_x"].size, r["field_left0_y"].size) and p.max() > 0
    assert set(np.unique(r["field_left0_status"])) <= {0, 1, 2}


def test_a22_summary_in_contact_conventions(a22_small, capsys):
    """The summary gives forces on the rail: the right wheel's flange pushes its rail to the
    field side (FY_TR > 0, CONTACT's y to the right) with FZ_TR = 10 kN down."""
    cases = _cases(a22_small["right"])
    last = cases[sorted(cases)[-1]][2]
    fy_tr = float(last.split("FY_TR ")[1].split()[0])
    fz_tr = float(last.split("FZ_TR ")[1].split()[0])
    assert fy_tr > 5e3 and fz_tr == pytest.approx(1.0e4, abs=0.2)


def test_wheel_rail_case_in_a_namelist_deck(tmp_path):
    """The case type the CONTACT cases become, written as a namelist: both wheels, the roll
    load-controlled, free rolling (omega = 0): no torque about the axle."""
    deck = tmp_path / "wr.nml"
    deck.write_text(
        "&case\n  type = 'wheel_rail', name = 'both_free'\n  y_mm = -3.0, yaw_mrad = -7.2\n"
        "  dx_mm = 0.5, dy_mm = 0.5\n/\n"
    )
    h5 = tmp_path / "wr.h5"
    assert main(["run", str(deck), "-o", str(h5), "-q"]) == 0
    r, inp, summary = _cases(h5)["001_both_free"]
    assert inp["side"] == "both" and inp["roll"] == "none"
    assert inp["y"] == pytest.approx(-3.0e-3) and inp["yaw"] == pytest.approx(
        -7.2e-3
    )  # the mm / mrad aliases, in SI
    assert np.all(np.isfinite(r["fn"][:, 0])) and np.all(np.isnan(r["fn"][:, 1:]))
    assert r["fz"] == pytest.approx([1.0e4, 1.0e4], rel=1e-5)
    scale = 0.3 * np.nansum(r["fn"] * r["rolling_radius"])
    assert abs(r["axle_torque"]) <= 1e-5 * scale
    assert summary.count("wheel:") == 2
