"""YADE from gapack's arrays: pack a two-material plate with gapack inside a
YADE scene, make one YADE material per gapack material and append the disks
to ``O.bodies`` straight from the numpy arrays (no file in between), then
step once and let YADE's collider confirm that no two spheres overlap.

Run it with YADE (Debian: ``apt-get install yade``), gapack importable by
YADE's Python (Debian's ``/usr/bin/python3``: ``pip install ./python``
with it, or gapack's package folder on ``PYTHONPATH``):

    PYTHONPATH=DIR yade -n -x examples/python/yade_from_arrays.py [CONFIG]

(``-n``: no GUI, ``-x``: exit when the script ends.)
"""

import sys

import numpy as np

import gapack

# YADE passes its own arguments before the script's.
args = [a for a in sys.argv[1:] if a.endswith(".toml")]
config = args[0] if args else "configs/fgm_power.toml"
p = gapack.layer(config, seed=1) if "[layering]" in open(config).read() else gapack.pack(config, seed=1)
n = len(p)
mm = 1e-3  # gapack's millimetres to YADE's metres

# One YADE material per gapack material, in config order (a disk's
# material is an index into that order); one for all without materials.
materials = p.materials or [{"name": "grain", "density": 2650.0}]
ids = [
    O.materials.append(FrictMat(density=m["density"], young=70e9, poisson=0.25, frictionAngle=0.5, label=m["name"]))
    for m in materials
]
material = p.material if p.material is not None else np.zeros(n, dtype=np.int32)

spheres = []
for x, y, r, m in zip(p.x.tolist(), p.y.tolist(), p.r.tolist(), material.tolist()):
    b = sphere((x * mm, y * mm, 0.0), r * mm, material=ids[m], fixed=False)
    b.state.blockedDOFs = "zXY"  # YADE is 3D: the disks stay in the plane
    spheres.append(b)
bodies = O.bodies.append(spheres)

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
    """Step once; YADE's deepest penetration between two spheres (m)."""
    O.step()
    return max((i.geom.penetrationDepth for i in O.interactions if i.isReal), default=0.0)


# What YADE holds, body by body, against the arrays.
pos = np.array([O.bodies[i].state.pos for i in bodies])
radius = np.array([O.bodies[i].shape.radius for i in bodies])
labels = [O.materials[O.bodies[i].material.id].label for i in bodies]
assert len(bodies) == n and len(O.bodies) == n
assert np.allclose(pos[:, 0], p.x * mm, rtol=0, atol=1e-15) and np.allclose(pos[:, 1], p.y * mm, rtol=0, atol=1e-15)
assert np.allclose(radius, p.r * mm, rtol=1e-15, atol=0)
assert labels == [materials[m]["name"] for m in material]
deepest = deepest_overlap()
bound = 1e-9 * 2 * p.r.min() * mm
contacts = sum(1 for i in O.interactions if i.isReal)
print(f"gapack: {n} disks, porosity {p.summary['porosity']:.4f}, materials {[m['name'] for m in materials]}")
print(
    f"YADE: {len(O.bodies)} spheres appended from the arrays, "
    f"{sum(1 for l in labels if l == materials[-1]['name'])} of them {materials[-1]['name']}; "
    f"{contacts} contacts, deepest overlap {deepest:.3e} m (tolerance {bound:.3e} m)"
)
assert deepest <= bound
# The measure sees an overlap: sphere 0 pushed 1 % of its radius into its nearest neighbour.
j = 1 + int(np.argmin(np.hypot(p.x[1:] - p.x[0], p.y[1:] - p.y[0]) - p.r[1:]))
u = np.array([p.x[j] - p.x[0], p.y[j] - p.y[0]])
u = 0.01 * p.r[0] * mm * u / np.linalg.norm(u)
O.bodies[bodies[0]].state.pos = O.bodies[bodies[0]].state.pos + Vector3(u[0], u[1], 0.0)
pushed = deepest_overlap()
print(f"YADE: with sphere 0 pushed 1 % of its radius into sphere {j}: deepest overlap {pushed:.3e} m")
assert abs(pushed - 0.01 * p.r[0] * mm) < 0.01 * 0.01 * p.r[0] * mm
