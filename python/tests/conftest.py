"""Shared fixtures of the Python package's tests (run by .ci/run:
``pytest python/tests``).

External programs: the gapack command line (for the comparisons with it)
is found as ``$GAPACK_BIN``, else ``target/{release,debug}/gapack`` under
``$CARGO_TARGET_DIR`` or the checkout; the DEM programs (``lmp``,
``liggghts``, Debian's ``/usr/bin/python3`` with ``python3-lammps``) and
the ``vtk`` module on PATH. A test whose program is missing is skipped,
saying which, unless ``GAPACK_DEM_TESTS=required`` (CI), which fails it.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CONFIGS = ROOT / "configs"


def required() -> bool:
    return os.environ.get("GAPACK_DEM_TESTS") == "required"


def need(condition: bool, what: str) -> None:
    """Skip (or in CI fail) the test when ``condition`` is false."""
    if condition:
        return
    if required():
        pytest.fail(f"GAPACK_DEM_TESTS=required but {what}")
    pytest.skip(what)


def gapack_bin():
    given = os.environ.get("GAPACK_BIN")
    if given:
        return Path(given)
    roots = [Path(os.environ["CARGO_TARGET_DIR"])] if os.environ.get("CARGO_TARGET_DIR") else []
    roots.append(ROOT / "target")
    for root in roots:
        for profile in ("release", "debug"):
            candidate = root / profile / "gapack"
            if candidate.is_file():
                return candidate
    return None


@pytest.fixture(scope="session")
def cli() -> Path:
    """The gapack command line."""
    found = gapack_bin()
    need(found is not None and found.is_file(), "no gapack binary: set GAPACK_BIN or build it (cargo build --release)")
    return found


@pytest.fixture
def work(tmp_path, monkeypatch) -> Path:
    """A clean folder holding a copy of configs/, made the current directory."""
    shutil.copytree(CONFIGS, tmp_path / "configs")
    monkeypatch.chdir(tmp_path)
    return tmp_path


SQUARE = """\
seed = 4
[domain]
shape = "rectangle"
width = 30
height = 20
[grading]
uniform = [1.0, 2.0]
"""
