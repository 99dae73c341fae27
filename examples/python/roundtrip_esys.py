"""Round trip through ESyS-Particle: gapack writes ``packing.geo`` (and
``packing.csv``); ESyS reads the export with ``sim.readGeometry`` as
docs/outputs.md says, and the particles it holds are checked against
``packing.csv``: the count, each radius, position and tag (material index
+ 1), then a time step with linear elastic repulsion (normal stiffness k),
in which ESyS's total elastic energy E bounds every overlap by
sqrt(2 E / k): it must lie within gapack's tolerance (1e-9 of the radii
sum). The check is shown to fail with one particle pushed 1 % of its
radius into its neighbour.

    PYTHONPATH=DIR mpirun -np 2 esysparticle examples/python/roundtrip_esys.py [CONFIG] [OUT]

(ESyS-Particle from Debian: ``apt-get install esys-particle``; as root,
``mpirun --allow-run-as-root``; gapack importable by Debian's Python.)
Prints ``ESyS-Particle round trip: passed``.
"""

import math
import sys
from pathlib import Path

import numpy as np
from esys.lsm import InteractionScalarFieldSaverPrms, LsmMpi, NRotElasticPrms
from esys.lsm.util import BoundingBox, Vec3

import gapack

args = [a for a in sys.argv[1:] if not a.startswith("-")]
config = args[0] if args else "configs/fgm_power.toml"
out = Path(args[1] if len(args) > 1 else "out/roundtrip_esys")
p = gapack.layer(config, seed=1) if "[layering]" in open(config).read() else gapack.pack(config, seed=1)
p.write(out, formats=["csv", "esys"])
csv = np.genfromtxt(out / "packing.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
n = len(csv)
units = 1e-3  # the export is in metres
r_max = csv["r"].max() * units
k = 1.0e5  # N/m

# The geometry file's own box and periodic axes make the spatial domain.
geo = open(out / "packing.geo").read()
box = geo.split("BoundingBox")[1].split("\n")[0].split()
lo, hi = [float(v) for v in box[:3]], [float(v) for v in box[3:]]
circular = [v == "1" for v in geo.split("PeriodicBoundaries")[1].split("\n")[0].split()]
sim = LsmMpi(numWorkerProcesses=1, mpiDimList=[1, 1, 1])
sim.initNeighbourSearch(particleType="NRotSphere", gridSpacing=2.5 * r_max, verletDist=0.05 * r_max)
sim.force2dComputations(True)
sim.setSpatialDomain(BoundingBox(Vec3(*lo), Vec3(*hi)), circular)
sim.setNumTimeSteps(3)
sim.setTimeStepSize(1e-9)
sim.readGeometry(str(out / "packing.geo"))
sim.createInteractionGroup(NRotElasticPrms(name="elastic", normalK=k, scaling=False))
energy_file = out / "elastic_energy.dat"
energy_file.unlink(missing_ok=True)
sim.createFieldSaver(
    InteractionScalarFieldSaverPrms(
        interactionName="elastic",
        fieldName="potential_energy",
        fileName=str(energy_file),
        fileFormat="SUM",
        beginTimeStep=0,
        endTimeStep=3,
        timeStepIncr=1,
    )
)

particles = sorted(sim.getParticleList(), key=lambda q: q.getId())
assert len(particles) == n, f"ESyS holds {len(particles)} particles, packing.csv {n}"
pos = np.array([[q.getPosn()[0], q.getPosn()[1], q.getPosn()[2]] for q in particles])
radius = np.array([q.getRad() for q in particles])
tags = np.array([q.getTag() for q in particles])
assert np.array_equal([q.getId() for q in particles], csv["id"])
assert np.allclose(radius, csv["r"] * units, rtol=1e-15, atol=0)
assert np.allclose(pos[:, 0], csv["x"] * units, rtol=0, atol=1e-15)
assert np.allclose(pos[:, 1], csv["y"] * units, rtol=0, atol=1e-15)
assert np.all(pos[:, 2] == 0.0)
names = [m["name"] for m in p.materials]
expected = [names.index(m) + 1 for m in csv["material"]] if names else [1] * n
assert list(tags) == expected

sim.runTimeStep()
sim.runTimeStep()  # the forces of the packing as read
x, y, r = csv["x"], csv["y"], csv["r"]
j = 1 + int(np.argmin(np.hypot(x[1:] - x[0], y[1:] - y[0]) - r[1:]))
u = np.array([x[j] - x[0], y[j] - y[0]])
u = 0.01 * r[0] * units * u / np.linalg.norm(u)
sim.moveParticleTo(int(csv["id"][0]), Vec3(pos[0, 0] + u[0], pos[0, 1] + u[1], 0.0))
sim.runTimeStep()  # with particle 0 pushed into its neighbour
sim.exit()

energies = [float(line) for line in energy_file.read_text().split()]
deepest = math.sqrt(2 * energies[-2] / k)
pushed = math.sqrt(2 * energies[-1] / k)
bound = 1e-9 * 2 * r.min() * units
print(
    f"ESyS-Particle read {out / 'packing.geo'}{' (a periodic cell)' if any(circular) else ''}: "
    f"{n} particles, radii, positions and tags as packing.csv"
)
print(f"ESyS-Particle: elastic energy {energies[-2]:.3e} J, every overlap under {deepest:.3e} m (tolerance {bound:.3e} m)")
print(f"ESyS-Particle: particle 0 pushed 1 % of its radius into particle {j}: overlap bound {pushed:.3e} m")
assert deepest <= bound
assert pushed >= 0.01 * r[0] * units * (1 - 1e-3)
print("ESyS-Particle round trip: passed")
