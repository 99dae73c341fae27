"""verify refuses tables that are no packing (empty, or not one-dimensional)
and stops on KeyboardInterrupt; copies of one disk are checked quickly."""

from __future__ import annotations

import _thread
import threading
import time

import numpy as np
import pytest

import gapack

SQUARE = """\
[domain]
shape = "rectangle"
width = 10
height = 10
[grading]
uniform = [0.8, 1.2]
"""


def test_empty_arrays_are_refused():
    with pytest.raises(ValueError, match="no disks to verify"):
        gapack.verify([], [], [], SQUARE)
    with pytest.raises(ValueError, match="no disks to verify"):
        gapack.verify(np.empty(0), np.empty(0), np.empty(0), SQUARE)


def test_two_dimensional_arrays_are_refused_not_flattened():
    x = np.array([[2.0, 5.0], [8.0, 5.0]])
    with pytest.raises(ValueError, match=r"x must be a one-dimensional array, got shape \(2, 2\)"):
        gapack.verify(x, x, np.full((2, 2), 0.5), SQUARE)
    with pytest.raises(ValueError, match=r"r must be a one-dimensional array, got shape \(1, 2\)"):
        gapack.verify([2.0, 8.0], [5.0, 5.0], [[0.5, 0.5]], SQUARE)
    with pytest.raises(ValueError, match=r"material must be a one-dimensional array, got shape \(2, 1\)"):
        gapack.verify([2.0, 8.0], [5.0, 5.0], [0.5, 0.5], SQUARE, material=[[0], [0]])
    # The same disks as one-dimensional arrays are checked.
    told = gapack.verify([2.0, 8.0], [5.0, 5.0], [0.5, 0.5], SQUARE)
    assert told["valid"] and told["particles"] == 2, told


def test_copies_of_one_disk_are_counted_and_named():
    n = 100_000
    told = gapack.verify(np.full(n, 5.0), np.full(n, 5.0), np.full(n, 1.0), SQUARE)
    assert not told["valid"] and told["verdict"] == "FAILED"
    assert told["overlaps"] == n * (n - 1) // 2 and told["overlaps_complete"]
    assert told["worst_overlap"] == (0, 1, 1.0)


def test_piled_disks_give_a_bounded_count_that_says_so():
    # 20 000 disks jittered about one point: every pair overlaps; each
    # disk's search stops soon after its first overlap, so the count is a
    # lower bound and the dict says so.
    rng = np.random.default_rng(2)
    n = 20_000
    x = 5.0 + rng.uniform(-1e-3, 1e-3, n)
    y = 5.0 + rng.uniform(-1e-3, 1e-3, n)
    told = gapack.verify(x, y, np.full(n, 1.0), SQUARE)
    assert not told["valid"] and not told["overlaps_complete"], told
    assert 0 < told["overlaps"] < n * (n - 1) // 2, told


def test_keyboard_interrupt_stops_a_long_check():
    # 5 000 000 disks jittered about one point: every pair overlaps and
    # none are copies; each disk's search is bounded after its first
    # overlap, but 5e6 disks of 256 tests still take seconds (about 8 s on
    # a 2-core machine, 1.3e9 tests).
    rng = np.random.default_rng(1)
    n = 5_000_000
    x = 5.0 + rng.uniform(-1e-3, 1e-3, n)
    y = 5.0 + rng.uniform(-1e-3, 1e-3, n)
    timer = threading.Timer(0.3, _thread.interrupt_main)
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        gapack.verify(x, y, np.full(n, 1.0), SQUARE)
    stopped = time.monotonic() - start
    timer.join()
    # Stopped soon after the interrupt, long before the check's end.
    assert stopped < 2.5, stopped
