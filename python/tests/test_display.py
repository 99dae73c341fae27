"""The packing in a notebook: its picture (``_repr_png_``, ``_repr_html_``,
``png``), ``plot`` with matplotlib, pandas tables both ways, the summary
read by attribute, and the progress bar's front end.

pandas and matplotlib are optional dependencies: the tests that need one
are skipped without it (CI installs both).
"""

from __future__ import annotations

import base64
import json
import struct
import sys
import time
import types
import zlib

import numpy as np
import pytest

import gapack
from conftest import ROOT, SQUARE

LAYERED = """\
seed = 1
[domain]
shape = "rectangle"
width = 20
height = 20
[grading]
uniform = [1.0, 1.6]
[[materials]]
name = "ceramic"
density = 3900.0
[[materials]]
name = "metal"
density = 7800.0
[layering]
axis = "y"
bins = 4
profile = "linear"
"""

ELLIPSES = SQUARE + '[shape]\nkind = "superellipse"\naspect = 1.5\n'


def png_size(png: bytes) -> tuple:
    """The width and height of a PNG, after checking that it is one: the
    signature, every chunk's CRC, and image data that inflates to the rows
    of an 8-bit RGB or RGBA image of that size."""
    assert png[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG signature"
    at, idat, header = 8, b"", None
    while at < len(png):
        (length,) = struct.unpack(">I", png[at : at + 4])
        kind, body = png[at + 4 : at + 8], png[at + 8 : at + 8 + length]
        (crc,) = struct.unpack(">I", png[at + 8 + length : at + 12 + length])
        assert zlib.crc32(kind + body) == crc, f"bad CRC in {kind!r}"
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        at += 12 + length
        if kind == b"IEND":
            break
    assert at == len(png) and header is not None
    width, height, depth, colour = header[:4]
    assert depth == 8 and colour in (2, 6)
    channels = 3 if colour == 2 else 4
    assert len(zlib.decompress(idat)) == height * (1 + channels * width)
    return width, height


@pytest.fixture(scope="module")
def square():
    return gapack.pack(SQUARE)


@pytest.fixture(scope="module")
def layered():
    return gapack.layer(LAYERED)


def test_the_summary_reads_by_key_and_by_attribute(square, layered):
    s = square.summary
    assert isinstance(s, dict) and isinstance(s, gapack.Summary)
    assert s.porosity == s["porosity"] and s.particles == len(square)
    # Nested tables too, and it stays plain JSON.
    tables = [k for k, v in s.items() if isinstance(v, dict)]
    assert tables, "summary.json has nested tables"
    for key in tables:
        assert isinstance(s[key], gapack.Summary)
        for inner in s[key]:
            if inner.isidentifier() and inner not in dir(dict):
                assert getattr(getattr(s, key), inner) == s[key][inner]
    assert json.loads(json.dumps(s)) == s
    assert dict(s) == s and "porosity" in dir(s)
    # The typed figures are in every run's summary, of their types.
    for run in (square, layered):
        for key, kind in gapack.Summary.__annotations__.items():
            kind = {"str": str, "int": int, "float": (int, float), "bool": bool}[kind]
            assert isinstance(getattr(run.summary, key), kind), key
    with pytest.raises(AttributeError, match="no 'nonesuch'"):
        s.nonesuch
    assert layered.summary.profile_rms_error <= layered.summary.baseline_rms_error


def test_repr_png_is_packing_png(square, tmp_path):
    png = square._repr_png_()
    assert isinstance(png, bytes)
    # 30 × 20 mm with 3 % margins: 1600 px wide, the legend strip below.
    width, height = png_size(png)
    assert width == 1600 and 900 < height < 1600
    # Kept: the same bytes again, and those write() puts in packing.png.
    assert square._repr_png_() == png
    square.write(tmp_path, formats=["png"])
    assert (tmp_path / "packing.png").read_bytes() == png
    # Other colourings draw other pictures of the same size.
    assert square.png("size") == png  # no materials: by size already
    with pytest.raises(ValueError, match="color_by"):
        square.png("rainbow")


def test_repr_png_colours_by_material(layered):
    by_material, by_size = layered._repr_png_(), layered.png(color_by="radius")
    assert png_size(by_material) == png_size(by_size)
    assert by_material != by_size and layered.png("material") == by_material


def test_repr_html_shows_the_picture_and_the_figures(layered):
    page = layered._repr_html_()
    start = page.index("data:image/png;base64,") + len("data:image/png;base64,")
    png = base64.b64decode(page[start : page.index("'", start)])
    assert png == layered._repr_png_()
    for words in (
        f"<td style='text-align:left'>{len(layered)}</td>",
        f"{layered.summary['porosity']:.4f}",
        "rectangle 20 × 20 mm",
        f"<td style='text-align:left'>{layered.seed}</td>",
        "grading KS",
        "ceramic, metal",
        "profile RMS error",
    ):
        assert words in page, words


def test_a_hundred_thousand_disks_render_as_a_png():
    """A benchmark figure, printed (run with -s or -rP to see it): the
    picture of 10⁵ disks. A square lattice, made as a packing by
    from_pandas (no packing run to wait for)."""
    pd = pytest.importorskip("pandas")
    side = 320
    i = np.arange(100_000)
    df = pd.DataFrame({"x": i % side + 0.5, "y": i // side + 0.5, "r": np.full(i.size, 0.45)})
    p = gapack.Packing.from_pandas(df, domain={"shape": "rectangle", "width": side, "height": side})
    assert len(p) == 100_000
    start = time.perf_counter()
    png = p._repr_png_()
    seconds = time.perf_counter() - start
    print(f"_repr_png_ of 100000 disks: {seconds:.3f} s, {len(png) / 1e6:.2f} MB")
    # A square drawing 1520 px a side (1600 less the legend strip's 80).
    assert png_size(png) == (1520, 1600)


def test_to_pandas_has_the_columns_of_packing_csv(layered, tmp_path):
    pd = pytest.importorskip("pandas")
    df = layered.to_pandas()
    layered.write(tmp_path, formats=["csv"])
    csv = pd.read_csv(tmp_path / "packing.csv")
    assert list(df.columns) == list(csv.columns) == ["id", "x", "y", "r", "material"]
    assert (df["id"].to_numpy() == csv["id"].to_numpy()).all()
    # packing.csv writes the shortest digits that read back exactly.
    for c in ("x", "y", "r"):
        assert np.array_equal(df[c].to_numpy(), csv[c].to_numpy())
    assert list(df["material"].astype(str)) == list(csv["material"])
    assert list(df["material"].cat.categories) == ["ceramic", "metal"]
    assert np.array_equal(df["material"].cat.codes.to_numpy(), layered.material)
    # A table of its own: writing to it leaves the packing alone.
    df.loc[0, "x"] = -1.0
    assert layered.x[0] != -1.0


def test_to_pandas_of_shapes_has_their_columns(tmp_path):
    pd = pytest.importorskip("pandas")
    p = gapack.pack(ELLIPSES)
    df = p.to_pandas()
    assert list(df.columns) == ["id", "x", "y", "r", "angle", "a", "b", "alpha", "beta"]
    assert np.array_equal(df["a"].to_numpy(), p.a) and np.array_equal(df["angle"].to_numpy(), p.angle)
    p.write(tmp_path, formats=["csv"])
    csv = pd.read_csv(tmp_path / "packing.csv")
    assert list(df.columns) == list(csv.columns)
    for c in df.columns:
        assert np.array_equal(df[c].to_numpy(), csv[c].to_numpy()), c
    # Polygons: their template index (packing.csv adds its rounding and vertices).
    polygons = gapack.pack(
        SQUARE + '[shape]\nkind = "polygon"\n[[shape.templates]]\nvertices = [[0, 0], [2, 0], [1, 1.7]]\nrounding = 0.1\n'
    ).to_pandas()
    assert list(polygons.columns) == ["id", "x", "y", "r", "angle", "template"]


def test_from_pandas_round_trips_exactly(layered):
    pd = pytest.importorskip("pandas")
    df = layered.to_pandas()
    back = gapack.Packing.from_pandas(df)
    for c in ("x", "y", "r", "material"):
        assert np.array_equal(getattr(back, c), getattr(layered, c)), c
    assert back.seed == layered.seed and back.materials == layered.materials
    assert back.summary.particles == layered.summary.particles
    assert back.summary.porosity == pytest.approx(layered.summary.porosity, abs=1e-12)
    assert back.summary.psd_ks == pytest.approx(layered.summary.psd_ks, abs=1e-12)
    pd.testing.assert_frame_equal(back.to_pandas(), df)
    # Materials by name (as packing.csv has them) or by index.
    named = df.assign(material=df["material"].astype(str))
    assert np.array_equal(gapack.Packing.from_pandas(named).material, layered.material)
    indexed = df.assign(material=layered.material.astype(np.int64))
    assert np.array_equal(gapack.Packing.from_pandas(indexed).material, layered.material)


def test_from_pandas_takes_a_domain_or_a_config(square):
    pd = pytest.importorskip("pandas")
    disks = pd.DataFrame({"x": square.x, "y": square.y, "d": 2 * square.r})
    in_domain = gapack.Packing.from_pandas(disks, domain={"shape": "rectangle", "width": 30, "height": 20})
    assert np.array_equal(in_domain.x, square.x) and np.allclose(in_domain.r, square.r)
    assert in_domain.summary.porosity == pytest.approx(square.summary.porosity, abs=1e-12)
    in_config = gapack.Packing.from_pandas(disks.rename(columns={"d": "diameter"}), config=SQUARE, seed=9)
    assert in_config.seed == 9 and in_config.summary.psd_ks == pytest.approx(square.summary.psd_ks, abs=1e-12)
    with pytest.raises(ValueError, match="domain= .* or config="):
        gapack.Packing.from_pandas(disks)
    with pytest.raises(ValueError, match="x, y and r"):
        gapack.Packing.from_pandas(disks[["x", "y"]], config=SQUARE)


def test_from_pandas_checks_the_disks(square, layered):
    pd = pytest.importorskip("pandas")
    df = square.to_pandas()
    piled = pd.concat([df, df.iloc[:1]], ignore_index=True)
    with pytest.raises(gapack.GapackError, match="overlapping"):
        gapack.Packing.from_pandas(piled)
    outside = df.assign(x=df["x"] + 5.0)
    with pytest.raises(gapack.GapackError, match="outside the domain"):
        gapack.Packing.from_pandas(outside)
    wrong = layered.to_pandas().assign(material="glass")
    with pytest.raises(ValueError, match='"glass" is not among'):
        gapack.Packing.from_pandas(wrong)


def test_plot_draws_every_disk(layered, square):
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import EllipseCollection

    fig, ax = plt.subplots()
    assert layered.plot(ax=ax) is ax
    (disks,) = [c for c in ax.collections if isinstance(c, EllipseCollection)]
    assert len(disks.get_offsets()) == len(layered)
    # By material: two colours, the legend names them.
    colours = {tuple(c) for c in disks.get_facecolors()}
    assert len(colours) == 2
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["ceramic", "metal"]
    # By radius (and material falls back to it without materials): a colour scale.
    ax2 = square.plot(color_by="radius", linewidth=0)
    (scaled,) = [c for c in ax2.collections if isinstance(c, EllipseCollection)]
    assert np.array_equal(scaled.get_array(), square.r)
    assert square.plot().collections[0].get_array() is not None
    with pytest.raises(ValueError, match="color_by"):
        square.plot(color_by="rainbow")
    plt.close("all")


def test_plot_without_matplotlib_says_what_to_install(square, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(ImportError, match="needs matplotlib.*pip install matplotlib"):
        square.plot()


def test_progress_is_a_notebook_widget_in_a_notebook(monkeypatch):
    """tqdm installed: in a Jupyter kernel the bar is tqdm's notebook
    widget (its text bar when ipywidgets is missing, where the widget
    fails); elsewhere tqdm.auto's choice, as before."""
    tqdm = pytest.importorskip("tqdm")
    from tqdm.auto import tqdm as auto

    assert not gapack._in_notebook()
    assert gapack._bar_class() is auto
    # A Jupyter kernel's shell has a kernel; a terminal IPython's has none.
    shell = types.SimpleNamespace(kernel=object())
    ipython = types.ModuleType("IPython")
    ipython.get_ipython = lambda: shell
    monkeypatch.setitem(sys.modules, "IPython", ipython)
    assert gapack._in_notebook()
    try:
        import ipywidgets  # noqa: F401
    except ImportError:
        from tqdm.std import tqdm as expected
    else:
        from tqdm.notebook import tqdm as expected
    assert gapack._bar_class() is expected
    monkeypatch.setitem(sys.modules, "ipywidgets", None)
    assert gapack._bar_class() is tqdm.std.tqdm
    shell.kernel = None
    assert not gapack._in_notebook() and gapack._bar_class() is auto


def test_the_version_is_set_in_one_place():
    """The installed distribution's version is the extension's, which is
    the workspace's (Cargo.toml's [workspace.package], inherited by every
    crate): pyproject.toml reads it from there."""
    from importlib.metadata import version

    assert version("gapack") == gapack.__version__
    workspace = (ROOT / "Cargo.toml").read_text()
    assert f'[workspace.package]\nversion = "{gapack.__version__}"\n' in workspace
    for crate in (".", "cli", "serve", "python", "benchmarks"):
        cargo = (ROOT / crate / "Cargo.toml").read_text()
        assert "\nversion.workspace = true\n" in cargo, crate
    assert 'dynamic = ["version"]' in (ROOT / "python" / "pyproject.toml").read_text()
