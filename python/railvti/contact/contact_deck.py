"""CONTACT's wheel-rail input decks (``.inp``, module 1), read into ``wheel_rail`` cases.

CONTACT (E.A.H. Vollebregt's program) reads a deck of cases, each a call of a *module*
(``1 MODULE``: wheel-rail contact) with three control words of digits (``C-P-B-T-N-F-S``,
``V-L-D-C-M-Z-E``, ``X-H-G-I-A-O-W-R``) that say which groups of values follow. railvti reads
the subset that the Manchester contact benchmark's case A-2.2 decks use (one wheel, CONTACT's
half wheelset, on one rail; steady rolling; vertical load, roll and pitch velocity
prescribed); every other module, digit value or unsupported input value is an InputError
naming the file, the line and the flag or value. The format (CONTACT's user guide, input
file specification): ``%`` starts a comment; values are separated by blanks or commas and a
group may continue on the next lines; the text after a group's last value on its line is
ignored; optional values ``{...}`` stand on the line of the group's last value; angles may
carry a ``d`` (degrees) or ``r`` (radians) suffix; strings are in single quotes. Units are
CONTACT's: mm, N, N/mm^2, rad, mm/s, rad/s.

Each case keeps what earlier cases set (the digits' "maintain" values: friction, material,
discretisation, track and wheelset); a case becomes a complete ``wheel_rail`` case in
railvti's conventions: SI units, track frame x forward, y to the LEFT, z UP (CONTACT's
track frame has y to the right and z down: y, yaw and their rates change sign; its pitch
velocity is negative for forward rolling, railvti's omega positive). Profile files are
resolved relative to the deck's folder. docs/contact_decks.md lists what railvti reads and
where it interprets a case differently from CONTACT.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..casetypes import REGISTRY, Case, register_deck_reader
from ..errors import InputError
from . import wheel_rail_cases

#: The control words of a module-1 case: letters and CONTACT's names of the digits.
WORDS = {
    "CPBTNFS": ("CONFIG", "PVTIME", "BOUND", "TANG", "NORM", "FORCE", "STRESS"),
    "VLDCMZE": ("VARFRC", "FRCLAW", "DISCNS", "INFLCF", "MATER", "ZTRACK", "EWHEEL"),
    "XHGIAOWR": ("XFLOW", "HEAT", "GAUSEI", "IESTIM", "MATFIL", "OUTPUT", "FLOW", "RETURN"),
}
#: The digit values railvti reads (those of the Manchester benchmark's A-2.2 decks), by
#: (word, letter): C 0/1 left/right wheel on a track, P 2 new sequence, B 0 elastic half-space,
#: T 3 steady rolling, N 1 vertical force prescribed, F 0 pitch velocity prescribed, S 0 no
#: subsurface stresses; V 0 one friction coefficient, L 0 Coulomb (1 keep), D 2 planar
#: contact, read the grid (1 keep), C 2 half-space influence coefficients for piecewise
#: constant tractions (1 keep), M 0 elastic, Z 3 read the track and rail (0 keep), E 3 read
#: the wheelset and wheel (2 read position and velocity only); X 0, H 0 no temperature,
#: G 0 read the solver's iteration limits (1 keep), I 0, A 0/1 (1 keep the patches' fields),
#: O 3, W 2 (output levels), R 1 one case per module call.
SUPPORTED = {
    ("CPBTNFS", "C"): {0, 1},
    ("CPBTNFS", "P"): {2},
    ("CPBTNFS", "B"): {0},
    ("CPBTNFS", "T"): {3},
    ("CPBTNFS", "N"): {1},
    ("CPBTNFS", "F"): {0},
    ("CPBTNFS", "S"): {0},
    ("VLDCMZE", "V"): {0},
    ("VLDCMZE", "L"): {0, 1},
    ("VLDCMZE", "D"): {1, 2},
    ("VLDCMZE", "C"): {1, 2},
    ("VLDCMZE", "M"): {0},
    ("VLDCMZE", "Z"): {0, 3},
    ("VLDCMZE", "E"): {2, 3},
    ("XHGIAOWR", "X"): {0},
    ("XHGIAOWR", "H"): {0},
    ("XHGIAOWR", "G"): {0, 1},
    ("XHGIAOWR", "I"): {0},
    ("XHGIAOWR", "A"): {0, 1},
    ("XHGIAOWR", "O"): {3},
    ("XHGIAOWR", "W"): {2},
    ("XHGIAOWR", "R"): {1},
}
#: Profile formats: SIMPACK files and plain two-column tables (any other extension); not
#: Miniprof files or slices (variable profiles).
UNSUPPORTED_PROFILES = (".ban", ".whl", ".slcs", ".slcw")

_NUMBER = re.compile(r"^([+-]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][+-]?\d+)?)([dDrR]?)$")


@dataclass(frozen=True)
class _Line:
    number: int
    tokens: list[str]


def _tokens(text: str) -> list[str]:
    """Blank/comma separated tokens of a line, single-quoted strings kept whole, '%' comments cut."""
    out, i, n = [], 0, len(text)
    while i < n:
        ch = text[i]
        if ch == "%":
            break
        if ch in " \t,\r":
            i += 1
            continue
        if ch == "'":
            j = text.find("'", i + 1)
            j = n if j < 0 else j
            out.append(text[i : j + 1])
            i = j + 1
            continue
        j = i
        while j < n and text[j] not in " \t,\r%'":
            j += 1
        out.append(text[i:j])
        i = j
    return out


class _Reader:
    """Groups of values from the deck's non-empty lines (see the module docstring)."""

    def __init__(self, path: Path, text: str) -> None:
        self.path = path
        self.lines = [
            _Line(k, t) for k, t in ((k, _tokens(s)) for k, s in enumerate(text.splitlines(), 1)) if t
        ]
        self.i = 0

    def where(self, line: int | None = None) -> str:
        """``file:line`` of a line number, or of the line being read (the last one at the end)."""
        if line is None:
            if self.i < len(self.lines):
                line = self.lines[self.i].number
            else:
                line = self.lines[-1].number if self.lines else 0
        return f"{self.path.name}:{line}"

    def at_end(self) -> bool:
        return self.i >= len(self.lines)

    def group(self, spec: list[tuple[str, str]], optional: list[tuple[str, str]] = ()) -> tuple[dict, int]:
        """Read the values named in ``spec`` ((name, kind): kind 'int', 'real', 'angle', 'str',
        'word'), across lines, then the ``optional`` ones present on the last value's line.
        Returns the values by name and the line number of the group's first value."""
        values: dict[str, Any] = {}
        first = None
        k = 0
        line = None
        for name, kind in spec:
            while line is None or k >= len(line.tokens):
                if self.i >= len(self.lines):
                    raise InputError(
                        f"{self.where()}: the deck ends while reading {', '.join(n for n, _ in spec)}"
                    )
                line, k = self.lines[self.i], 0
                self.i += 1
            first = line.number if first is None else first
            values[name] = self._value(line, line.tokens[k], name, kind)
            k += 1
        for name, kind in optional:
            if k >= len(line.tokens) or not self._is_value(line.tokens[k], kind):
                break
            values[name] = self._value(line, line.tokens[k], name, kind)
            k += 1
        return values, first

    @staticmethod
    def _is_value(token: str, kind: str) -> bool:
        if kind == "str":
            return token.startswith("'")
        m = _NUMBER.match(token)
        return bool(m) and (kind == "angle" or not m.group(2))

    def _value(self, line: _Line, token: str, name: str, kind: str) -> Any:
        where = f"{self.path.name}:{line.number}"
        if kind == "str":
            if not (len(token) >= 2 and token.startswith("'") and token.endswith("'")):
                raise InputError(f"{where}: {name} must be a string in single quotes, got {token!r}")
            return token[1:-1]
        if kind == "word":
            if not token.isdigit():
                raise InputError(f"{where}: expected the control word {name} (digits), got {token!r}")
            return token
        m = _NUMBER.match(token)
        if not m:
            raise InputError(f"{where}: expected a number for {name}, got {token!r}")
        text, unit = m.group(1).replace("d", "e").replace("D", "e"), m.group(2).lower()
        if kind == "int":
            if unit or not re.fullmatch(r"[+-]?\d+", m.group(1)):
                raise InputError(f"{where}: {name} must be an integer, got {token!r}")
            return int(text)
        if unit and kind != "angle":
            raise InputError(f"{where}: {name} is not an angle: no unit suffix, got {token!r}")
        v = float(text)
        return math.radians(v) if unit == "d" else v


def _digits(reader: _Reader, word: str, token: str, line: int) -> dict[str, int]:
    letters = word
    if len(token) > len(letters):  # leading zeros too: '02203100' would shift every digit
        raise InputError(
            f"{reader.where(line)}: control word {'-'.join(letters)} has {len(token)} digits "
            f"({token}); it has at most {len(letters)}, one per letter {', '.join(letters)} "
            "(leading zeros may be left out, not added)"
        )
    padded = token[-len(letters) :].rjust(len(letters), "0")
    out = {}
    for letter, name, d in zip(letters, WORDS[word], padded):
        v = int(d)
        ok = SUPPORTED[(word, letter)]
        if v not in ok:
            raise InputError(
                f"{reader.where(line)}: {letter} ({name}) = {v} in {'-'.join(letters)} is not "
                f"supported: railvti reads {letter} = {', '.join(map(str, sorted(ok)))} "
                "(the Manchester benchmark's A-2.2 decks)"
            )
        out[letter] = v
    return out


def _require(cond: bool, reader: _Reader, line: int, message: str) -> None:
    if not cond:
        raise InputError(f"{reader.where(line)}: {message}")


def _keep(state: dict, key: str, reader: _Reader, line: int, flag: str) -> None:
    if key not in state:
        raise InputError(
            f"{reader.where(line)}: {flag} keeps the {key} of a previous case, but no case "
            "before this one set it"
        )


def _profile(reader: _Reader, line: int, values: dict, kind: str) -> dict[str, Any]:
    name = "RFNAME" if kind == "rail" else "WFNAME"
    path = Path(values[name])
    if not path.is_absolute():
        path = reader.path.parent / path
    if path.suffix.lower() in UNSUPPORTED_PROFILES:
        raise InputError(
            f"{reader.where(line)}: {name} '{values[name]}': {path.suffix} profiles are not "
            "supported (SIMPACK .prw/.prr or a two-column table)"
        )
    if not path.is_file():
        raise InputError(
            f"{reader.where(line)}: {kind} profile file {name} = '{values[name]}' not found "
            f"(looked for {path})"
        )
    _require(
        values["MIRRORY"] in (-1, 0, 1), reader, line, f"MIRRORY must be -1, 0 or 1, got {values['MIRRORY']}"
    )
    _require(values["SCALE"] > 0, reader, line, f"SCALE must be > 0, got {values['SCALE']}")
    _require(
        values["SMOOTH"] == 0,
        reader,
        line,
        f"SMOOTH = {values['SMOOTH']}: railvti does not smooth profiles (give 0)",
    )
    _require(
        values.get("MIRRORZ", 0) in (-1, 0),
        reader,
        line,
        f"MIRRORZ = {values.get('MIRRORZ')} is not supported (give 0 or -1: the profile as it is)",
    )
    _require(
        values.get("PRFOPT", 0) == 0,
        reader,
        line,
        f"PRFOPT = {values.get('PRFOPT')} is not supported (give 0)",
    )
    return {
        kind: str(path),
        f"{kind}_mirror_y": int(values["MIRRORY"] == 1),
        f"{kind}_scale": values["SCALE"],
    }


_PROFILE_LINE = [("MIRRORY", "int"), ("SCALE", "real"), ("SMOOTH", "real")]
_PROFILE_OPT = [("MIRRORZ", "int"), ("PRFOPT", "int")]


def _read_track(r: _Reader, state: dict) -> None:
    v, ln = r.group(
        [("GAUGHT", "real"), ("GAUGSQ", "int"), ("GAUGWD", "real"), ("CANT", "angle")], [("CURV", "real")]
    )
    _require(
        v["GAUGHT"] > 0,
        r,
        ln,
        f"GAUGHT = {v['GAUGHT']}: absolute rail placement (GAUGHT <= 0) is not "
        "supported; give the gauge measuring height (> 0)",
    )
    _require(v["GAUGSQ"] == 0, r, ln, f"GAUGSQ = {v['GAUGSQ']} is not supported (give 0)")
    _require(v.get("CURV", 0.0) == 0.0, r, ln, f"CURV = {v.get('CURV')}: track curvature is not supported")
    _require(v["GAUGWD"] > 0, r, ln, f"GAUGWD must be > 0, got {v['GAUGWD']}")
    state["track"] = {"gauge_depth": v["GAUGHT"] * 1e-3, "gauge": v["GAUGWD"] * 1e-3, "cant_rad": v["CANT"]}
    v, ln = r.group([("RFNAME", "str")] + _PROFILE_LINE, _PROFILE_OPT)
    state["track"].update(_profile(r, ln, v, "rail"))
    v, ln = r.group(
        [
            ("DYRAIL", "real"),
            ("DZRAIL", "real"),
            ("DROLLR", "angle"),
            ("VYRAIL", "real"),
            ("VZRAIL", "real"),
            ("VROLLR", "real"),
        ]
    )
    for key, value in v.items():
        _require(value == 0.0, r, ln, f"{key} = {value}: rail deviations are not supported (give 0)")


def _read_wheelset(r: _Reader, state: dict) -> None:
    v, ln = r.group([("FBDIST", "real"), ("FBPOS", "real"), ("NOMRADW", "real")], [("YTAPE", "real")])
    _require(
        abs(v.get("YTAPE", 1e3)) >= 1e3,
        r,
        ln,
        f"YTAPE = {v.get('YTAPE')}: the tape circle computation is not supported (omit YTAPE)",
    )
    _require(v["FBDIST"] > 0 and v["NOMRADW"] > 0, r, ln, "FBDIST and NOMRADW must be > 0")
    state["wheelset"] = {
        "back_to_back": v["FBDIST"] * 1e-3,
        "contact_offset": -v["FBPOS"] * 1e-3,
        "radius": v["NOMRADW"] * 1e-3,
    }
    v, ln = r.group([("WFNAME", "str")] + _PROFILE_LINE, _PROFILE_OPT)
    state["wheelset"].update(_profile(r, ln, v, "wheel"))


def _read_settings(r: _Reader, d: dict[str, int], line: int, state: dict) -> None:
    """Solver limits, friction, material and grid (as the digits say)."""
    if d["G"] == 0:
        r.group(
            [("MAXGS", "int"), ("MAXIN", "int"), ("MAXNR", "int"), ("MAXOUT", "int"), ("EPS", "real")],
            [("NPOT_MAX", "int")],
        )
        state["solver"] = True
    else:
        _keep(state, "solver", r, line, "G (GAUSEI) = 1")
    if d["L"] == 0:
        v, ln = r.group([("FSTAT", "real"), ("FKIN", "real")])
        _require(
            v["FSTAT"] == v["FKIN"],
            r,
            ln,
            f"FSTAT = {v['FSTAT']} and FKIN = {v['FKIN']} differ: railvti's "
            "Coulomb friction has one coefficient",
        )
        _require(v["FSTAT"] >= 0, r, ln, f"FSTAT must be >= 0, got {v['FSTAT']}")
        state["friction"] = {"mu": v["FSTAT"]}
    else:
        _keep(state, "friction", r, line, "L (FRCLAW) = 1")
    if d["C"] == 2:
        v, ln = r.group([("POISS1", "real"), ("POISS2", "real"), ("GG1", "real"), ("GG2", "real")])
        _require(
            v["POISS1"] == v["POISS2"] and v["GG1"] == v["GG2"],
            r,
            ln,
            "POISS 1,2 and GG 1,2 must be equal: railvti's contact model is for quasi-identical bodies",
        )
        _require(v["GG1"] > 0 and 0 <= v["POISS1"] < 0.5, r, ln, "GG must be > 0 and 0 <= POISS < 0.5")
        state["material"] = {"shear_modulus": v["GG1"] * 1e6, "poisson": v["POISS1"]}
    else:
        _keep(state, "material", r, line, "C (INFLCF) = 1")
    if d["D"] == 2:
        v, ln = r.group(
            [
                ("DX", "real"),
                ("DS", "real"),
                ("DQREL", "real"),
                ("A_SEP", "angle"),
                ("D_SEP", "real"),
                ("D_COMB", "real"),
            ],
            [("D_TURN", "real"), ("G_MISS", "real")],
        )
        _require(v["DX"] > 0 and v["DS"] > 0, r, ln, f"DX and DS must be > 0, got {v['DX']}, {v['DS']}")
        _require(
            0 < v["D_COMB"] < v["D_SEP"],
            r,
            ln,
            f"D_COMB and D_SEP must satisfy 0 < D_COMB < D_SEP, got {v['D_COMB']}, {v['D_SEP']}",
        )
        state["grid"] = {
            "dx": v["DX"] * 1e-3,
            "dy": v["DS"] * 1e-3,
            "d_sep": v["D_SEP"] * 1e-3,
            "d_comb": v["D_COMB"] * 1e-3,
        }
    else:
        _keep(state, "grid", r, line, "D (DISCNS) = 1")


def _read_state(r: _Reader) -> dict[str, Any]:
    """Wheelset position and velocity (CONTACT's frame), in railvti's keys and frame."""
    v, ln = r.group(
        [
            ("S", "real"),
            ("Y", "real"),
            ("FZ", "real"),
            ("ROLL", "angle"),
            ("YAW", "angle"),
            ("PITCH", "angle"),
        ]
    )
    _require(v["FZ"] > 0, r, ln, f"FZ must be > 0 (the vertical force on the rail, N), got {v['FZ']}")
    # The angles pass through mrad (x 1e3 x 1e-3), as they did when the keys were roll_mrad
    # and yaw_mrad: bitwise the same inputs, so the benchmark's results stay as stored (a
    # flange case's Mz moves by 3e-9 with a one-ulp change of the yaw).
    out = {"y": -v["Y"] * 1e-3, "fz": v["FZ"], "roll": v["ROLL"] * 1e3 * 1e-3, "yaw": -v["YAW"] * 1e3 * 1e-3}
    v, ln = r.group(
        [
            ("VS", "real"),
            ("VY", "real"),
            ("VZ", "real"),
            ("VROLL", "real"),
            ("VYAW", "real"),
            ("VPITCH", "real"),
        ]
    )
    _require(v["VS"] > 0, r, ln, f"VS = {v['VS']}: railvti rolls forward only (VS > 0)")
    _require(v["VPITCH"] < 0, r, ln, f"VPITCH = {v['VPITCH']}: forward rolling has a negative pitch velocity")
    out.update(
        speed=v["VS"] * 1e-3,
        lateral_velocity=-v["VY"] * 1e-3,
        vertical_velocity=-v["VZ"] * 1e-3,
        roll_rate=v["VROLL"],
        yaw_rate=-v["VYAW"],
        omega=-v["VPITCH"],
    )
    return out


def _read_case(r: _Reader, state: dict, number: int) -> tuple[dict[str, Any], int]:
    w, line = r.group([("CPBTNFS", "word")])
    d1 = _digits(r, "CPBTNFS", w["CPBTNFS"], line)
    w, ln = r.group([("VLDCMZE", "word")], [("M2", "int")])
    d2 = _digits(r, "VLDCMZE", w["VLDCMZE"], ln)
    _require(w.get("M2", 0) == 0, r, ln, f"M2 (MATER2) = {w.get('M2')} is not supported (no damping: 0)")
    w, ln = r.group([("XHGIAOWR", "word")])
    d3 = _digits(r, "XHGIAOWR", w["XHGIAOWR"], ln)
    _read_settings(r, {**d2, **d3}, line, state)
    if d2["Z"] == 3:
        _read_track(r, state)
    else:
        _keep(state, "track", r, line, "Z (ZTRACK) = 0")
    if d2["E"] == 3:
        _read_wheelset(r, state)
    else:
        _keep(state, "wheelset", r, line, "E (EWHEEL) = 2")
    params = dict(wheel_rail_cases.DEFAULTS)
    for key in ("friction", "material", "grid", "track", "wheelset"):
        params.update(state[key])
    params.update(_read_state(r))
    params.update(
        side="left" if d1["C"] == 0 else "right",
        store_fields=d3["A"],
        origin=f"{r.path.name}:{line} (case {number})",
    )
    return params, line


def read_contact_deck(path: str | Path) -> list[Case]:
    """Read a CONTACT wheel-rail deck (module 1) into ``wheel_rail`` cases.

    Parameters
    ----------
    path : str or Path
        The ``.inp`` file. Profile file names in it are relative to its folder.

    Returns
    -------
    list of Case
        One per CONTACT case, named ``<side>_<number>``, of type ``wheel_rail``.

    Raises
    ------
    InputError
        An unreadable file, a module other than 1, an unsupported digit value (named with
        its letter and CONTACT's name), an unsupported or bad value, a profile file that
        does not exist, a case that keeps what no earlier case set, or a deck without
        ``0 MODULE`` at its end; each names the file and line.
    """
    path = Path(path)
    try:
        text = path.read_text(errors="replace")
    except OSError as exc:
        raise InputError(f"cannot read CONTACT deck {path}: {exc.strerror}") from None
    r = _Reader(path, text)
    ctype = REGISTRY["wheel_rail"]
    cases: list[Case] = []
    state: dict[str, Any] = {}
    while True:
        if r.at_end():
            raise InputError(f"{r.where()}: the deck ends without '0 MODULE'")
        v, line = r.group([("MODULE", "int")])
        if v["MODULE"] == 0:
            break
        if v["MODULE"] != 1:
            raise InputError(
                f"{r.where(line)}: MODULE {v['MODULE']} is not supported: railvti reads module 1 "
                "(wheel-rail contact)"
            )
        params, _ = _read_case(r, state, len(cases) + 1)
        cases.append(
            Case(
                index=len(cases) + 1,
                name=f"{params['side']}_{len(cases) + 1}",
                case_type=ctype,
                params=params,
            )
        )
    if not cases:
        raise InputError(f"{path.name}: the deck holds no case")
    return cases


register_deck_reader(".inp", read_contact_deck)

__all__ = ["WORDS", "SUPPORTED", "UNSUPPORTED_PROFILES", "read_contact_deck"]
