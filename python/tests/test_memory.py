"""A 10^6-disk pack comes back as three arrays made once: the heap then
holds 24 bytes per disk (x, y, r as float64) and nothing else of the run. Measured in a process of
its own (Linux: /proc/self/status, glibc's mallinfo2)."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

SCRIPT = textwrap.dedent(
    r'''
    import ctypes, gc, json, warnings
    import gapack

    warnings.simplefilter("ignore", gapack.GapackWarning)

    class MallInfo2(ctypes.Structure):
        _fields_ = [(n, ctypes.c_size_t) for n in (
            "arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks",
            "fsmblks", "uordblks", "fordblks", "keepcost")]

    libc = ctypes.CDLL("libc.so.6")
    libc.mallinfo2.restype = MallInfo2

    def heap():
        """Bytes malloc has handed out and not had back."""
        m = libc.mallinfo2()
        return m.uordblks + m.hblkhd

    def status(key):
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith(key + ":"):
                    return int(line.split()[1]) * 1024

    # Table 3.4 in a 1224.2 mm square: about 10^6 disks (gapack bench's scene).
    config = """
    seed = 1
    [domain]
    shape = "rectangle"
    width = 1224.2
    height = 1224.2
    [grading]
    table = [[1.200, 0], [1.215, 11], [1.225, 21], [1.235, 31], [1.245, 43], [1.255, 54], [1.265, 65], [1.275, 77], [1.285, 89], [1.295, 100]]
    """
    gapack.pack(config.replace("1224.2", "30"))  # libraries loaded, pools made
    gc.collect()
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")  # the peak (VmHWM) from here
    rss, held = status("VmRSS"), heap()
    p = gapack.pack(config, force=True)
    n = len(p)
    told = {
        "disks": n,
        "peak_rss_per_disk": (status("VmHWM") - rss) / n,
        "heap_per_disk": (heap() - held) / n,
        "arrays_per_disk": (p.x.nbytes + p.y.nbytes + p.r.nbytes) / n,
        "not_copied": all(
            not a.flags.owndata and type(a.base).__name__ == "PySliceContainer"
            for a in (p.x, p.y, p.r)
        ),
    }
    print(json.dumps(told))
    '''
)


def test_a_million_disks_come_back_as_three_arrays_made_once():
    run = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    told = json.loads(run.stdout.strip().splitlines()[-1])
    print(
        f"10^6 pack from Python: {told['disks']} disks, peak RSS "
        f"{told['peak_rss_per_disk']:.1f} bytes/disk, heap held after "
        f"{told['heap_per_disk']:.2f} bytes/disk (arrays {told['arrays_per_disk']:.0f})"
    )
    assert told["disks"] > 950_000
    assert told["arrays_per_disk"] == 24.0
    # The arrays own Rust's vectors: no copy into numpy's own buffers...
    assert told["not_copied"]
    # ...and the run keeps nothing else of its disks: no second copy (a
    # kept Rust packing would add 24 bytes per disk, a copied array 8).
    assert 23.5 < told["heap_per_disk"] < 26.0, told
    # The peak: the job's own (the packer, the measures, the check) and the
    # hand-over, where the packing's disks and the arrays exist together for
    # a moment (24 + 24 bytes per disk). `gapack pack` on this scene with no
    # formats peaks at 53 bytes per disk over its baseline; this run at 65
    # (a virtualenv) to 74 (CI's pyenv Python), the same extension.
    assert told["peak_rss_per_disk"] < 90.0, told
