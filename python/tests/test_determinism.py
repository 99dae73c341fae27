"""Same config and seed: the same files as the command line, byte for
byte, but for the times a run records."""

from __future__ import annotations

import csv
import io
import json
import re
import subprocess
import warnings
from pathlib import Path

import numpy as np
import pytest

import gapack

ALL_FORMATS = '["csv", "json", "vtk", "lammps", "yade", "pfc", "mercury", "esys", "svg", "png"]'


def untimed(name: str, data: bytes) -> bytes:
    """A file with the times of the run taken out: every JSON key naming
    seconds, and the `seconds` column of convergence.csv."""
    if name.endswith(".json"):
        def strip(value):
            if isinstance(value, dict):
                return {k: strip(v) for k, v in value.items() if "seconds" not in k}
            if isinstance(value, list):
                return [strip(v) for v in value]
            return value

        return json.dumps(strip(json.loads(data)), sort_keys=True).encode()
    if name == "convergence.csv":
        rows = list(csv.reader(io.StringIO(data.decode())))
        assert rows[0][-1] == "seconds"
        return "\n".join(",".join(row[:-1]) for row in rows).encode()
    return data


@pytest.mark.parametrize(
    ("job", "config", "seed"),
    [
        ("pack", "configs/square_100.toml", 7),
        ("pack", "configs/periodic_pfc.toml", 2),
        ("optimise", "configs/ap4.toml", 2),
        ("layer", "configs/fgm_power.toml", 3),
    ],
)
def test_the_same_files_as_the_command_line(work, cli, job, config, seed):
    path = Path(config)
    text = path.read_text()
    if "[output]" in text:
        text = re.sub(r"^formats = .*$", f"formats = {ALL_FORMATS}", text, flags=re.M)
    else:
        text += f"\n[output]\nformats = {ALL_FORMATS}\n"
    path.write_text(text)
    run = subprocess.run(
        [str(cli), job, config, "--seed", str(seed), "--out", "by_cli", "--quiet"],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr
    with warnings.catch_warnings():
        # A table the job ignores is the command line's warning too: not this test's subject.
        warnings.simplefilter("ignore", gapack.GapackWarning)
        packing = getattr(gapack, job)(config, seed=seed)
    written = packing.write("by_python")
    by_cli = sorted(p.name for p in Path("by_cli").iterdir())
    assert written == by_cli
    assert {"packing.lammps", "packing.vtk", "packing.yade.txt", "packing.geo", "packing.png"} <= set(written)
    timed = {"summary.json", "packing.json", "convergence.csv"}
    for name in written:
        a = (work / "by_cli" / name).read_bytes()
        b = (work / "by_python" / name).read_bytes()
        if name in timed:
            a, b = untimed(name, a), untimed(name, b)
        assert a == b, f"{name} differs from the command line's"
    # And the arrays are packing.csv's numbers, exactly.
    table = np.genfromtxt(work / "by_cli" / "packing.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert np.array_equal(table["x"], packing.x) and np.array_equal(table["y"], packing.y)
    assert np.array_equal(table["r"], packing.r)
    if packing.material is not None:
        names = [m["name"] for m in packing.materials]
        assert [names[i] for i in packing.material] == list(table["material"])

