"""The binary outputs read by their formats' own readers: `packing.vtp`
(raw and zlib-compressed) with VTK's `vtkXMLPolyDataReader`, `packing.npz` with `numpy.load`, each
value equal to `packing.csv`'s (shortest round-trip numbers: exactly).

Runs the gapack command line (``$GAPACK_BIN``, see conftest.py); the VTK
check needs the `vtk` Python module and is skipped without it unless
GAPACK_DEM_TESTS=required (CI).
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pytest

from conftest import SQUARE, need

#: The scenes: disks in the conftest's square, and superellipses.
SCENES = {
    "disks": SQUARE,
    "superellipses": SQUARE
    + '[shape]\nkind = "superellipse"\naspect = [1.2, 2.0]\norientation = "random"\n',
}

#: The shape columns packing.csv may have, in its order (all float64 in
#: the binary files; `template` int32).
SHAPE_COLUMNS = ("angle", "a", "b", "alpha", "beta", "template", "rounding")


def packed(cli: Path, tmp_path: Path, scene: str, compression: str = "none") -> Path:
    """`gapack pack` of the scene writing csv, vtp (its arrays stored as
    `compression` says) and npz; its folder."""
    config = (
        SCENES[scene]
        + '[output]\nformats = ["csv", "vtp", "npz"]\n'
        + f'vtp_compression = "{compression}"\n'
    )
    (tmp_path / "c.toml").write_text(config)
    done = subprocess.run(
        [str(cli), "pack", "c.toml", "--out", "out"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return tmp_path / "out"


def table(out: Path):
    """packing.csv as a structured array (floats exactly as written)."""
    return np.genfromtxt(out / "packing.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")


def shape_columns(csv) -> list[str]:
    return [c for c in SHAPE_COLUMNS if c in csv.dtype.names]


@pytest.mark.parametrize("scene", list(SCENES))
def test_numpy_loads_the_npz(cli, tmp_path, scene):
    out = packed(cli, tmp_path, scene)
    csv = table(out)
    n = len(csv)
    assert n > 50
    shapes = shape_columns(csv)
    assert bool(shapes) == (scene != "disks")
    with np.load(out / "packing.npz") as z:
        assert z.files == ["x", "y", "r", *shapes, "material"]
        for name in ("x", "y", "r", *shapes):
            assert z[name].dtype == np.dtype("<f8") and z[name].shape == (n,)
            assert np.array_equal(z[name], csv[name]), name
        assert z["material"].dtype == np.dtype("<i4")
        assert np.array_equal(z["material"], np.zeros(n, dtype=np.int32))


@pytest.mark.parametrize("compression", ["none", "zlib"])
@pytest.mark.parametrize("scene", list(SCENES))
def test_vtk_reads_the_vtp(cli, tmp_path, scene, compression):
    try:
        import vtk
        from vtk.util.numpy_support import vtk_to_numpy
    except ImportError:
        vtk = None
    need(vtk is not None, "the vtk Python module is not installed: pip install vtk")
    out = packed(cli, tmp_path, scene, compression)
    head = (out / "packing.vtp").read_bytes()[:1024]
    assert (b'compressor="vtkZLibDataCompressor"' in head) == (compression == "zlib")
    csv = table(out)
    n = len(csv)
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(str(out / "packing.vtp"))
    reader.Update()
    assert reader.GetErrorCode() == 0
    poly = reader.GetOutput()
    assert poly.GetNumberOfPoints() == n and poly.GetNumberOfVerts() == n
    points = vtk_to_numpy(poly.GetPoints().GetData())
    assert points.dtype == np.float64
    assert np.array_equal(points[:, 0], csv["x"]) and np.array_equal(points[:, 1], csv["y"])
    assert np.all(points[:, 2] == 0.0)
    # One vertex cell per point, in order.
    verts = poly.GetVerts()
    assert np.array_equal(vtk_to_numpy(verts.GetConnectivityArray()), np.arange(n))
    assert np.array_equal(vtk_to_numpy(verts.GetOffsetsArray()), np.arange(n + 1))
    data = poly.GetPointData()
    names = {data.GetArrayName(i) for i in range(data.GetNumberOfArrays())}
    shapes = shape_columns(csv)
    assert names == {"radius", "material", "id", *shapes}
    assert np.array_equal(vtk_to_numpy(data.GetArray("radius")), csv["r"])
    for name in shapes:
        assert np.array_equal(vtk_to_numpy(data.GetArray(name)), csv[name]), name
    assert np.array_equal(vtk_to_numpy(data.GetArray("id")), csv["id"])
    assert data.GetArray("material").GetDataTypeAsString() == "int"
    assert np.array_equal(vtk_to_numpy(data.GetArray("material")), np.zeros(n))
