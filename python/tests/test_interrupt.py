"""KeyboardInterrupt cancels a run through the job's cancel token; runs
release the GIL."""

from __future__ import annotations

import _thread
import json
import signal
import threading
import time

import pytest

import gapack

# A search that would run for a minute: an unreachable target. Its time
# limit only bounds a run whose interrupt went astray: the test then fails
# after a minute rather than holding CI for an hour.
LONG_SEARCH = """\
seed = 3
[domain]
shape = "rectangle"
width = 30
height = 30
[grading]
uniform = [1.2, 3.0]
[optimise]
target_porosity = 0.9
population = 24
generations = 100000
stagnation = 100000
time_limit_s = 60
max_psd_ks = 0.2
"""

# About 10^6 disks: a pack that takes about a second.
BIG_PACK = """\
seed = 1
[domain]
shape = "rectangle"
width = 1224.2
height = 1224.2
[grading]
table = [[1.200, 0], [1.215, 11], [1.225, 21], [1.235, 31], [1.245, 43], [1.255, 54], [1.265, 65], [1.275, 77], [1.285, 89], [1.295, 100]]
"""


@pytest.fixture(autouse=True)
def ctrl_c_raises():
    """Python's own Ctrl-C handler for each test: a process started in the
    background by a shell inherits SIGINT ignored, and then
    ``_thread.interrupt_main`` does nothing."""
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, before)


def interrupt_after(seconds: float) -> threading.Timer:
    """Raise KeyboardInterrupt in the main thread after ``seconds``, as Ctrl-C does."""
    timer = threading.Timer(seconds, _thread.interrupt_main)
    timer.start()
    return timer


def test_keyboard_interrupt_raises_with_the_best_so_far():
    generations = []
    timer = interrupt_after(0.6)
    start = time.monotonic()
    with pytest.warns(gapack.GapackWarning), pytest.raises(gapack.Interrupted) as caught:
        gapack.optimise(LONG_SEARCH, on_generation=generations.append)
    stopped = time.monotonic() - start
    timer.join()
    err = caught.value
    assert isinstance(err, KeyboardInterrupt)
    p = err.packing
    assert p is err.result and p.interrupted
    # Stopped at the next generation, long before the search's own limits.
    assert 0.6 <= stopped < 5.0, stopped
    assert len(generations) >= 2
    assert p.summary["interrupted"] is True and p.summary["stop"] == "interrupted"
    # Every generation was told but, at most, the one whose callback the
    # KeyboardInterrupt itself broke into (Python runs the signal's handler
    # between any two bytecodes, the callback's included).
    seen = [g["index"] for g in generations]
    g = p.summary["generations"]
    assert set(seen) <= set(range(g + 1)) and len(seen) >= g
    assert all(p.history["best"][e["index"]] == e["best"] for e in generations)
    # The best so far is a valid packing of the config.
    told = gapack.verify(p.x, p.y, p.r, LONG_SEARCH)
    assert told["valid"], told


def test_keyboard_interrupt_can_return_the_best_so_far(tmp_path):
    timer = interrupt_after(0.4)
    with pytest.warns(gapack.GapackWarning):
        p = gapack.optimise(LONG_SEARCH, on_interrupt="return")
    timer.join()
    assert p.interrupted and p.summary["interrupted"] is True
    files = p.write(tmp_path / "best", formats=["csv"])
    assert "packing.csv" in files and "convergence.csv" in files
    manifest = json.loads((tmp_path / "best" / "manifest.json").read_text())
    assert manifest["interrupted"] is True


def test_interrupt_before_anything_is_finished_is_a_plain_keyboard_interrupt():
    timer = interrupt_after(0.15)
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt) as caught, pytest.warns(gapack.GapackWarning, match="975,582 disks"):
        gapack.pack(BIG_PACK, force=True)
    stopped = time.monotonic() - start
    timer.join()
    assert not isinstance(caught.value, gapack.Interrupted)
    # The pack of ~10^6 disks (about a second, and more for its measures)
    # stopped within a few of the packer's polls of its token.
    assert stopped < 0.15 + 0.5, stopped


def test_runs_release_the_gil():
    count = 0
    running = True

    def spin():
        nonlocal count
        while running:
            count += 1

    spinner = threading.Thread(target=spin)
    spinner.start()
    try:
        timer = interrupt_after(0.8)
        with pytest.warns(gapack.GapackWarning), pytest.raises(gapack.Interrupted):
            gapack.optimise(LONG_SEARCH)
        timer.join()
    finally:
        running = False
        spinner.join()
    # A run that held the GIL would have let the spinner count only while
    # Python switched threads between calls; it counts freely instead
    # (millions in 0.8 s; a few thousand if the GIL were held).
    assert count > 100_000, count
