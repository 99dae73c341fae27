# %% [markdown]
# # Porosity study: which porosities does a grading reach in a domain?
#
# A notebook in a script (each `# %%` is a cell: VS Code, Spyder and
# Jupytext open it as one). For a set of target porosities, gapack's
# genetic algorithm searches the packing of a 40 × 40 mm square with sizes
# uniform in 1.2–4.8 mm (the thesis' AP-4 grading) that hits each target
# while keeping the sizes within a KS distance of the grading; targets
# below the advancing front's range are packed by the densify method. The
# chart shows what each search reached, and how.
#
#     python examples/python/porosity_study.py        # writes out/porosity_study/
#
# Needs gapack (`pip install ./python`) and matplotlib; tqdm, if installed,
# draws a progress bar per search in a notebook or a terminal.

# %%
import copy
import os
import warnings

import matplotlib

if "ipykernel" not in os.sys.modules:
    matplotlib.use("Agg")  # a script writes the chart; a notebook shows it
import matplotlib.pyplot as plt
import numpy as np

import gapack

base = {
    "seed": 1,
    "domain": {"shape": "rectangle", "width": 40, "height": 40},
    "grading": {"uniform": [1.2, 4.8]},
    "optimise": {
        "tolerance": 0.002,
        "population": 24,
        "generations": 60,
        "stagnation": 20,
        "max_evaluations": 1500,  # the same stop on every machine
        "max_psd_ks": 0.05,
    },
}
targets = [0.18, 0.22, 0.26, 0.30, 0.34, 0.38, 0.42, 0.46, 0.50]
out = "out/porosity_study"

# %% One search per target: the best packing, its history, the verdict.
results = []
for target in targets:
    config = copy.deepcopy(base)
    config["optimise"]["target_porosity"] = target
    with warnings.catch_warnings():
        # A target out of reach is said in the verdict below.
        warnings.simplefilter("ignore", gapack.GapackWarning)
        p = gapack.optimise(config)
    s = p.summary
    results.append((target, p))
    print(
        f"target {target:.2f}: porosity {s['porosity']:.4f}, psd_ks {s['psd_ks']:.3f}, "
        f"{len(p)} disks, {s['evaluations']} evaluations, {s['verdict']}"
    )

# %% The chart: reached against asked, and each search's convergence.
fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5), constrained_layout=True)
asked = np.array([t for t, _ in results])
reached = np.array([p.summary["porosity"] for _, p in results])
hit = np.array([p.summary["verdict"] == "reached" for _, p in results])
tol = base["optimise"]["tolerance"]
line = np.linspace(min(asked) - 0.03, max(asked) + 0.03, 2)
left.fill_between(line, line - tol, line + tol, color="0.85", label=f"target ± {tol}")
left.plot(line, line, color="0.4", lw=1)
left.scatter(asked[hit], reached[hit], color="tab:blue", zorder=3, label="reached")
left.scatter(asked[~hit], reached[~hit], color="tab:red", marker="x", zorder=3, label="not reached")
left.set(xlabel="target porosity", ylabel="porosity of the best packing", title="What the search reached")
left.legend(loc="upper left")
for target, p in results:
    h = p.history
    right.plot(h["generation"], h["best"], marker=".", label=f"{target:.2f}")
    right.axhline(target, color="0.8", lw=0.8, ls="--")
right.set(xlabel="generation", ylabel="best porosity so far", title="Convergence (dashed: targets)")
right.legend(title="target", fontsize=8)
os.makedirs(out, exist_ok=True)
fig.savefig(f"{out}/porosity_study.png", dpi=120)
print(f"{out}/porosity_study.png")

# %% Keep the densest packing's files, as `gapack optimise` writes them.
densest = min(results, key=lambda r: r[1].summary["porosity"])[1]
files = densest.write(f"{out}/densest", formats=["csv", "lammps", "png"])
print(f"{out}/densest: {', '.join(files)}")
