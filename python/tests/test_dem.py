"""DEM round trips: what gapack writes, loaded by the DEM programs
themselves — LAMMPS and LIGGGHTS (`read_data`, then `run 0` with a granular
pair style) and VTK's own reader — checked against `packing.csv`: the
count, each disk's radius, position, type and mass, and no overlap as the
program itself measures it. Each check is first shown to fail on a
packing with one disk pushed into its neighbour.

Needs Debian's `lammps` and `liggghts` (the `lmp` and `liggghts`
commands) and the `vtk` Python module; skipped without them unless
GAPACK_DEM_TESTS=required (CI).
"""

from __future__ import annotations

import math
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import gapack
from conftest import need

#: gapack's overlap tolerance: a fraction of the radii sum.
OVERLAP_REL = 1e-9
#: Normal stiffness of the linear (Hooke) contacts in LAMMPS (N/m): a
#: contact's force is KN times its overlap, with no velocity to damp.
KN = 1.0e5

SCENES = {
    # Two materials (two atom types), walls.
    "fgm": ("configs/fgm_power.toml", "layer", 2),
    # A periodic cell: overlaps across the edges count too (LAMMPS' ghosts).
    "periodic": ("configs/periodic_pfc.toml", "pack", 5),
}


def table(dir: Path) -> dict:
    """packing.csv: ids, x, y, r (mm) and the material index of each disk."""
    t = np.genfromtxt(dir / "packing.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    return t


def exported(work: Path, scene: str, formats) -> tuple:
    config, job, seed = SCENES[scene]
    packing = getattr(gapack, job)(config, seed=seed)
    out = work / f"out_{scene}"
    packing.write(out, formats=["csv", *formats])
    return packing, out


def types_of(packing) -> np.ndarray:
    """The atom type each disk should have: material index + 1 (1 without materials)."""
    if packing.material is None:
        return np.ones(len(packing), dtype=int)
    return packing.material.astype(int) + 1


def push_first_disk_into_its_neighbour(data: Path, packing, fraction=0.01) -> None:
    """Rewrite a LAMMPS data file with atom 1 moved toward its nearest
    neighbour by ``fraction`` of its radius: an overlap every check must see."""
    x, y, r = packing.x, packing.y, packing.r
    d = np.hypot(x[1:] - x[0], y[1:] - y[0]) - r[1:] - r[0]
    j = 1 + int(np.argmin(d))
    ux, uy = float(x[j] - x[0]), float(y[j] - y[0])
    norm = math.hypot(ux, uy)
    shift = fraction * float(r[0]) / 1000.0  # m
    lines = data.read_text().splitlines()
    start = lines.index("Atoms # sphere") + 2
    parts = lines[start].split()
    assert parts[0] == "1"
    parts[4] = repr(float(parts[4]) + shift * ux / norm)
    parts[5] = repr(float(parts[5]) + shift * uy / norm)
    lines[start] = " ".join(parts)
    data.write_text("\n".join(lines) + "\n")


def lammps_input(data: Path, periodic: bool) -> str:
    return f"""\
units          si
dimension      2
boundary       {"p p p" if periodic else "f f p"}
atom_style     sphere
atom_modify    map array
read_data      {data.name}
comm_modify    vel yes
pair_style     gran/hooke {KN} NULL 0.0 NULL 0.5 0
pair_coeff     * *
neighbor       0.0001 bin
fix            flat all enforce2d
compute        pairs all pair/local force
compute        fmax all reduce max c_pairs
thermo_style   custom step atoms c_fmax
thermo_modify  format float %.17g
run            0
write_dump     all custom atoms.dump id type radius mass x y z modify sort id format line "%d %d %.17g %.17g %.17g %.17g %.17g"
"""


def liggghts_input(data: Path, periodic: bool, types: int) -> str:
    pairs = " ".join(["0.5"] * (types * types))
    per_type = " ".join(["5.0e6"] * types)
    ratio = " ".join(["0.3"] * types)
    return f"""\
atom_style     sphere
atom_modify    map array
boundary       {"p p p" if periodic else "f f p"}
newton         off
communicate    single vel yes
units          si
dimension      2
read_data      {data.name}
neighbor       0.0001 bin
neigh_modify   delay 0
fix            m1 all property/global youngsModulus peratomtype {per_type}
fix            m2 all property/global poissonsRatio peratomtype {ratio}
fix            m3 all property/global coefficientRestitution peratomtypepair {types} {pairs}
fix            m4 all property/global coefficientFriction peratomtypepair {types} {pairs}
fix            m5 all property/global characteristicVelocity scalar 1.0
pair_style     gran model hooke tangential history
pair_coeff     * *
timestep       1.0e-8
fix            integrate all nve/sphere
fix            flat all enforce2d
compute        contacts all pair/gran/local id force delta
dump           atoms all custom 1 atoms.dump id type radius mass x y z
dump_modify    atoms sort id format "%d %d %.17g %.17g %.17g %.17g %.17g"
dump           contacts all local 1 contacts.dump c_contacts[1] c_contacts[2] c_contacts[7]
dump_modify    contacts format "%.0f %.0f %.17g"
run            0
"""


def run(program: str, script: str, cwd: Path) -> str:
    (cwd / "in.run").write_text(script)
    done = subprocess.run(
        [program, "-in", "in.run", "-log", "none", "-echo", "none"],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0 and "ERROR" not in done.stdout, done.stdout[-3000:] + done.stderr
    return done.stdout


def dumped_atoms(path: Path) -> np.ndarray:
    lines = path.read_text().splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
    return np.array([[float(v) for v in l.split()] for l in lines[start:] if l.strip()])


def check_atoms(atoms: np.ndarray, csv, packing, mass) -> None:
    """The program's atoms against packing.csv: count, id order, type,
    radius, position (m), mass."""
    n = len(csv)
    assert atoms.shape == (n, 7)
    assert np.array_equal(atoms[:, 0], csv["id"] + 1)
    assert np.array_equal(atoms[:, 1].astype(int), types_of(packing))
    r = csv["r"] / 1000.0
    assert np.allclose(atoms[:, 2], r, rtol=1e-12, atol=0)
    assert np.allclose(atoms[:, 4], csv["x"] / 1000.0, rtol=0, atol=1e-15)
    assert np.allclose(atoms[:, 5], csv["y"] / 1000.0, rtol=0, atol=1e-15)
    assert np.all(atoms[:, 6] == 0.0)
    density = np.array([packing.materials[t - 1]["density"] for t in types_of(packing)]) if packing.materials else 2650.0
    assert np.allclose(atoms[:, 3], mass(density, r), rtol=1e-9, atol=0)


def lammps_overlap(stdout: str) -> float:
    """The deepest overlap LAMMPS finds (m): its largest contact force / KN."""
    lines = stdout.splitlines()
    head = next(i for i, l in enumerate(lines) if l.split()[:3] == ["Step", "Atoms", "c_fmax"])
    step, atoms, fmax = lines[head + 1].split()
    return float(fmax) / KN


@pytest.mark.parametrize("scene", list(SCENES))
def test_lammps_reads_the_packing_and_finds_no_overlap(work, scene):
    need(shutil.which("lmp") is not None, "LAMMPS (lmp) is not installed: apt-get install lammps")
    packing, out = exported(work, scene, ["lammps"])
    csv = table(out)
    periodic = packing.domain["periodic"]
    bound = OVERLAP_REL * 2 * packing.r.min() / 1000.0
    # The check fails on a packing with an overlap.
    bad = work / f"bad_{scene}"
    bad.mkdir()
    shutil.copy(out / "packing.lammps", bad / "packing.lammps")
    push_first_disk_into_its_neighbour(bad / "packing.lammps", packing)
    deepest = lammps_overlap(run("lmp", lammps_input(bad / "packing.lammps", periodic), bad))
    assert deepest == pytest.approx(0.01 * packing.r[0] / 1000.0, rel=1e-3)
    # gapack's packing: every disk as written, no overlap beyond the tolerance.
    stdout = run("lmp", lammps_input(out / "packing.lammps", periodic), out)
    check_atoms(dumped_atoms(out / "atoms.dump"), csv, packing, lambda rho, r: rho * 4 / 3 * math.pi * r**3)
    deepest = lammps_overlap(stdout)
    print(f"LAMMPS {scene}: {len(csv)} atoms read, deepest overlap {deepest:.3e} m (bound {bound:.3e} m)")
    assert deepest <= bound


def liggghts_overlap(path: Path) -> float:
    """The deepest overlap LIGGGHTS reports among its contacts (m)."""
    lines = path.read_text().splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ENTRIES")) + 1
    deltas = [float(l.split()[2]) for l in lines[start:] if l.strip()]
    assert len(deltas) > 0
    return max(deltas)


@pytest.mark.parametrize("scene", list(SCENES))
def test_liggghts_reads_the_packing_and_finds_no_overlap(work, scene):
    need(shutil.which("liggghts") is not None, "LIGGGHTS is not installed: apt-get install liggghts")
    packing, out = exported(work, scene, ["lammps"])
    csv = table(out)
    periodic = packing.domain["periodic"]
    types = max(1, len(packing.materials))
    bound = OVERLAP_REL * 2 * packing.r.min() / 1000.0
    bad = work / f"bad_{scene}"
    bad.mkdir()
    shutil.copy(out / "packing.lammps", bad / "packing.lammps")
    push_first_disk_into_its_neighbour(bad / "packing.lammps", packing)
    run("liggghts", liggghts_input(bad / "packing.lammps", periodic, types), bad)
    assert liggghts_overlap(bad / "contacts.dump") == pytest.approx(0.01 * packing.r[0] / 1000.0, rel=1e-3)
    run("liggghts", liggghts_input(out / "packing.lammps", periodic, types), out)
    # LIGGGHTS with dimension 2: the mass of a disc of unit thickness.
    check_atoms(dumped_atoms(out / "atoms.dump"), csv, packing, lambda rho, r: rho * math.pi * r**2)
    deepest = liggghts_overlap(out / "contacts.dump")
    print(f"LIGGGHTS {scene}: {len(csv)} atoms read, deepest overlap {deepest:.3e} m (bound {bound:.3e} m)")
    assert deepest <= bound


@pytest.mark.parametrize("scene", list(SCENES))
def test_vtk_reads_the_packing_and_its_outline(work, scene):
    try:
        import vtk
        from vtk.util.numpy_support import vtk_to_numpy
    except ImportError:
        vtk = None
    need(vtk is not None, "the vtk Python module is not installed: pip install vtk")
    packing, out = exported(work, scene, ["vtk"])
    csv = table(out)
    reader = vtk.vtkPolyDataReader()
    reader.SetFileName(str(out / "packing.vtk"))
    # Every array of the file, as ParaView reads it (VTK's default: the first only).
    reader.ReadAllScalarsOn()
    reader.ReadAllFieldsOn()
    reader.Update()
    assert reader.IsFilePolyData()
    disks = reader.GetOutput()
    n = len(csv)
    assert disks.GetNumberOfPoints() == n and disks.GetNumberOfVerts() == n
    points = vtk_to_numpy(disks.GetPoints().GetData())
    assert np.array_equal(points[:, 0], csv["x"]) and np.array_equal(points[:, 1], csv["y"])
    assert np.all(points[:, 2] == 0.0)
    data = disks.GetPointData()
    assert np.array_equal(vtk_to_numpy(data.GetArray("radius")), csv["r"])
    assert np.allclose(vtk_to_numpy(data.GetArray("diameter")), 2 * csv["r"], rtol=1e-15)
    # material index + 1, 0 without materials (docs/outputs.md).
    material_id = types_of(packing) if packing.materials else np.zeros(n, dtype=int)
    assert np.array_equal(vtk_to_numpy(data.GetArray("material_id")), material_id)
    if packing.domain["periodic"]:
        field = disks.GetFieldData()
        assert vtk_to_numpy(field.GetArray("periodic"))[0] == 1
        cell = vtk_to_numpy(field.GetArray("cell")).reshape(-1)
        assert list(cell) == [0.0, packing.domain["width"], 0.0, packing.domain["height"]]
    reader = vtk.vtkPolyDataReader()
    reader.SetFileName(str(out / "boundary.vtk"))
    reader.Update()
    outline = reader.GetOutput()
    assert outline.GetNumberOfLines() == 1
    corners = vtk_to_numpy(outline.GetPoints().GetData())[:, :2]
    assert np.array_equal(corners, packing.domain["outline"])
    ids = vtk.vtkIdList()
    outline.GetLines().InitTraversal()
    outline.GetLines().GetNextCell(ids)
    # A closed polyline through every corner.
    assert [ids.GetId(i) for i in range(ids.GetNumberOfIds())] == [*range(len(corners)), 0]
    print(f"VTK {scene}: {n} points, radius, diameter and material_id read back")
