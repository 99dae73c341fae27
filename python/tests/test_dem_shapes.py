"""DEM round trips of particles that are not disks: a hand-made table of
superellipses, exported with `gapack export`, loaded by the programs
themselves — LAMMPS (`atom_style body rounded/polygon`, `run 0` with
`pair_style body/rounded/polygon`), VTK's own reader and LIGGGHTS
(`atom_style superquadric`). LAMMPS must see no contact in the packing
and must see one once a particle is pushed 1 % of its size into its
neighbour; VTK must give back every polygon, point for point.

Needs Debian's `lammps` and `liggghts` and the `vtk` Python module;
skipped without them unless GAPACK_DEM_TESTS=required (CI).
"""

from __future__ import annotations

import math
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from conftest import need

CONFIG = """\
seed = 0
[domain]
shape = "rectangle"
width = 20.0
height = 20.0
[grading]
table = [[1.0, 0], [4.0, 100]]
[output]
formats = ["vtk", "lammps", "liggghts-superquadric", "mercury"]
units = "mm"
"""

#: Semi-axes and exponent of the test's superellipses (mm).
A, B, N = 1.5, 1.0, 4.0
#: The gap between neighbours, tip to tip (mm).
GAP = 1e-6


def superellipse_area(a: float, b: float, n: float) -> float:
    """Area of |x/a|^n + |y/b|^n <= 1."""
    return 4 * a * b * math.gamma(1 + 1 / n) ** 2 / math.gamma(1 + 2 / n)


def particles() -> list[tuple[float, float, float]]:
    """Centres and angles: a row along x (angle 0) whose tips all but
    touch, and a column along y (angle pi/2) whose tips all but touch."""
    out = [(2.0 + k * (2 * A + GAP), 3.0, 0.0) for k in range(5)]
    out += [(4.0, 6.0 + k * (2 * A + GAP), math.pi / 2) for k in range(4)]
    return out


def write_table(path: Path) -> None:
    r = math.sqrt(superellipse_area(A, B, N) / math.pi)
    rows = ["id,x,y,r,angle,a,b,alpha,beta"]
    for i, (x, y, t) in enumerate(particles()):
        rows.append(f"{i},{x!r},{y!r},{r!r},{t!r},{A!r},{B!r},{N!r},{N!r}")
    path.write_text("\n".join(rows) + "\n")


@pytest.fixture
def exported(cli, tmp_path) -> Path:
    write_table(tmp_path / "packing.csv")
    (tmp_path / "cfg.toml").write_text(CONFIG)
    done = subprocess.run(
        [str(cli), "export", "packing.csv", "--config", "cfg.toml", "--out", "out"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return tmp_path / "out"


def lammps_input(data: Path) -> str:
    header = data.read_text()
    nmin, nmax = re.search(r"rounded/polygon (\d+) (\d+)", header).groups()
    return f"""\
units           si
dimension       2
boundary        f f p
atom_style      body rounded/polygon {nmin} {nmax}
atom_modify     map array
read_data       {data.name}
pair_style      body/rounded/polygon 1.0 1.0 0.0 0.5 0.0
pair_coeff      * * 1000.0 0.0
comm_modify     vel yes
neighbor        0.5 bin
neigh_modify    every 1 delay 0 check yes
fix             1 all nve/body
fix             2 all enforce2d
thermo_style    custom step pe fnorm
run             0
print           "RESULT $(pe:%.17g) $(fnorm:%.17g)"
"""


def run_lammps(data: Path) -> tuple[float, float]:
    (data.parent / "in.run").write_text(lammps_input(data))
    done = subprocess.run(
        ["lmp", "-in", "in.run", "-log", "none", "-echo", "none"],
        cwd=data.parent,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0 and "ERROR" not in done.stdout, done.stdout[-3000:] + done.stderr
    pe, fnorm = re.search(r"^RESULT (\S+) (\S+)$", done.stdout, re.M).groups()
    return float(pe), float(fnorm)


def pushed(data: Path, shift: float) -> Path:
    """A copy of the data file with atom 1 moved `shift` (mm) along +x,
    into its neighbour."""
    lines = data.read_text().splitlines()
    start = lines.index("Atoms # body") + 2
    parts = lines[start].split()
    assert parts[0] == "1"
    parts[4] = repr(float(parts[4]) + shift)
    lines[start] = " ".join(parts)
    out = data.with_name("pushed.lammps")
    out.write_text("\n".join(lines) + "\n")
    return out


def test_lammps_reads_the_bodies_and_sees_contacts_only_when_pushed(exported):
    need(shutil.which("lmp") is not None, "LAMMPS is not installed: apt-get install lammps")
    data = exported / "packing.lammps"
    text = data.read_text()
    assert f"{len(particles())} bodies" in text
    pe, fnorm = run_lammps(data)
    assert pe == 0.0 and fnorm == 0.0, (pe, fnorm)
    r = math.sqrt(superellipse_area(A, B, N) / math.pi)
    pe, fnorm = run_lammps(pushed(data, 0.01 * 2 * r))
    assert pe > 0.0 and fnorm > 0.0, (pe, fnorm)


def test_vtk_reader_recovers_every_polygon(exported):
    try:
        import vtk  # noqa: PLC0415
        from vtk.util.numpy_support import vtk_to_numpy  # noqa: PLC0415
    except ImportError:
        need(False, "the vtk Python module is not installed: pip install vtk")
        return
    reader = vtk.vtkPolyDataReader()
    reader.SetFileName(str(exported / "packing.vtk"))
    # Every SCALARS block, not only the first (ParaView reads them all).
    reader.ReadAllScalarsOn()
    reader.ReadAllVectorsOn()
    reader.Update()
    data = reader.GetOutput()
    placed = particles()
    assert data.GetNumberOfPolys() == len(placed)
    points = vtk_to_numpy(data.GetPoints().GetData())
    angle = vtk_to_numpy(data.GetCellData().GetArray("angle"))
    a = vtk_to_numpy(data.GetCellData().GetArray("a"))
    centre = vtk_to_numpy(data.GetCellData().GetArray("centre"))
    polys = data.GetPolys()
    polys.InitTraversal()
    ids = vtk.vtkIdList()
    for i, (x, y, t) in enumerate(placed):
        assert polys.GetNextCell(ids)
        corners = points[[ids.GetId(k) for k in range(ids.GetNumberOfIds())]]
        assert len(corners) == 64
        assert angle[i] == t and a[i] == A
        assert tuple(centre[i][:2]) == (x, y)
        # Every point on the superellipse, back in the particle's own axes.
        dx, dy = corners[:, 0] - x, corners[:, 1] - y
        u = math.cos(t) * dx + math.sin(t) * dy
        v = -math.sin(t) * dx + math.cos(t) * dy
        level = np.abs(u / A) ** N + np.abs(v / B) ** N
        assert np.all(np.abs(level - 1.0) < 1e-9), level
        assert np.all(corners[:, 2] == 0.0)


def test_liggghts_reads_the_superquadrics(exported):
    data = exported / "packing.superquadric.data"
    lines = [l for l in data.read_text().splitlines()]
    start = lines.index("Atoms") + 2
    rows = [l.split() for l in lines[start:] if l.strip()]
    placed = particles()
    # id type density shapex shapey shapez blockiness1 blockiness2 x y z
    assert len(rows) == len(placed)
    for i, (row, (x, y, _)) in enumerate(zip(rows, placed)):
        assert len(row) == 11
        assert int(row[0]) == i + 1
        assert [float(v) for v in row[3:8]] == [A, B, 0.5 * B, N, N]
        assert (float(row[8]), float(row[9]), float(row[10])) == (x, y, 0.0)
    turns = (exported / "packing.superquadric.in").read_text().splitlines()[1:]
    assert [float(l.split()[-1]) for l in turns] == [math.degrees(t) for (_, _, t) in placed]
    need(shutil.which("liggghts") is not None, "LIGGGHTS is not installed: apt-get install liggghts")
    probe = subprocess.run(["liggghts", "-h"], capture_output=True, text=True, timeout=60)
    styles = re.search(r"\* Atom styles:(.*?)\n\* ", probe.stdout, re.S)
    if styles is None or "superquadric" not in styles.group(1).split():
        pytest.skip("this LIGGGHTS build has no atom_style superquadric (built without superquadrics)")
    script = f"""\
atom_style      superquadric
atom_modify     map array
boundary        f f f
newton          off
communicate     single vel yes
units           si
read_data       {data.name}
include         packing.superquadric.in
print           "RESULT $(count(all))"
"""
    (exported / "in.sq").write_text(script)
    done = subprocess.run(
        ["liggghts", "-in", "in.sq", "-log", "none", "-echo", "none"],
        cwd=exported,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0 and "ERROR" not in done.stdout, done.stdout[-3000:] + done.stderr
    assert f"RESULT {len(placed)}" in done.stdout


SHAPE_CONFIG = """\
seed = 0
[domain]
shape = "rectangle"
width = 20.0
height = 20.0
[grading]
constant = 2.0
[shape]
kind = "superellipse"
aspect = 1.5
alpha = 4.0
size = "sieve"
"""


def test_verify_certifies_the_particles_and_finds_a_push(cli, tmp_path):
    """verify proves the superellipses apart and inside (their least width
    2b the grading's size), and finds the overlap once one is pushed 1 %
    of its size into its neighbour."""
    write_table(tmp_path / "packing.csv")
    (tmp_path / "cfg.toml").write_text(SHAPE_CONFIG)

    def verify(name):
        return subprocess.run(
            [str(cli), "verify", name, "--config", "cfg.toml"],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            timeout=120,
        )

    done = verify("packing.csv")
    assert done.returncode == 0, done.stdout + done.stderr
    assert ": valid" in done.stdout, done.stdout
    rows = (tmp_path / "packing.csv").read_text().splitlines()
    cells = rows[2].split(",")
    cells[1] = repr(float(cells[1]) - 0.01 * 2 * B)
    rows[2] = ",".join(cells)
    (tmp_path / "pushed.csv").write_text("\n".join(rows) + "\n")
    done = verify("pushed.csv")
    assert done.returncode == 1, done.stdout + done.stderr
    assert "FAILED" in done.stdout and "overlap" in done.stderr, done.stdout + done.stderr
