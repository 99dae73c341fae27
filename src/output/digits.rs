//! Numbers written straight into byte buffers, byte for byte as Rust's
//! `Display` writes them, and text tables written as a stream of blocks of
//! rows formatted on all cores.
//!
//! Large tables (`packing.csv`, the DEM exports) spend most of their time
//! formatting floats: `ryu` gives the same shortest round-trip digits as
//! `Display` several times faster, and blocks of rows formatted in
//! parallel are written in order, so the bytes never depend on the thread
//! count and only a few blocks are held at once.

use std::io::{self, Write};

use rayon::prelude::*;

/// Appends `x` exactly as `format!("{x}")` writes it.
///
/// `ryu` writes the same shortest round-trip digits as `Display` in plain
/// decimal for magnitudes in [1e-5, 1e16) and zero, but ends whole numbers
/// with `.0` (`1.0`, `-0.0`), which is dropped, and breaks an exact tie
/// between two shortest candidates the other way ([`may_tie`]); outside
/// that range (where `ryu` switches to exponent form), for NaN and
/// infinities and where a tie is possible `Display` itself writes the
/// number.
pub(crate) fn push_f64(out: &mut Vec<u8>, x: f64) {
    let a = x.abs();
    if a == 0.0 || ((1e-5..1e16).contains(&a) && !may_tie(x)) {
        let mut buffer = ryu::Buffer::new();
        let text = buffer.format_finite(x).as_bytes();
        out.extend_from_slice(text.strip_suffix(b".0").unwrap_or(text));
    } else {
        // Writing to a Vec cannot fail.
        let _ = write!(out, "{x}");
    }
}

/// Whether two shortest decimal candidates for `x` can be equally close
/// to it, where `ryu` (half to even) and `Display` (half away from zero)
/// may pick different ones.
///
/// A tie needs the exact value of `x` to be the midpoint of two decimals
/// of the shortest length L ≤ 17, so to have L + 1 ≤ 18 significant
/// digits. With `x` = m·2^e (m odd), a whole `x` (e ≥ 0) is its own
/// shortest form, and otherwise `x` = m·5^−e · 10^e has exactly the digits
/// of m·5^−e (odd, so without trailing zeros): a tie is possible only when
/// m·5^−e < 10^18. Coordinates of a packing almost never are (they need
/// some 40 significant bits or more), halves and quarters are.
fn may_tie(x: f64) -> bool {
    let bits = x.to_bits();
    let field = (bits >> 52) & 0x7ff;
    let fraction = bits & ((1 << 52) - 1);
    let (mantissa, exponent) = if field == 0 {
        (fraction, -1074)
    } else {
        (fraction | (1 << 52), field as i64 - 1075)
    };
    if mantissa == 0 {
        return false;
    }
    let zeros = mantissa.trailing_zeros();
    let (m, e) = (mantissa >> zeros, exponent + i64::from(zeros));
    if e >= 0 {
        return false;
    }
    // 5^26 alone exceeds 10^18.
    if e < -25 {
        return false;
    }
    u128::from(m) * 5u128.pow(e.unsigned_abs() as u32) < 10u128.pow(18)
}

/// Appends the integer `n` in decimal, as `Display` writes it.
pub(crate) fn push_int<I: itoa::Integer>(out: &mut Vec<u8>, n: I) {
    out.extend_from_slice(itoa::Buffer::new().format(n).as_bytes());
}

/// Rows formatted into one buffer at a time: ~1 MB of a disk table (a
/// few rows in tests, so that small tables span many blocks).
const BLOCK_ROWS: usize = if cfg!(test) { 7 } else { 16_384 };

/// Writes `rows` rows to `out` in order, row `i` appended to a buffer by
/// `row(i, buffer)`, formatted in blocks of [`BLOCK_ROWS`] on all cores
/// ([`write_blocks`]).
///
/// # Errors
/// The first I/O error of `out`.
pub(crate) fn write_rows(
    out: &mut dyn Write,
    rows: usize,
    row: impl Fn(usize, &mut Vec<u8>) + Sync,
) -> io::Result<()> {
    write_blocks(out, rows.div_ceil(BLOCK_ROWS), |b, buffer| {
        let start = b * BLOCK_ROWS;
        for i in start..(start + BLOCK_ROWS).min(rows) {
            row(i, buffer);
        }
    })
}

/// Writes `blocks` blocks to `out` in order, block `b` appended to an
/// empty buffer by `block(b, buffer)`.
///
/// The blocks are made two per thread at once on the current rayon pool,
/// while the previous group of blocks is written: at most two groups are
/// held, whatever the number of blocks, and the bytes are the same
/// whatever the number of threads.
///
/// # Errors
/// The first I/O error of `out`.
pub(crate) fn write_blocks(
    out: &mut dyn Write,
    blocks: usize,
    block: impl Fn(usize, &mut Vec<u8>) + Sync,
) -> io::Result<()> {
    let per_group = 2 * rayon::current_num_threads().max(1);
    let groups = blocks.div_ceil(per_group);
    let make = |group: usize, buffers: &mut Vec<Vec<u8>>| {
        let first = group * per_group;
        let count = per_group.min(blocks - first);
        buffers.resize_with(count, Vec::new);
        buffers.par_iter_mut().enumerate().for_each(|(k, buffer)| {
            buffer.clear();
            block(first + k, buffer);
        });
    };
    let (mut ready, mut next) = (Vec::new(), Vec::new());
    if groups > 0 {
        make(0, &mut ready);
    }
    for group in 0..groups {
        let mut written = Ok(());
        rayon::in_place_scope(|s| {
            if group + 1 < groups {
                let (make, next) = (&make, &mut next);
                s.spawn(move |_| make(group + 1, next));
            }
            written = ready.iter().try_for_each(|b| out.write_all(b));
        });
        written?;
        std::mem::swap(&mut ready, &mut next);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    fn fast(x: f64) -> String {
        let mut out = Vec::new();
        push_f64(&mut out, x);
        String::from_utf8(out).expect("ascii")
    }

    fn edges() -> Vec<f64> {
        let mut v = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            2.0,
            10.0,
            100.0,
            12345.0,
            0.5,
            0.1 + 0.2,
            1e-5,
            -1e-5,
            9.999_999_999_999_999e-6,
            1.000_000_000_000_001e-5,
            1e-6,
            1e-7,
            1.5e-7,
            1e15,
            1e16,
            9_999_999_999_999_998.0,
            1e16 - 2.0,
            1e16 + 2.0,
            1e17,
            6.02e23,
            1e300,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            f64::EPSILON,
            5e-324,
            -5e-324,
            2.225_073_858_507_201e-308,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            123.456,
            -238_228_101_817_032.12,
            2f64.powi(50) + 0.25,
            2f64.powi(51) + 0.5,
            1224.2,
            3871.3,
            0.000_123_4,
        ];
        for e in -30..=30 {
            let p = 10f64.powi(e);
            v.extend([p, -p, p * 1.5, p.next_up(), p.next_down()]);
        }
        v
    }

    #[test]
    fn fast_floats_are_display_on_edges_and_random_bits() {
        for x in edges() {
            assert_eq!(fast(x), format!("{x}"), "{x:e}");
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(45);
        for _ in 0..200_000 {
            // Any bit pattern: every exponent, subnormals, NaNs.
            let x = f64::from_bits(rng.r#gen::<u64>());
            assert_eq!(fast(x), format!("{x}"), "{:x}", x.to_bits());
        }
        for _ in 0..200_000 {
            // Coordinates and radii as packings hold them, and whole numbers.
            let x = rng.gen_range(-5000.0..5000.0_f64);
            let whole = x.round();
            let small = rng.gen_range(0.0..1e-4_f64);
            for v in [x, whole, small, x * 1e-3, whole * 1e12] {
                assert_eq!(fast(v), format!("{v}"), "{v:e}");
            }
        }
    }

    #[test]
    fn integers_are_display() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
        for n in [0usize, 1, 9, 10, usize::MAX]
            .into_iter()
            .chain((0..1000).map(|_| rng.r#gen::<usize>() >> rng.gen_range(0..64)))
        {
            let mut out = Vec::new();
            push_int(&mut out, n);
            assert_eq!(out, n.to_string().into_bytes());
        }
    }

    #[test]
    fn rows_come_out_in_order_whatever_the_threads() {
        let row = |i: usize, b: &mut Vec<u8>| {
            push_int(b, i);
            b.push(b'\n');
        };
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool");
            for rows in [0, 1, BLOCK_ROWS, BLOCK_ROWS + 1, 100_003] {
                let mut out = Vec::new();
                pool.install(|| write_rows(&mut out, rows, row))
                    .expect("written");
                let want: String = (0..rows).map(|i| format!("{i}\n")).collect();
                assert_eq!(String::from_utf8(out).expect("ascii"), want);
            }
        }
    }
}
