"""The status vocabulary: Fortran's codes (common_status) and Python's translator agree."""

from __future__ import annotations

import pytest

from railvti import _status
from railvti.errors import ConvergenceError, GridTooSmallError, InputError, RailvtiError


def test_every_fortran_code_has_the_same_name_in_python():
    last = _status.last_code()
    assert last == max(_status.Status)
    for code in range(last + 1):
        name, msg = _status.describe(code)
        assert name == _status.Status(code).name
        assert msg and msg != "unknown status code"


def test_codes_are_distinct_and_unknown_code_is_reported():
    assert len({int(s) for s in _status.Status}) == len(_status.Status)
    assert _status.describe(_status.last_code() + 1)[0] == "UNKNOWN"
    err = _status.error(987, "some kernel")
    assert type(err) is RailvtiError and "987" in str(err)


def test_every_failing_code_maps_to_an_exception_naming_the_context():
    for code in _status.Status:
        if code == _status.Status.OK:
            continue
        err = _status.error(code, "the context")
        assert isinstance(err, _status.EXCEPTIONS[code])
        assert str(err).startswith("the context: ") and code.name in str(err)


def test_check_raises_the_mapped_class_and_passes_ok():
    _status.check(_status.Status.OK, "nothing")
    with pytest.raises(GridTooSmallError):
        _status.check(_status.Status.GRID_EDGE, "patch")
    with pytest.raises(InputError):
        _status.check(_status.Status.BAD_ARGUMENT, "x")
    with pytest.raises(ConvergenceError) as e:
        _status.check(_status.Status.NOT_CONVERGED, "cg", iterations=7, residual=0.5)
    assert e.value.iterations == 7 and e.value.residual == 0.5
