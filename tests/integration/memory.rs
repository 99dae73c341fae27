//! Memory of the whole `gapack pack` process (issue 22): the peak resident
//! set a packed disk adds, packer, metrics and writers together.

use std::path::Path;
use std::process::{Command, Stdio};

use super::common::scratch;

/// Bytes of peak resident set that a packed disk may add to `gapack pack`
/// with CSV output: the bound for 10⁶ disks, whose whole process
/// peaks at about 64 bytes a disk (`/usr/bin/time -v`). Here, on about 10⁵
/// disks, the fixed part of the process (binary, libraries, threads, about
/// 9 MB) is taken off by a run of some 550 disks: the rest measures
/// 56–58 bytes a disk (the packer's own peak), and measured 113–118 while
/// the metrics copied the packing and `packing.csv` was built whole in
/// memory before being written. The margin, about 40 bytes a disk (4 MB
/// here), is far above the run-to-run spread of the kernel's count (a few
/// pages) and leaves the packer room to change.
const MAX_BYTES_PER_DISK: f64 = 100.0;

/// The thesis' Table 3.4 grading in a square of `side` mm, CSV output only.
fn square(side: f64) -> String {
    format!(
        "seed = 0\n[domain]\nshape = \"rectangle\"\nwidth = {side}\nheight = {side}\n\
         [grading]\ntable = [[1.200, 0], [1.215, 11], [1.225, 21], [1.235, 31], [1.245, 43], \
         [1.255, 54], [1.265, 65], [1.275, 77], [1.285, 89], [1.295, 100]]\n\
         interpolation = \"log\"\nbasis = \"number\"\n[output]\nformats = [\"csv\"]\n"
    )
}

/// Run `gapack pack` on a square of `side` mm in `dir`: the disks written
/// and the peak resident set of that process alone (bytes), as the kernel
/// counted it when the process was reaped (`wait4`, `ru_maxrss`).
#[expect(
    clippy::zombie_processes,
    reason = "the child is reaped by wait4, which gives its resource usage"
)]
fn pack_peak(dir: &Path, side: f64) -> (usize, f64) {
    let name = format!("square_{side}");
    let config = dir.join(format!("{name}.toml"));
    std::fs::write(&config, square(side)).expect("config written");
    let out = dir.join(&name);
    let child = Command::new(env!("CARGO_BIN_EXE_gapack"))
        .arg("pack")
        .arg(&config)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        // The same threads on every machine: each may hold memory of its own.
        .env("RAYON_NUM_THREADS", "2")
        .stdout(Stdio::null())
        .spawn()
        .expect("gapack started");
    let pid = child.id() as libc::pid_t;
    let mut status = 0;
    // SAFETY: an all-zero `rusage` is a valid value of that plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: `pid` is our own child, not yet waited for; the pointers are
    // to live locals of the right types.
    let reaped = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    assert_eq!(reaped, pid, "wait4: {}", std::io::Error::last_os_error());
    assert!(
        libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
        "gapack pack {} failed: status {status}",
        config.display()
    );
    let table = std::fs::read_to_string(out.join("packing.csv")).expect("packing.csv written");
    let disks = table.lines().count() - 1;
    // Linux counts `ru_maxrss` in kilobytes (KiB).
    (disks, usage.ru_maxrss as f64 * 1024.0)
}

#[test]
fn a_packed_disk_adds_at_most_100_bytes_to_the_peak_of_gapack_pack() {
    let dir = scratch("memory-per-disk");
    let (few, base) = pack_peak(&dir, 30.0);
    let (disks, peak) = pack_peak(&dir, 400.0);
    assert!(few < 1_000 && disks > 100_000, "{few} and {disks} disks");
    let per_disk = (peak - base) / (disks - few) as f64;
    assert!(
        per_disk <= MAX_BYTES_PER_DISK,
        "{per_disk:.1} bytes of peak resident set a disk (peak {:.1} MB with {disks} disks, {:.1} MB with {few}): the bound is {MAX_BYTES_PER_DISK}",
        peak / 1e6,
        base / 1e6
    );
    let _ = std::fs::remove_dir_all(&dir);
}
