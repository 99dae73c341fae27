"""Each function of the package, each kind of config, the arrays, the errors."""

from __future__ import annotations

import json
import math
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import gapack
from conftest import SQUARE

SQUARE_DICT = {
    "seed": 4,
    "domain": {"shape": "rectangle", "width": 30, "height": 20},
    "grading": {"uniform": [1.0, 2.0]},
}

# A quick search: 20 x 20 mm, about 30 disks, a reachable target.
SEARCH = """\
seed = 1
[domain]
shape = "rectangle"
width = 20
height = 20
[grading]
uniform = [1.2, 4.8]
[optimise]
target_porosity = 0.45
tolerance = 0.01
population = 16
generations = 30
stagnation = 30
max_evaluations = 400
max_psd_ks = 0.2
"""


def test_path_text_and_dict_give_one_packing(work):
    Path("square.toml").write_text(SQUARE)
    by_path = gapack.pack("square.toml")
    by_pathlib = gapack.pack(Path("square.toml"))
    by_text = gapack.pack(SQUARE)
    by_dict = gapack.pack(SQUARE_DICT)
    assert len(by_path) > 100
    for other in (by_pathlib, by_text, by_dict):
        assert np.array_equal(other.x, by_path.x)
        assert np.array_equal(other.y, by_path.y)
        assert np.array_equal(other.r, by_path.r)
    assert (by_path.config, by_text.config, by_dict.config) == ("square.toml", "<string>", "<dict>")
    # The seed argument overrides the config's, as --seed does.
    other_seed = gapack.pack(SQUARE_DICT, seed=5)
    assert other_seed.seed == 5 and by_dict.seed == 4
    assert not np.array_equal(other_seed.r[:10], by_dict.r[:10])


def test_arrays_are_float64_vectors_made_once_and_read_only():
    p = gapack.pack(SQUARE)
    n = p.summary["particles"]
    assert len(p) == n
    for name in ("x", "y", "r"):
        a = getattr(p, name)
        assert a.dtype == np.float64 and a.shape == (n,) and a.ndim == 1
        assert a.flags.c_contiguous
        assert not a.flags.writeable
        # The same array on every access: no copy per attribute read.
        assert getattr(p, name) is a
        # Handed over from Rust's vector, not copied into numpy's own buffer.
        assert not a.flags.owndata and type(a.base).__name__ == "PySliceContainer"
    with pytest.raises(ValueError):
        p.x[0] = 1.0
    assert p.material is None and p.materials == []
    assert p.history is None
    # The disks lie in the domain and their area gives the summary's porosity.
    d = p.domain
    assert d["shape"] == "rectangle" and (d["width"], d["height"]) == (30.0, 20.0)
    assert d["area"] == 600.0 and d["walls"] == "exact" and d["periodic"] is False
    assert d["outline"].shape == (4, 2)
    assert np.all(p.x - p.r >= -1e-9) and np.all(p.x + p.r <= 30 + 1e-9)
    assert np.all(p.y - p.r >= -1e-9) and np.all(p.y + p.r <= 20 + 1e-9)
    porosity = 1 - np.sum(math.pi * p.r**2) / d["area"]
    assert abs(porosity - p.summary["porosity"]) < 1e-12
    assert p.summary["seed"] == 4 and p.summary["config"] == "<string>"
    assert p.job == "pack" and not p.interrupted
    assert repr(p).startswith(f"<gapack.Packing pack: {n} disks, porosity ")
    assert p.lines[0].startswith(f"<string>: {n} disks, porosity ")


def test_layer_gives_materials_as_int32_indices(work):
    p = gapack.layer("configs/fgm_power.toml")
    n = len(p)
    assert p.material.dtype == np.int32 and p.material.shape == (n,)
    assert not p.material.flags.writeable
    assert set(np.unique(p.material)) == {0, 1}
    assert [m["name"] for m in p.materials] == ["ceramic", "metal"]
    assert p.materials[1] == {"id": 2, "name": "metal", "density": 7800.0}
    # The power profile puts the metal at the top.
    top = p.material[p.y > 40].mean()
    bottom = p.material[p.y < 10].mean()
    assert top > 0.5 > bottom
    assert p.summary["profile_rms_error"] <= p.summary["baseline_rms_error"]


def test_optimise_returns_the_history_and_calls_back_each_generation():
    seen = []
    p = gapack.optimise(SEARCH, on_generation=seen.append)
    h = p.history
    g = p.summary["generations"]
    assert set(h) == {"generation", "best", "mean", "worst", "evaluations", "seconds", "feasible"}
    for key in ("best", "mean", "worst", "seconds"):
        assert h[key].dtype == np.float64 and h[key].shape == (g + 1,)
    assert h["generation"].dtype == np.int64 and list(h["generation"]) == list(range(g + 1))
    assert h["feasible"].dtype == np.bool_
    assert np.all(np.diff(h["evaluations"]) >= 0)
    # One call per generation, in order, with the history's figures.
    assert [s["index"] for s in seen] == list(range(g + 1))
    assert all(s["stage"] == "optimise" for s in seen)
    assert np.allclose([s["best"] for s in seen], h["best"], rtol=0, atol=0)
    assert set(seen[0]) == {"stage", "index", "best", "feasible", "mean", "worst", "evaluations", "seconds"}
    assert p.summary["best_porosity"] == pytest.approx(p.summary["porosity"])
    assert abs(p.summary["porosity"] - 0.45) <= 0.01
    assert p.summary["verdict"] == "reached" and p.summary["stop"] == "target reached"


def test_an_exception_in_on_generation_stops_the_search_and_is_raised():
    calls = []

    def stop_at_two(gen):
        calls.append(gen["index"])
        if gen["index"] == 2:
            raise RuntimeError("enough")

    slow = SEARCH.replace("max_evaluations = 400", "max_evaluations = 100000").replace(
        "generations = 30", "generations = 10000"
    ).replace("stagnation = 30", "stagnation = 10000").replace("target_porosity = 0.45", "target_porosity = 0.9")
    with pytest.raises(RuntimeError, match="enough"), pytest.warns(gapack.GapackWarning, match="outside the range"):
        gapack.optimise(slow, on_generation=stop_at_two)
    # The search stopped at the next generation: no call after the raise but
    # at most the one generation under way.
    assert calls[:3] == [0, 1, 2] and len(calls) <= 4


def test_warnings_are_gapack_warnings_and_kept(work):
    with pytest.warns(gapack.GapackWarning, match=r"\[optimise\] is not used by the pack job"):
        p = gapack.pack("configs/ap4.toml")
    assert any("[optimise] is not used" in w for w in p.warnings)


def test_verify_finds_overlaps_and_disks_outside():
    p = gapack.pack(SQUARE)
    ok = gapack.verify(p.x, p.y, p.r, SQUARE)
    assert ok["verdict"] == "valid" and ok["valid"] and ok["grading_kept"]
    assert ok["particles"] == len(p) and ok["overlaps"] == 0 and ok["outside"] == 0
    assert ok["porosity"] == pytest.approx(p.summary["porosity"], abs=1e-12)
    assert ok["psd_ks"] == pytest.approx(p.summary["psd_ks"], abs=1e-12)
    # Disk 7 moved onto disk 3: one overlap at least, naming both.
    x, y = p.x.copy(), p.y.copy()
    x[7], y[7] = x[3] + 0.5 * p.r[3], y[3]
    bad = gapack.verify(x, y, p.r, SQUARE)
    assert bad["verdict"] == "FAILED" and not bad["valid"] and bad["overlaps"] >= 1
    assert 7 in bad["worst_overlap"][:2]
    # A disk pushed through the right wall.
    x = p.x.copy()
    x[0] = 30.0
    out = gapack.verify(x, p.y, p.r, SQUARE)
    assert out["outside"] == 1 and out["worst_outside"][0] == 0
    assert out["worst_outside"][1] == pytest.approx(p.r[0], rel=1e-9)
    # Any array-like is taken; lengths must agree.
    small = gapack.verify([5.0, 10.0], [5.0, 5.0], [1.0, 1.0], SQUARE)
    assert small["verdict"] == "valid, grading not checked" and small["psd_ks"] is None
    with pytest.raises(ValueError, match="one length"):
        gapack.verify([1.0, 2.0], [1.0], [0.5, 0.5], SQUARE)


def test_validate_describes_the_plan(work):
    told = gapack.validate("configs/ap4.toml")
    assert told["valid"] and told["job"] == "optimise" and told["seed"] == 1
    assert told["config"] == "configs/ap4.toml" and told["out"] == "out/ap4"
    assert any(line.startswith("job: optimise") for line in told["plan"])
    assert told["warnings"] == []
    as_pack = gapack.validate("configs/ap4.toml", job="pack", seed=9)
    assert as_pack["job"] == "pack" and as_pack["seed"] == 9
    assert any("[optimise] is not used by the pack job" in w for w in as_pack["warnings"])
    with pytest.raises(ValueError, match="unknown job"):
        gapack.validate("configs/ap4.toml", job="dance")


def test_config_errors_carry_their_location():
    text = SQUARE.replace("width = 30", "width = -30")
    with pytest.raises(gapack.ConfigError) as caught:
        gapack.pack(text)
    e = caught.value
    assert (e.origin, e.line, e.column, e.key) == ("<string>", 4, 9, "domain.width")
    assert str(e) == "<string>:4:9: domain.width: must be a positive finite number, got -30"
    assert isinstance(e, gapack.GapackError) and isinstance(e, ValueError)
    # From a dict: the key, and the place in gapack.to_toml(config).
    bad = {**SQUARE_DICT, "grading": {"uniform": [2.0, 1.0]}}
    with pytest.raises(gapack.ConfigError) as caught:
        gapack.validate(bad)
    e = caught.value
    assert e.origin == "<dict>" and e.key.startswith("grading.uniform")
    line = gapack.to_toml(bad).splitlines()[e.line - 1]
    assert line.startswith("uniform = [2.0, 1.0]")
    # A syntax error and an unknown key.
    with pytest.raises(gapack.ConfigError) as caught:
        gapack.pack(SQUARE + "[packer\n")
    assert caught.value.line == 8 and "TOML syntax error" in str(caught.value)
    with pytest.raises(gapack.ConfigError) as caught:
        gapack.pack(SQUARE.replace("height = 20", "height = 20\nheigth = 3"))
    assert caught.value.line == 6 and caught.value.key == "domain.heigth"


def test_other_errors(work, tmp_path):
    # optimise needs an [optimise] table: an input error, located.
    with pytest.raises(gapack.InputError, match=r"^<string>:1:1: optimise: missing table \[optimise\]"):
        gapack.optimise(SQUARE)
    # A [fracture] config writes folders of its own: gapack.run runs it.
    with pytest.raises(gapack.InputError, match=r"gapack\.run\(config, out=DIR\)"):
        gapack.pack("configs/wells_exact.toml")
    with pytest.raises(FileNotFoundError):
        gapack.pack("configs/no_such.toml")
    with pytest.raises(TypeError, match="expected a path, TOML text or a dict"):
        gapack.pack(42)
    with pytest.raises(ValueError, match='on_interrupt: "raise" or "return"'):
        gapack.pack(SQUARE, on_interrupt="ignore")
    # A run that fails: the output folder is a file.
    p = gapack.pack(SQUARE)
    (tmp_path / "taken").write_text("a file")
    with pytest.raises(gapack.GapackError, match="cannot create directory"):
        p.write(tmp_path / "taken" / "sub")


def test_write_follows_formats_and_removes_what_an_earlier_run_left(tmp_path):
    p = gapack.pack(SQUARE)
    out = tmp_path / "run"
    files = p.write(out)  # the config's formats: csv, svg, png
    assert files == sorted(files)
    assert {"packing.csv", "packing.svg", "packing.png", "summary.json", "manifest.json"} <= set(files)
    assert sorted(f.name for f in out.iterdir()) == files
    files = p.write(out, formats=["lammps"])
    assert files == ["manifest.json", "packing.lammps", "summary.json"]
    assert sorted(f.name for f in out.iterdir()) == files
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["job"] == "pack" and manifest["seed"] == 4 and manifest["interrupted"] is False
    # packing.csv read back: the arrays, exactly (shortest round-trip numbers).
    p.write(out, formats=["csv"])
    table = np.loadtxt(out / "packing.csv", delimiter=",", skiprows=1)
    assert np.array_equal(table[:, 1], p.x) and np.array_equal(table[:, 3], p.r)
    with pytest.raises(ValueError, match="unknown format \"vrml\"; valid: csv, json, vtk"):
        p.write(out, formats=["vrml"])
    with pytest.raises(ValueError, match="given twice"):
        p.write(out, formats=["csv", "csv"])
    assert set(gapack.FORMATS) == {"csv", "json", "vtk", "vtp", "npz", "lammps", "yade", "pfc", "mercury", "liggghts-superquadric", "esys", "lammps-clumps", "liggghts-clumps", "svg", "png"}


def test_write_defaults_to_the_command_lines_folder(work):
    p = gapack.pack("configs/square_100.toml")
    files = p.write()
    assert (work / "out" / "square_100" / "packing.csv").is_file()
    assert "packing.csv" in files


def test_run_writes_any_job_like_the_command_line(work):
    told = gapack.run("configs/wells_exact.toml", out="out/wells")
    assert told["job"] == "pack" and not told["interrupted"]
    assert "wells.csv" in told["files"] and "7-CP-0370-SE/packing.csv" in told["files"]
    rows = (work / "out" / "wells" / "wells.csv").read_text().splitlines()
    assert len(rows) == 4
    assert told["lines"][-1].startswith("out/wells/wells.csv: 3 wells in ")


@pytest.mark.skipif(sys.version_info < (3, 11), reason="tomllib is Python 3.11's")
def test_to_toml_writes_what_the_dict_holds():
    import tomllib

    config = {
        "seed": np.int64(3),
        "domain": {"shape": "polygon", "vertices": np.array([[0, 0], [20, 0], [20, 8], [0, 8]])},
        "grading": {"table": [[1.2, 0], [1.5, 100]], "basis": "mass"},
        "materials": [
            {"name": "sand \"A\"", "density": 2650.0, "grading": {"uniform": [1.0, 1.4]}},
            {"name": "glass", "density": 2500},
        ],
        "sweep": {"fracture.width_mm": [1.5, 2.5], "seeds": 2},
        "flag": True,
        "tiny": 1e-07,
        "big": 1e20,
    }
    text = gapack.to_toml(config)
    back = tomllib.loads(text)
    assert back["seed"] == 3 and back["domain"]["vertices"] == [[0, 0], [20, 0], [20, 8], [0, 8]]
    assert back["materials"][0] == {"name": 'sand "A"', "density": 2650.0, "grading": {"uniform": [1.0, 1.4]}}
    assert back["materials"][1]["density"] == 2500
    assert back["sweep"]["fracture.width_mm"] == [1.5, 2.5]
    assert back["flag"] is True and back["tiny"] == 1e-07 and back["big"] == 1e20
    with pytest.raises(TypeError, match="domain.width: a config value must be"):
        gapack.to_toml({"domain": {"width": object()}})


def test_progress_draws_a_bar_per_stage(monkeypatch):
    """progress=True hands the events to tqdm.auto (a stand-in here: tqdm is optional)."""
    import types

    bars = []

    class Bar:
        def __init__(self, total=None, unit=None, desc=None, leave=True):
            self.total, self.unit, self.desc, self.n, self.postfix, self.closed = total, unit, desc, 0, "", False
            bars.append(self)

        def refresh(self):
            pass

        def update(self, k):
            self.n += k

        def set_postfix_str(self, text):
            self.postfix = text

        def close(self):
            self.closed = True

    auto = types.ModuleType("tqdm.auto")
    auto.tqdm = Bar
    monkeypatch.setitem(sys.modules, "tqdm", types.ModuleType("tqdm"))
    monkeypatch.setitem(sys.modules, "tqdm.auto", auto)
    p = gapack.optimise(SEARCH, progress=True)
    (bar,) = bars
    assert (bar.desc, bar.unit, bar.total) == ("optimise", "generation", 30)
    assert bar.n == p.summary["generations"] and bar.closed
    assert bar.postfix == f"best porosity {p.history['best'][-1]:.4f}"
    # A small pack draws no bar; progress=False none at all.
    bars.clear()
    gapack.pack(SQUARE, progress=True)
    gapack.optimise(SEARCH, progress=False)
    assert bars == []


def test_the_module_docstring_example_runs():
    import doctest

    result = doctest.testmod(gapack)
    assert result.attempted >= 2 and result.failed == 0


def test_shape_arrays_equal_packing_csv(tmp_path):
    import csv
    ellipses = SQUARE + '[shape]\nkind = "superellipse"\naspect = [1.2, 2.5]\nalpha = [2, 4]\n'
    polygons = SQUARE + (
        '[shape]\nkind = "polygon"\n'
        '[[shape.templates]]\nvertices = [[0, 0], [2, 0], [1, 1.7]]\nrounding = 0.1\nshare = 0.4\n'
        '[[shape.templates]]\nvertices = [[0, 0], [3, 0], [3, 1], [0, 1]]\nrounding = 0.1\nshare = 0.6\n'
    )
    for name, text in [("ellipses", ellipses), ("polygons", polygons)]:
        p = gapack.pack(text)
        out = tmp_path / name
        p.write(out, formats=["csv"])
        with open(out / "packing.csv", newline="") as f:
            rows = list(csv.DictReader(f))
        assert len(rows) == len(p) > 50
        for attr in ("angle", "a", "b", "alpha", "beta", "template"):
            array = getattr(p, attr)
            assert array.shape == (len(p),) and not array.flags.writeable
            assert getattr(p, attr) is array  # made once
        assert p.template.dtype == np.int32 and p.angle.dtype == np.float64
        assert np.array_equal(p.angle, [float(r["angle"]) for r in rows])
        assert np.array_equal(p.r, [float(r["r"]) for r in rows])
        if name == "ellipses":
            for col in ("a", "b", "alpha", "beta"):
                assert np.array_equal(getattr(p, col), [float(r[col]) for r in rows]), col
            assert (p.template == -1).all()
            assert ((p.alpha >= 2) & (p.alpha <= 4) & (p.beta >= 2) & (p.beta <= 4)).all()
            assert ((p.a / p.b >= 1.2 - 1e-9) & (p.a / p.b <= 2.5 + 1e-9)).all()
        else:
            assert np.array_equal(p.template, [int(r["template"]) for r in rows])
            assert set(p.template) == {0, 1}
            assert np.isnan(p.a).all() and np.isnan(p.beta).all()
    disks = gapack.pack(SQUARE)
    assert disks.angle is None and disks.a is None and disks.template is None


def test_verify_certifies_superellipses_and_finds_a_push():
    text = SQUARE + '[shape]\nkind = "superellipse"\naspect = 2\nalpha = 4\n'
    p = gapack.pack(text)
    shapes = dict(angle=p.angle, a=p.a, b=p.b, alpha=p.alpha, beta=p.beta)
    told = gapack.verify(p.x, p.y, p.r, text, **shapes)
    assert told["valid"] and told["overlaps"] == 0 and told["particles"] == len(p)
    assert told["porosity"] == pytest.approx(p.summary["porosity"], abs=1e-9)
    # Particle 1 (placed touching particle 0) pushed towards it by 5 % of
    # its radius: found.
    x, y = p.x.copy(), p.y.copy()
    d = np.array([x[0] - x[1], y[0] - y[1]])
    d /= np.linalg.norm(d)
    x[1] += d[0] * 0.05 * p.r[1]
    y[1] += d[1] * 0.05 * p.r[1]
    pushed = gapack.verify(x, y, p.r, text, **shapes)
    assert not pushed["valid"] and pushed["overlaps"] >= 1 and pushed["verdict"] == "FAILED"
    # Some of the five columns only: refused, not taken as disks.
    with pytest.raises(ValueError, match="all of angle"):
        gapack.verify(p.x, p.y, p.r, text, angle=p.angle)
