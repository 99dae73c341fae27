"""The examples of examples/python/ run as their docstrings say.

The porosity study runs under this Python. The LAMMPS example runs under
Debian's /usr/bin/python3 (where Debian's python3-lammps lives) with this
gapack's package folder on PYTHONPATH (its abi3 extension loads in any
CPython >= 3.9): required in CI (GAPACK_DEM_TESTS=required). The YADE
example and the YADE and ESyS-Particle round trips run when those programs
are installed (Debian: yade, esys-particle), and are skipped otherwise,
even in CI (heavy installs; GAPACK_HEAVY_DEM_TESTS=required makes them
required).
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

import gapack
from conftest import ROOT, need

EXAMPLES = ROOT / "examples" / "python"
DEBIAN_PYTHON = "/usr/bin/python3"


def heavy(condition: bool, what: str) -> None:
    if condition:
        return
    if os.environ.get("GAPACK_HEAVY_DEM_TESTS") == "required":
        pytest.fail(f"GAPACK_HEAVY_DEM_TESTS=required but {what}")
    pytest.skip(what)


@pytest.fixture
def gapack_path(tmp_path) -> dict:
    """An environment whose PYTHONPATH holds a copy of this gapack package alone."""
    folder = tmp_path / "pythonpath"
    shutil.copytree(Path(gapack.__file__).parent, folder / "gapack", ignore=shutil.ignore_patterns("__pycache__"))
    return {**os.environ, "PYTHONPATH": str(folder)}


def run(command, env=None, timeout=600) -> str:
    """Run ``command`` in its own process group; its output, or a failure with it."""
    process = subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env, start_new_session=True
    )
    try:
        output, _ = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        # An MPI program whose master failed leaves its workers waiting.
        os.killpg(process.pid, signal.SIGKILL)
        output, _ = process.communicate()
        pytest.fail(f"{command} did not end in {timeout} s:\n{output[-3000:]}")
    assert process.returncode == 0, f"{command} failed ({process.returncode}):\n{output[-3000:]}"
    return output


def test_porosity_study(work):
    pytest.importorskip("matplotlib")
    output = run([sys.executable, str(EXAMPLES / "porosity_study.py")])
    lines = [line for line in output.splitlines() if line.startswith("target ")]
    assert len(lines) == 9
    assert sum(line.endswith(", reached") for line in lines) >= 7, output
    assert (work / "out" / "porosity_study" / "porosity_study.png").stat().st_size > 10_000
    assert (work / "out" / "porosity_study" / "densest" / "packing.lammps").is_file()


def lammps_module() -> bool:
    if not Path(DEBIAN_PYTHON).is_file():
        return False
    probe = subprocess.run([DEBIAN_PYTHON, "-c", "import lammps, numpy; lammps.lammps(cmdargs=['-screen', 'none', '-log', 'none']).close()"], capture_output=True)
    return probe.returncode == 0


@pytest.mark.parametrize("config", ["configs/fgm_power.toml", "configs/periodic_pfc.toml"])
def test_lammps_example(work, gapack_path, config):
    need(lammps_module(), "LAMMPS' Python module is missing for /usr/bin/python3: apt-get install python3-lammps liblammps-dev")
    output = run([DEBIAN_PYTHON, str(EXAMPLES / "lammps_from_arrays.py"), config], env=gapack_path)
    print(output)
    made = next(line for line in output.splitlines() if line.startswith("LAMMPS: ") and "made from the arrays" in line)
    n = len(gapack.pack(config, seed=1)) if "fgm" not in config else len(gapack.layer(config, seed=1))
    assert made.startswith(f"LAMMPS: {n} atoms made from the arrays, deepest overlap ")
    assert "pushed 1 % of its radius" in output


def test_yade_example(work, gapack_path):
    heavy(shutil.which("yade") is not None, "YADE is not installed (apt-get install yade)")
    output = run(["yade", "-n", "-x", str(EXAMPLES / "yade_from_arrays.py")], env=gapack_path)
    print(output[output.index("gapack:"):])
    assert "YADE: 1635 spheres appended from the arrays" in output
    assert "pushed 1 % of its radius" in output


@pytest.mark.parametrize("config", ["configs/fgm_power.toml", "configs/periodic_pfc.toml"])
def test_yade_round_trip(work, gapack_path, config):
    heavy(shutil.which("yade") is not None, "YADE is not installed (apt-get install yade)")
    output = run(["yade", "-n", "-x", str(EXAMPLES / "roundtrip_yade.py"), config, "out/yade"], env=gapack_path)
    print(output[output.index("YADE read"):])
    assert output.rstrip().endswith("YADE round trip: passed")


@pytest.mark.parametrize("config", ["configs/fgm_power.toml", "configs/periodic_pfc.toml"])
def test_esys_round_trip(work, gapack_path, config):
    heavy(shutil.which("esysparticle") is not None and shutil.which("mpirun") is not None, "ESyS-Particle is not installed (apt-get install esys-particle)")
    root = ["--allow-run-as-root"] if os.geteuid() == 0 else []
    command = ["mpirun", *root, "--oversubscribe", "-np", "2", "esysparticle", str(EXAMPLES / "roundtrip_esys.py"), config, "out/esys"]
    output = run(command, env=gapack_path, timeout=300)
    print(output[output.index("ESyS-Particle read"):])
    assert "ESyS-Particle round trip: passed" in output
