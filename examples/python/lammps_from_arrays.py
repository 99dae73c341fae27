"""LAMMPS from gapack's arrays: pack a two-material plate with gapack, make
the atoms in LAMMPS straight from the numpy arrays (no file in between),
and let LAMMPS confirm it holds them without overlap.

Needs LAMMPS' Python module (Debian: ``apt-get install python3-lammps
liblammps-dev``, for Debian's ``/usr/bin/python3``) and gapack importable
by the same Python (``pip install ./python`` with it, or gapack's package
folder on ``PYTHONPATH``: its abi3 build loads in any CPython >= 3.9).

    python3 examples/python/lammps_from_arrays.py [CONFIG]

CI runs it (.ci/run, through python/tests/test_examples.py).
"""

import math
import sys

import numpy as np
from lammps import LMP_STYLE_GLOBAL, LMP_TYPE_SCALAR, lammps

import gapack

config = sys.argv[1] if len(sys.argv) > 1 else "configs/fgm_power.toml"
p = gapack.layer(config, seed=1) if "layering" in open(config).read() else gapack.pack(config, seed=1)
n = len(p)
types = (p.material + 1) if p.material is not None else np.ones(n, dtype=np.int32)
density = np.array([m["density"] for m in p.materials]) if p.materials else np.array([2650.0])
(x0, y0), (x1, y1) = p.domain["bounds"]
mm = 1e-3  # gapack's millimetres to LAMMPS' metres (units si)
r_max = p.r.max() * mm

lmp = lammps(cmdargs=["-log", "none", "-screen", "none"])
lmp.commands_string(
    f"""
    units          si
    dimension      2
    boundary       {"p p p" if p.domain["periodic"] else "f f p"}
    atom_style     sphere
    atom_modify    map array
    region         box block {x0 * mm} {x1 * mm} {y0 * mm} {y1 * mm} {-r_max} {r_max}
    create_box     {len(density)} box
    comm_modify    vel yes
    """
)
# The atoms, from the arrays: ids 1..n, types, positions (z = 0).
xyz = np.column_stack([p.x * mm, p.y * mm, np.zeros(n)]).ravel()
made = lmp.create_atoms(n, list(range(1, n + 1)), types.tolist(), xyz.tolist())
assert made == n, f"LAMMPS made {made} atoms of {n}"
# Radii and masses written into LAMMPS' own per-atom arrays (numpy views).
radius = lmp.numpy.extract_atom("radius")
rmass = lmp.numpy.extract_atom("rmass")
ids = lmp.numpy.extract_atom("id")
order = ids[:n] - 1
radius[:n] = p.r[order] * mm
rho = density[types[order] - 1]
rmass[:n] = rho * 4.0 / 3.0 * math.pi * radius[:n] ** 3  # as read_data does
# Linear contacts: a contact's force is kn times its overlap.
kn = 1.0e5
lmp.commands_string(
    f"""
    pair_style     gran/hooke {kn} NULL 0.0 NULL 0.5 0
    pair_coeff     * *
    neighbor       {0.1 * r_max} bin
    fix            flat all enforce2d
    compute        contacts all pair/local force
    compute        fmax all reduce max c_contacts
    thermo_style   custom step atoms c_fmax
    run            0
    """
)
def deepest_overlap():
    """LAMMPS' largest contact force over kn: the deepest overlap (m)."""
    return lmp.extract_compute("fmax", LMP_STYLE_GLOBAL, LMP_TYPE_SCALAR) / kn


atoms = lmp.get_natoms()
deepest = deepest_overlap()
bound = 1e-9 * 2 * p.r.min() * mm
print(f"gapack: {n} disks, porosity {p.summary['porosity']:.4f}, {len(density)} materials")
print(f"LAMMPS: {atoms} atoms made from the arrays, deepest overlap {deepest:.3e} m (tolerance {bound:.3e} m)")
assert atoms == n and deepest <= bound
# The measure sees an overlap: atom 1 pushed 1 % of its radius into its nearest neighbour.
j = 1 + int(np.argmin(np.hypot(p.x[1:] - p.x[0], p.y[1:] - p.y[0]) - p.r[1:]))
u = np.array([p.x[j] - p.x[0], p.y[j] - p.y[0]])
push = 0.01 * p.r[0] * u / np.linalg.norm(u)
lmp.command(f"set atom 1 x {(p.x[0] + push[0]) * mm} y {(p.y[0] + push[1]) * mm}")
lmp.command("run 0")
print(f"LAMMPS: with atom 1 pushed 1 % of its radius into atom {j + 1}: deepest overlap {deepest_overlap():.3e} m")
assert abs(deepest_overlap() - 0.01 * p.r[0] * mm) < 1e-3 * 0.01 * p.r[0] * mm
lmp.close()
