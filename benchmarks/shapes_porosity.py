"""Porosity against aspect ratio and exponent, packed by the gapack binary,
beside published random-packing figures.

Runs `gapack pack` on a 40 mm square for superellipses of aspect 1-5 and
exponents 1, 2, 4 and 10, two gradings (uniform 1-2 mm and constant
1.5 mm, sieve sizes), each at two contacts and at one contact, and disks
of the same gradings packed by the disk front; writes shapes_porosity.csv
and shapes_porosity.png into the folder given, and prints the table of
docs/shapes.md (one row per grading, exponent and contact rule, with the
range over aspect ratios).

    python3 benchmarks/shapes_porosity.py target/release/gapack docs/img

The published points drawn beside the measured curves are the figures
quoted, with their references, in docs/shapes.md ("Published figures").
"""

import csv
import json
import math
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
{shape}[output]
formats = ["csv"]
"""

SHAPE = """[shape]
kind = "superellipse"
aspect = {aspect}
alpha = {exponent}
"""

GRADINGS = [("uniform 1-2 mm", "uniform = [1, 2]"), ("constant 1.5 mm", "constant = 1.5")]
ASPECTS = [1.0, 1.25, 1.5, 2.0, 3.0, 4.0, 5.0]
EXPONENTS = [2.0, 1.0, 4.0, 10.0]

# Published packing fractions phi drawn as markers (aspect ratio a/b, phi,
# legend label); the sources are cited in docs/shapes.md.
DENSEST_ELLIPSES = math.pi / (2 * math.sqrt(3))  # any aspect ratio (affine image of the disks' lattice)
PUBLISHED = [
    # Densest random jammed ellipse packings (bidisperse, compressed), at the aspect ratio of the maximum.
    (1.43, 0.895, "jammed ellipses, maximum (Delaney et al. 2005)"),
    (1.40, 0.8974, "jammed ellipses, maximum (Donev et al. 2007)"),
    (1.30, 0.891, "jammed ellipses, maximum (VanderWerf et al. 2018)"),
    (1.45, 0.8917, "jammed ellipses, maximum (Rocks & Hoy 2023)"),
    # Bidisperse disks jammed by compression (O'Hern et al. 2003).
    (1.0, 0.84, "jammed bidisperse disks (O'Hern et al. 2003)"),
    # Saturated random sequential addition of equal disks (Zhang & Torquato 2013).
    (1.0, 0.5470690, "RSA of equal disks, saturated (Zhang & Torquato 2013)"),
]


def run(binary, folder, grading, aspect, exponent, share):
    """Packs one scene (exponent None: disks, no [shape]) and returns its summary's figures."""
    config = os.path.join(folder, "scene.toml")
    shape = "" if exponent is None else SHAPE.format(aspect=aspect, exponent=exponent)
    with open(config, "w") as f:
        f.write(SCENE.format(grading=grading, share=share, shape=shape))
    out = os.path.join(folder, "out")
    subprocess.run([binary, "pack", config, "--out", out, "--quiet"], check=True)
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    return s["particles"], s["porosity"], s["seconds"]


def markdown(rows, disks):
    """The table of docs/shapes.md: porosity per aspect ratio and its range."""
    head = "| grading | α = β | contacts | " + " | ".join(f"{a:g}" for a in ASPECTS) + " | range |"
    lines = [head, "|" + "---|" * (len(ASPECTS) + 4)]
    for gname, _ in GRADINGS:
        for exponent in EXPONENTS:
            for contacts in (2, 1):
                pts = [r[5] for r in rows if r[0] == gname and r[1] == exponent and r[3] == contacts]
                cells = " | ".join(f"{p:.3f}" for p in pts)
                span = f"{min(pts):.2f}–{max(pts):.2f}"
                lines.append(f"| {gname.replace('-', '–')} | {exponent:g} | {contacts} | {cells} | {span} |")
    lines.append("")
    for gname, _ in GRADINGS:
        lines.append(f"disks, {gname}, disk front: porosity {disks[gname]:.3f}")
    return "\n".join(lines)


def main():
    binary, dest = sys.argv[1], sys.argv[2]
    rows = []
    disks = {}
    with tempfile.TemporaryDirectory() as folder:
        for gname, grading in GRADINGS:
            n, phi, secs = run(binary, folder, grading, 1.0, None, 0)
            disks[gname] = phi
            rows.append([gname, "disks", 1.0, 2, n, round(phi, 4), round(secs, 2)])
            print(*rows[-1], flush=True)
            for exponent in EXPONENTS:
                for aspect in ASPECTS:
                    for share in (0, 1):
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

    colours = dict(zip(EXPONENTS, ["C0", "C1", "C2", "C3"]))
    markers = ["^", "v", "<", ">"]
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.2), sharey=True)
    for ax, (gname, _) in zip(axes, GRADINGS):
        for exponent in EXPONENTS:
            for contacts in (2, 1):
                pts = [(r[2], r[5]) for r in rows if r[0] == gname and r[1] == exponent and r[3] == contacts]
                label = f"gapack, alpha = beta = {exponent:g}, {contacts} contact{'s' if contacts == 2 else ''}"
                ax.plot(
                    *zip(*pts),
                    marker="o",
                    markersize=4,
                    color=colours[exponent],
                    linestyle="-" if contacts == 2 else "--",
                    label=label,
                )
        ax.plot([1.0], [disks[gname]], marker="*", markersize=12, color="k", linestyle="", label="gapack, disks (disk front)")
        ax.axhline(1 - DENSEST_ELLIPSES, color="0.4", linestyle=":", label="densest ellipses, any aspect: 1 - pi/(2 sqrt 3)")
        jammed = [p for p in PUBLISHED if p[2].startswith("jammed ellipses")]
        for (aspect, phi, label), m in zip(jammed, markers):
            ax.plot([aspect], [1 - phi], marker=m, markersize=7, color="k", fillstyle="none", linestyle="", label=label)
        for aspect, phi, label in PUBLISHED[len(jammed):]:
            m = "s" if label.startswith("jammed") else "x"
            ax.plot([aspect], [1 - phi], marker=m, markersize=7, color="k", fillstyle="none", linestyle="", label=label)
        ax.set_title(f"{gname}, 40 mm square")
        ax.set_xlabel("aspect ratio a/b")
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel("porosity 1 - phi")
    handles, labels = axes[1].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.2, 1, 1))
    fig.savefig(os.path.join(dest, "shapes_porosity.png"), dpi=110)
    print(markdown(rows, disks))


if __name__ == "__main__":
    main()
