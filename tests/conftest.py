"""The test session's disk cache (railvti._cache): a temporary folder, shared by the session's
processes (subprocesses and Dask workers inherit the environment) and removed at its end, so
that tests never write in the user's cache folder and start from an empty cache."""

from __future__ import annotations

import os
import shutil
import tempfile

_ENV = "RAILVTI_CACHE_DIR"
_state: dict[str, str | None] = {}


def pytest_configure(config) -> None:
    _state["saved"] = os.environ.get(_ENV)
    _state["folder"] = tempfile.mkdtemp(prefix="railvti-test-cache-")
    os.environ[_ENV] = _state["folder"]


def pytest_unconfigure(config) -> None:
    saved, folder = _state.get("saved"), _state.get("folder")
    if saved is None:
        os.environ.pop(_ENV, None)
    else:
        os.environ[_ENV] = saved
    if folder:
        shutil.rmtree(folder, ignore_errors=True)
