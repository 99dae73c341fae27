"""Round trip through YADE: gapack writes ``packing.yade.txt`` (and
``packing.csv``); YADE reads the export with ``ymport.text`` as
docs/outputs.md says, and the spheres it holds are checked against
``packing.csv``: the count, each radius, position and material, then one
step in which YADE's collider must find no overlap beyond gapack's
tolerance (1e-9 of the radii sum). The check is shown to fail on the same
spheres with one pushed 1 % of its radius into its neighbour.

    PYTHONPATH=DIR yade -n -x examples/python/roundtrip_yade.py [CONFIG] [OUT]

(YADE from Debian: ``apt-get install yade``; gapack importable by its
Python, as for yade_from_arrays.py.) Prints ``YADE round trip: passed``.
"""

import sys
from pathlib import Path

import numpy as np
from yade import ymport

import gapack

args = [a for a in sys.argv[1:] if not a.startswith("-")]
config = args[0] if args else "configs/fgm_power.toml"
out = Path(args[1] if len(args) > 1 else "out/roundtrip_yade")
p = gapack.layer(config, seed=1) if "[layering]" in open(config).read() else gapack.pack(config, seed=1)
p.write(out, formats=["csv", "yade"])
csv = np.genfromtxt(out / "packing.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
n = len(csv)
units = 1e-3  # [output] units = "m" (the default): the export is in metres

# The materials first, in config order: matId is that index.
names = [m["name"] for m in p.materials]
for m in p.materials:
    O.materials.append(FrictMat(density=m["density"], young=70e9, poisson=0.25, frictionAngle=0.5, label=m["name"]))
if not names:
    O.materials.append(FrictMat(density=2650.0, young=70e9, poisson=0.25, frictionAngle=0.5, label="grain"))
# A periodic cell's file says how to declare it: run that first.
for line in open(out / "packing.yade.txt"):
    if line.startswith("# periodic cell: "):
        exec(line[len("# periodic cell: ") :])
spheres = ymport.text(str(out / "packing.yade.txt"))
for b in spheres:
    b.state.blockedDOFs = "zXY"
ids = O.bodies.append(spheres)

pos = np.array([O.bodies[i].state.pos for i in ids])
radius = np.array([O.bodies[i].shape.radius for i in ids])
material = [O.bodies[i].material.id for i in ids]
assert len(ids) == n, f"YADE holds {len(ids)} spheres, packing.csv {n}"
assert np.allclose(radius, csv["r"] * units, rtol=1e-15, atol=0)
assert np.allclose(pos[:, 0], csv["x"] * units, rtol=0, atol=1e-15)
assert np.allclose(pos[:, 1], csv["y"] * units, rtol=0, atol=1e-15)
assert np.all(pos[:, 2] == 0.0)
if names:
    assert [names[m] for m in material] == list(csv["material"])

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb()]),
    InteractionLoop(
        [Ig2_Sphere_Sphere_ScGeom()],
        [Ip2_FrictMat_FrictMat_FrictPhys()],
        [Law2_ScGeom_FrictPhys_CundallStrack()],
    ),
    NewtonIntegrator(gravity=(0, 0, 0), damping=0.0),
]
O.dt = 0.5 * PWaveTimeStep()


def deepest_overlap():
    O.step()
    return max((i.geom.penetrationDepth for i in O.interactions if i.isReal), default=0.0)


deepest = deepest_overlap()
bound = 1e-9 * 2 * csv["r"].min() * units
print(
    f"YADE read {out / 'packing.yade.txt'}{' (a periodic cell)' if O.periodic else ''}: "
    f"{len(ids)} spheres, radii, positions and materials as packing.csv"
)
print(f"YADE: deepest overlap {deepest:.3e} m (tolerance {bound:.3e} m)")
assert deepest <= bound
x, y, r = csv["x"], csv["y"], csv["r"]
j = 1 + int(np.argmin(np.hypot(x[1:] - x[0], y[1:] - y[0]) - r[1:]))
u = np.array([x[j] - x[0], y[j] - y[0]])
u = 0.01 * r[0] * units * u / np.linalg.norm(u)
O.bodies[ids[0]].state.pos = O.bodies[ids[0]].state.pos + Vector3(u[0], u[1], 0.0)
pushed = deepest_overlap()
print(f"YADE: sphere 0 pushed 1 % of its radius into sphere {j}: deepest overlap {pushed:.3e} m")
assert abs(pushed - 0.01 * r[0] * units) < 1e-4 * r[0] * units
print("YADE round trip: passed")
