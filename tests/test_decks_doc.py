"""docs/decks.md: its table of plausibility bounds is what the deck check enforces, and every
case type it names exists."""

from pathlib import Path

from railvti.runner.deck_registry import case_types

DOC = Path(__file__).resolve().parents[1] / "docs" / "decks.md"


def _rows():
    rows = []
    for line in DOC.read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 4 and cells[0] not in ("type", "---") and not cells[0].startswith("-"):
            rows.append(cells)
    return rows


def test_bounds_table_matches_the_checks():
    types = case_types()
    rows = _rows()
    assert len(rows) >= 20
    for tname, key, allowed, _ in rows:
        assert tname in types, tname
        spec = types[tname].keys[key]
        assert spec.bounds() == allowed, (tname, key, spec.bounds(), allowed)


def test_every_case_type_has_documented_keys():
    """Every key of every case type has a unit and a meaning (for `railvti cases`)."""
    for tname, ct in case_types().items():
        missing = [k for k in ct.defaults if k not in ct.keys or not ct.keys[k].meaning]
        assert not missing, (tname, missing)


def test_aliases_name_no_key_and_point_to_one():
    for tname, ct in case_types().items():
        for alias, a in ct.aliases.items():
            assert alias not in ct.defaults, (tname, alias)
            assert a.key in ct.defaults, (tname, alias, a.key)


def test_cases_command_prints_units_meaning_and_bounds(capsys):
    from railvti.runner.cli import main

    assert main(["cases", "rolling"]) == 0
    out = capsys.readouterr().out
    assert "type = 'rolling'" in out and "type = 'normal'" not in out
    mu = next(line for line in out.splitlines() if line.split()[:1] == ["mu"])
    assert "friction" in mu and "(0, 1]" in mu
    speed = next(line for line in out.splitlines() if line.split()[:1] == ["speed"])
    assert " m/s " in speed
    assert main(["cases"]) == 0
    out = capsys.readouterr().out
    assert all(f"type = '{t}'" in out for t in case_types())
    assert "alias of 'speed'" in out and "km/h" in out


def test_cases_command_unknown_type(capsys):
    from railvti.runner.cli import main

    assert main(["cases", "rollin"]) == 2
    assert "did you mean 'rolling'" in capsys.readouterr().err
