"""Input decks: Fortran namelist files of ``&case ... /`` groups, parsed with f90nml, and
CONTACT's wheel-rail decks (``.inp``, read by :mod:`railvti.contact.contact_deck`).

Example::

    &case
        name = 'hertz_circle'
        type = 'normal'
        nx = 64, ny = 64, dx = 1.0e-4, dy = 1.0e-4
        gap = 'hertz', gap_a = 1.087, gap_b = 1.087
        fn = 1.0e4
    /

Every group must be ``&case``; its ``type`` selects a registered case type
(:mod:`railvti.casetypes`) whose keys it may use. The whole deck is checked
before any case runs, and every problem is reported at once, each naming the case
and the key (or the line): the text (UTF-8, a byte-order mark allowed; UTF-16 refused by
name; no NUL or other control bytes), the namelist syntax (quotes closed on
their line, each key once per group), the case names (safe HDF5 group names), and
each value (type, range, plausibility bound, consistency between keys: see
:meth:`railvti.casetypes.CaseType.problems` and ``railvti cases TYPE``).
"""

from __future__ import annotations

import codecs
import contextlib
import dataclasses
import difflib
import io
import re
from pathlib import Path
from typing import Any

import f90nml

from ..casetypes import MAX_NAME, REQUIRED, Case, CaseType, name_problem  # noqa: F401 (Case, MAX_NAME: names of this module too)
from .deck_registry import case_types, deck_readers
from .sweeps import expand, split_sweep
from ..errors import InputError

#: Most cases in one deck (f90nml's time grows with the square of the groups: 1000 take ~0.5 s).
MAX_CASES = 1000
#: Most cases of a deck with its sweeps' points.
MAX_TASKS = 10000
#: Most problems listed in one message (the rest are counted).
MAX_LISTED = 40


def _suggest(key: str, known: list[str]) -> str:
    close = difflib.get_close_matches(key, known, n=1, cutoff=0.5)
    return f" (did you mean '{close[0]}'?)" if close else ""


def decode_deck(data: bytes, source: str = "deck") -> str:
    """The text of a deck file's bytes: UTF-8 (a byte-order mark is dropped).

    Raises
    ------
    InputError
        UTF-16 or UTF-32 text (named by its byte-order mark), bytes that are not UTF-8 (a
        Latin-1 or binary file), a NUL or another control byte; the message names the line
        and column.
    """
    for bom, name in (
        (codecs.BOM_UTF32_LE, "UTF-32"),
        (codecs.BOM_UTF32_BE, "UTF-32"),
        (codecs.BOM_UTF16_LE, "UTF-16"),
        (codecs.BOM_UTF16_BE, "UTF-16"),
    ):
        if data.startswith(bom):
            raise InputError(
                f"{source}: line 1: the deck is {name} text (byte-order mark "
                f"{bom.hex(' ').upper()}); save it as UTF-8"
            )
    if data.startswith(codecs.BOM_UTF8):
        data = data[len(codecs.BOM_UTF8) :]
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        col = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise InputError(
            f"{source}: line {line}, column {col}: byte 0x{data[exc.start]:02X} is not UTF-8 text "
            "(a Latin-1 or binary file? save the deck as UTF-8)"
        ) from None
    return check_text(text, source)


def check_text(text: str, source: str = "deck") -> str:
    """Return ``text`` without a leading byte-order mark; raise InputError naming the line of
    a NUL or another control character (a binary file)."""
    text = text.removeprefix("\ufeff")
    bad = re.search(r"[\x00-\x08\x0b\x0e-\x1f\x7f]", text)
    if bad:
        line = text.count("\n", 0, bad.start()) + 1
        col = bad.start() - (text.rfind("\n", 0, bad.start()) + 1) + 1
        what = "a NUL byte" if bad.group() == "\x00" else f"the control character 0x{ord(bad.group()):02X}"
        raise InputError(
            f"{source}: line {line}, column {col}: {what} (a binary file, or a deck saved "
            "as UTF-16 without byte-order mark? a deck is text)"
        )
    return text


_TOKEN = re.compile(r"&(\w+)|(/)|(?<![\w.&%])([A-Za-z_]\w*)[ \t]*(\([^)]{0,80}\))?[ \t]*=(?!=)")


def _scan(text: str) -> tuple[list[str], list[dict[str, list[int]]]]:
    """Syntax problems f90nml reports badly (quotes, indexed keys) and the keys of each group
    with their lines (f90nml silently keeps the last of a duplicated key)."""
    problems: list[str] = []
    groups: list[dict[str, list[int]]] = []
    current: dict[str, list[int]] | None = None
    for ln, line in enumerate(text.split("\n"), 1):
        buf = []
        quote, qcol = "", 0
        for i, ch in enumerate(line):
            if quote:
                if ch == quote:
                    quote = ""
                    buf.append(ch)
                else:
                    buf.append(" ")
            elif ch in "'\"":
                quote, qcol = ch, i + 1
                buf.append(ch)
            elif ch == "!":
                break
            else:
                buf.append(ch)
        if quote:
            problems.append(
                f"line {ln}: unbalanced quote: the {quote} opened at column {qcol} is not closed on its line"
            )
        clean = "".join(buf)
        for m in re.finditer(r"=", clean):
            j = m.start() - 1
            while j >= 0 and clean[j] in " \t\r\f":
                j -= 1
            if j < 0 or not (clean[j].isalnum() or clean[j] in "_)"):
                problems.append(f"line {ln}, column {m.start() + 1}: '=' without a key name before it")
        for m in _TOKEN.finditer(clean):
            if m.group(1):
                if m.group(1).lower() == "end":
                    current = None
                else:
                    current = {}
                    groups.append(current)
            elif m.group(2):
                current = None
            elif current is not None:
                key = m.group(3).lower()
                if m.group(4):
                    problems.append(
                        f"line {ln}: key '{key}{m.group(4)}': element assignment is not "
                        f"supported; give all values of '{key}' at once"
                    )
                current.setdefault(key, []).append(ln)
    return problems, groups


def _build_case(
    index: int, group: dict[str, Any], lines: dict[str, list[int]], types: dict[str, CaseType]
) -> tuple[Case | None, list[str]]:
    """A case from one namelist group, and the problems of its keys (not yet its values)."""
    group = {k: v for k, v in group.items() if not str(k).startswith("_start_index")}
    raw_name = group.pop("name", None)
    name = raw_name if isinstance(raw_name, str) and raw_name else None
    where = f"case {index}" + (f" '{name[:40]}{'...' if len(name) > MAX_NAME else ''}'" if name else "")
    problems = [
        f"{where}: key '{k}' is given {len(v)} times (lines {', '.join(map(str, sorted(set(v))[:10]))}"
        f"{', ...' if len(set(v)) > 10 else ''}): give it once"
        for k, v in lines.items()
        if len(v) > 1
    ]
    if raw_name is not None and (msg := name_problem(raw_name)):
        problems.append(f"{where}: {msg}")
    tname = group.pop("type", None)
    if tname is None:
        return None, problems + [f"{where}: missing key 'type' (one of {', '.join(sorted(types))})"]
    if not isinstance(tname, str):
        return None, problems + [f"{where}: key 'type' must be a text in quotes, got {tname!r}"]
    tname = tname.strip().lower()
    if tname not in types:
        return None, problems + [
            f"{where}: unknown type '{tname}'{_suggest(tname, sorted(types))}; "
            f"known types: {', '.join(sorted(types))}"
        ]
    ctype = types[tname]
    known = sorted(set(ctype.defaults) | set(ctype.aliases))
    given = {}
    for key, value in group.items():
        if key not in ctype.defaults and key not in ctype.aliases:
            problems.append(f"{where}: unknown key '{key}' for type '{tname}'{_suggest(key, known)}")
        elif value is None:
            problems.append(f"{where}: key '{key}' has no value")
        else:
            given[key] = value
    written = ctype.aliases_written(given)
    given, alias_problems = ctype.resolve_aliases(given)
    problems += [f"{where}: {p}" for p in alias_problems]
    params = {}
    for key, default in ctype.defaults.items():
        if key in given:
            params[key] = given[key]
            spec = ctype.keys.get(key)
            if spec is not None and spec.choices and isinstance(given[key], str):
                params[key] = spec.choice(given[key]) or given[key]
        elif default is not REQUIRED:  # a missing required key: CaseType.problems names it
            params[key] = default
    name = name or f"{tname}_{index}"
    return Case(index=index, name=str(name), case_type=ctype, params=params, written=written), problems


def check_cases(cases: list[Case]) -> list[str]:
    """Every problem of the cases' values (type, range, plausibility, consistency between
    keys) and names, each naming the case and the key; empty if all may run."""
    out = []
    for c in cases:
        msg = name_problem(c.name)
        if msg:
            out.append(f"{c.label}: {msg}")
        out.extend(f"{c.label}: {p}" for p in c.case_type.problems(c.params, c.written))
    return out


def _raise(problems: list[str]) -> None:
    if problems:
        if len(problems) == 1:
            raise InputError(problems[0])
        listed = problems[:MAX_LISTED]
        more = f"\n  ... and {len(problems) - len(listed)} more" if len(problems) > len(listed) else ""
        raise InputError(f"the deck has {len(problems)} problems:\n  " + "\n  ".join(listed) + more)


_NUMBERISH = re.compile(r"[-+]?[0-9.]*(?:[eEdD][-+]?[0-9]*)?")


def _bad_value_line(lines: list[str], start: int, stop: int) -> int | None:
    """The number (from 1) of the first line in ``lines[start:stop]`` with a value that
    looks like a number cut short ('82.0e', '-', '1.5e+'), or None."""
    for i in range(start, stop):
        code = re.sub(r"'[^']*'|\"[^\"]*\"", "''", lines[i]).split("!")[0]
        for part in code.split("=")[1:]:
            for tok in re.split(r"[\s,/]+", part):
                if tok and _NUMBERISH.fullmatch(tok) and (re.search(r"[0-9]", tok) or tok in "+-."):
                    try:
                        float(tok.replace("d", "e").replace("D", "e"))
                    except ValueError:
                        return i + 1
    return None


def _namelist_error(text: str, exc: Exception) -> str:
    """A message for f90nml's failure on ``text`` that names the line: the group the deck
    ends inside (a truncated file), a value cut short, or the group f90nml cannot read."""
    detail = str(exc).strip()
    if isinstance(exc, AssertionError) or not detail:  # f90nml's bare asserts say nothing
        detail = "a malformed value"
    hint = "check the quotes, the 'key = value' pairs and the '/' that closes each group"
    lines = text.split("\n")
    starts = [i for i, ln in enumerate(lines) if re.match(r"\s*&(?!end\b)", ln, re.IGNORECASE)]
    for j, start in enumerate(starts):
        stop = starts[j + 1] if j + 1 < len(starts) else len(lines)
        chunk = "\n".join(lines[start:stop])
        try:
            with contextlib.redirect_stdout(io.StringIO()):
                f90nml.reads(chunk)
            continue
        except Exception:
            pass
        bad = _bad_value_line(lines, start, stop)
        if bad is not None:
            return (
                f"line {bad}: a value that is not a number (cut short? e.g. '82.0e' or '-'): "
                f"'{lines[bad - 1].strip()[:60]}' in the group of line {start + 1}"
            )
        code = [re.sub(r"'[^']*'|\"[^\"]*\"", "''", ln).split("!")[0] for ln in lines[start:stop]]
        if not any("/" in c for c in code) and j == len(starts) - 1:
            last = max((i + 1 for i in range(start, stop) if lines[i].strip()), default=start + 1)
            return (
                f"line {last}: the deck ends inside the group opened at line {start + 1} "
                "(no '/' closes the namelist group: a truncated file?)"
            )
        return f"lines {start + 1}-{stop}: the group is not a valid Fortran namelist group ({detail}): {hint}"
    return f"deck is not a valid Fortran namelist ({detail}): {hint}"


def parse_deck(text: str) -> list[Case]:
    """Parse and check the text of a deck: every problem is collected, then raised at once.

    Raises
    ------
    InputError
        A control byte, a syntax error, a group other than ``&case``, a key given twice, an
        unknown type or key, a key without a value, a missing required key, an unsafe case
        name, a value of the wrong type, out of range or implausible (each named).
    """
    text = check_text(text)
    problems, scanned = _scan(text)
    if len(scanned) > MAX_CASES:
        problems.append(f"the deck has {len(scanned)} groups; at most {MAX_CASES} cases per deck (split it)")
    _raise(problems)
    out = io.StringIO()
    try:
        with contextlib.redirect_stdout(out):  # f90nml prints its token table on some errors
            nml = f90nml.reads(text)
    except Exception as exc:  # f90nml raises ValueError, AssertionError and others on syntax errors
        raise InputError(_namelist_error(text, exc)) from None
    groups: list[dict[str, Any]] = []
    for gname in dict.fromkeys(str(k) for k in nml.keys()):  # cogroup keys print as the name
        if gname != "case":
            raise InputError(f"unknown namelist group '&{gname}': a deck holds only '&case' groups")
        value = nml[gname]
        groups.extend(value if isinstance(value, list) else [value])
    if not groups:
        raise InputError("deck holds no '&case' group" + (" (is '&case' misspelt?)" if text.strip() else ""))
    types = case_types()
    if len(scanned) != len(groups):
        scanned = [{} for _ in groups]
    cases = []
    for i, g in enumerate(groups):
        g, spec, sweep_probs = split_sweep(dict(g))
        case, probs = _build_case(i + 1, g, scanned[i], types)
        problems += probs + [f"case {i + 1}: {p}" for p in sweep_probs]
        points = [case] if case is not None else []
        if case is not None and spec is not None and not sweep_probs:
            points, probs = expand(case, spec, given=[k for k in g if k not in ("name", "type")])
            problems += [f"{case.label}: {p}" for p in probs]
        for c in points:  # its values too, whatever else is wrong with it
            if c.index != len(cases) + 1:  # numbered in the deck's order of cases and points
                c = dataclasses.replace(c, index=len(cases) + 1)
            problems += [f"{c.label}: {p}" for p in c.case_type.problems(c.params, c.written)]
            cases.append(c)
    if len(cases) > MAX_TASKS:
        problems.append(f"the deck makes {len(cases)} cases with its sweeps; at most {MAX_TASKS}")
    _raise(problems)
    return cases


def read_deck(path: str | Path) -> list[Case]:
    """Read and check a deck file: a namelist deck (see :func:`parse_deck`), or a CONTACT
    wheel-rail deck if its name ends in ``.inp`` (:func:`railvti.contact.contact_deck.read_contact_deck`).
    Every case's values are checked (:func:`check_cases`) before this returns."""
    path = Path(path)
    reader = deck_readers(path.suffix).get(path.suffix.lower())
    if reader is not None:
        cases = reader(path)
        _raise(check_cases(cases))
        return cases
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"cannot read deck {path}: {exc.strerror}") from None
    return parse_deck(decode_deck(data, str(path)))


__all__ = [
    "MAX_CASES",
    "MAX_TASKS",
    "MAX_LISTED",
    "decode_deck",
    "check_text",
    "check_cases",
    "parse_deck",
    "read_deck",
]
