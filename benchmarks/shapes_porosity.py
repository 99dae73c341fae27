"""Porosity against aspect ratio and exponent, packed by the gapack binary.

Runs `gapack pack` on a 40 mm square for superellipses of aspect 1-5 and
exponents 1, 2, 4 and 10, two gradings (uniform 1-2 mm and constant
1.5 mm, sieve sizes), at two contacts and (ellipses) one contact; writes
shapes_porosity.csv and shapes_porosity.png into the folder given.

    python3 benchmarks/shapes_porosity.py target/release/gapack docs/img
"""

import csv
import json
import os
import subprocess
import sys
import tempfile

SCENE = """seed = 1
[domain]
shape = "rectangle"
width = 40
height = 40
[grading]
{grading}
[packer]
one_contact_share = {share}
[shape]
kind = "superellipse"
aspect = {aspect}
alpha = {exponent}
[output]
formats = ["csv"]
"""

GRADINGS = [("uniform 1-2 mm", "uniform = [1, 2]"), ("constant 1.5 mm", "constant = 1.5")]
ASPECTS = [1.0, 1.25, 1.5, 2.0, 3.0, 4.0, 5.0]
EXPONENTS = [2.0, 1.0, 4.0, 10.0]


def run(binary, folder, grading, aspect, exponent, share):
    config = os.path.join(folder, "scene.toml")
    with open(config, "w") as f:
        f.write(SCENE.format(grading=grading, share=share, aspect=aspect, exponent=exponent))
    out = os.path.join(folder, "out")
    subprocess.run([binary, "pack", config, "--out", out, "--quiet"], check=True)
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    return s["particles"], s["porosity"], s["seconds"]


def main():
    binary, dest = sys.argv[1], sys.argv[2]
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for gname, grading in GRADINGS:
            for exponent in EXPONENTS:
                for aspect in ASPECTS:
                    for share in ([0, 1] if exponent == 2.0 else [0]):
                        n, phi, secs = run(binary, folder, grading, aspect, exponent, share)
                        rows.append([gname, exponent, aspect, 2 - share, n, round(phi, 4), round(secs, 2)])
                        print(*rows[-1], flush=True)
    with open(os.path.join(dest, "shapes_porosity.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["grading", "exponent", "aspect", "contacts", "particles", "porosity", "seconds"])
        w.writerows(rows)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    for ax, (gname, _) in zip(axes, GRADINGS):
        for exponent in EXPONENTS:
            for contacts in (2, 1):
                pts = [(r[2], r[5]) for r in rows if r[0] == gname and r[1] == exponent and r[3] == contacts]
                if not pts:
                    continue
                label = f"alpha = beta = {exponent:g}" + (", one contact" if contacts == 1 else "")
                ax.plot(*zip(*pts), marker="o", linestyle="--" if contacts == 1 else "-", label=label)
        ax.set_title(f"{gname}, 40 mm square")
        ax.set_xlabel("aspect ratio a/b")
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel("porosity")
    axes[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(dest, "shapes_porosity.png"), dpi=110)


if __name__ == "__main__":
    main()
