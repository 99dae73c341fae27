"""h6, the meshless support size, from Python: each particle's distance to
its k-th nearest centre, against a brute-force search, and the same
values as packing.csv's h6 column."""

from __future__ import annotations

import csv

import numpy as np

import gapack

CONFIG = {
    "seed": 4,
    "domain": {"shape": "rectangle", "width": 30, "height": 20},
    "grading": {"uniform": [1.0, 2.0]},
    "output": {"formats": ["csv"], "per_particle": ["h6"]},
}


def brute(x: np.ndarray, y: np.ndarray, k: int) -> np.ndarray:
    """The k-th smallest distance from each centre to the others."""
    dx = x[:, None] - x[None, :]
    dy = y[:, None] - y[None, :]
    d = np.sqrt(dx * dx + dy * dy)
    np.fill_diagonal(d, np.inf)
    return np.sort(d, axis=1)[:, k - 1]


def test_hk_is_the_kth_nearest_centre():
    p = gapack.pack(CONFIG)
    assert len(p) > 100
    for k in (1, 5, 6, 7):
        h = p.h6(k)
        assert h.shape == p.x.shape
        np.testing.assert_allclose(h, brute(p.x, p.y, k), rtol=1e-12, atol=0)
    assert np.array_equal(p.h6(), p.h6(6))
    # h6 over the local diameter: a dense pack's neighbours are near.
    ratio = p.h6() / (2 * p.r)
    assert 0.8 < np.median(ratio) < 2.0


def test_the_csv_column_holds_the_same_values(tmp_path):
    p = gapack.pack(CONFIG)
    p.write(str(tmp_path / "out"))
    with open(tmp_path / "out" / "packing.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0])[-1] == "h6"
    column = np.array([float(row["h6"]) for row in rows])
    assert np.array_equal(column, p.h6())
    assert p.summary["h6_over_d"]["count"] == len(p)


def test_too_few_particles_give_nan():
    p = gapack.pack({
        "seed": 1,
        "domain": {"shape": "rectangle", "width": 3, "height": 3},
        "grading": {"constant": 1.0},
    })
    assert 0 < len(p) <= 9
    h = p.h6(len(p))
    assert np.isnan(h).all()
