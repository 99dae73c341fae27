//! The grading curve: sieve-table validation, exact conversion to a number
//! distribution, inverse-CDF sampling, the CDF and the mean disk area.
//!
//! # Model
//! The table is cut into *pieces*, each carrying a positive share of the
//! curve's mass: a *segment* between two different diameters (interpolated
//! in ln d or in d) or an *atom* at a repeated diameter (a step of the CDF).
//! Flat stretches (equal percents) carry nothing and are dropped.
//!
//! Within a segment, write t = ln(d / d_lo) ∈ [0, T] with T = ln(d_hi / d_lo).
//! A particle of diameter d weighs d^k in the curve's basis (k = 0, 2, 3),
//! so the number density is the curve's density divided by d^k. In t that is
//! always proportional to exp(−m t):
//! - Log interpolation: the curve's density in t is constant, so m = k;
//! - Linear interpolation: the curve's density in d is constant, so the
//!   number density in t is ∝ d^(1−k), m = k − 1.
//!
//! Every piece's number weight and its inverse CDF are therefore closed
//! forms (written with `exp_m1`/`ln_1p` and computed in logarithms so that
//! extreme diameter ratios neither overflow nor cancel).

use super::error::GradingError;

/// How percent passing is interpolated between sieve points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Interpolation {
    /// Linear in ln d (a straight line on the semi-log grading chart; default).
    #[default]
    Log,
    /// Linear in d.
    Linear,
}

/// What "percent passing" counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Basis {
    /// Fraction of particle count (the thesis' reading; default).
    #[default]
    Number,
    /// Fraction of 2D solid area (weight d²).
    Mass,
    /// Fraction of 3D sphere mass (weight d³), for true sieve data.
    Mass3d,
}

impl Basis {
    /// The exponent k of the weight d^k one particle carries in this basis.
    pub(crate) fn exponent(self) -> i32 {
        match self {
            Basis::Number => 0,
            Basis::Mass => 2,
            Basis::Mass3d => 3,
        }
    }
}

/// How the number distribution inside one piece is inverted.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Shape {
    /// All of the piece sits at `d_lo` (== `d_hi`).
    Atom,
    /// Number density uniform in d (Linear interpolation, Number basis; m = −1).
    UniformD,
    /// Number density uniform in ln d (Log interpolation, Number basis; m = 0).
    UniformLnD,
    /// Number density ∝ exp(−m t) with m > 0; holds m and exp_m1(−m T).
    Decaying { m: f64, expm1_neg_mt: f64 },
}

/// One piece of the curve with its cumulative values at both ends.
#[derive(Debug, Clone, PartialEq)]
struct Piece {
    shape: Shape,
    /// Diameter where the piece starts (mm).
    d_lo: f64,
    /// Diameter where the piece ends (mm); equals `d_lo` for an atom.
    d_hi: f64,
    /// T = ln(d_hi / d_lo); 0 for an atom.
    ln_ratio: f64,
    /// Curve fraction passing (0..1, the curve's basis) at both ends.
    p_lo: f64,
    p_hi: f64,
    /// Number fraction passing (0..1) at both ends.
    n_lo: f64,
    n_hi: f64,
}

impl Piece {
    fn atom(d: f64, p_lo: f64, p_hi: f64) -> Self {
        Piece {
            shape: Shape::Atom,
            d_lo: d,
            d_hi: d,
            ln_ratio: 0.0,
            p_lo,
            p_hi,
            n_lo: 0.0,
            n_hi: 0.0,
        }
    }

    /// A segment between `d_lo < d_hi`; an atom if the ratio rounds to 1.
    fn segment(d_lo: f64, d_hi: f64, p_lo: f64, p_hi: f64, interp: Interpolation, k: i32) -> Self {
        let ln_ratio = (d_hi / d_lo).ln();
        if ln_ratio <= 0.0 {
            return Piece::atom(d_lo, p_lo, p_hi);
        }
        let m = segment_decay(interp, k);
        let shape = if m < 0.0 {
            Shape::UniformD
        } else if m == 0.0 {
            Shape::UniformLnD
        } else {
            Shape::Decaying {
                m,
                expm1_neg_mt: (-m * ln_ratio).exp_m1(),
            }
        };
        Piece {
            shape,
            d_lo,
            d_hi,
            ln_ratio,
            p_lo,
            p_hi,
            n_lo: 0.0,
            n_hi: 0.0,
        }
    }

    /// ln of the piece's number weight, up to a factor common to all pieces.
    fn ln_number_weight(&self, interp: Interpolation, k: i32) -> f64 {
        let k = f64::from(k);
        let base = (self.p_hi - self.p_lo).ln() - k * self.d_lo.ln();
        let t = self.ln_ratio;
        match (self.shape, interp) {
            (Shape::Atom, _) => base,
            // ∫ (Δp/T) d_lo^-k e^(-k t) dt = Δp d_lo^-k φ(-k T)
            (_, Interpolation::Log) => base + ln_phi(-k * t),
            // ∫ Δp/(d_hi-d_lo) d_lo^(1-k) e^((1-k) t) dt, with d_hi-d_lo = d_lo T φ(T)
            (_, Interpolation::Linear) => base + ln_phi((1.0 - k) * t) - ln_phi(t),
        }
    }

    /// E[d²] of a particle drawn by number from this piece (mm²).
    fn mean_d2(&self, interp: Interpolation, k: i32) -> f64 {
        if self.shape == Shape::Atom {
            return self.d_lo * self.d_lo;
        }
        let m = segment_decay(interp, k);
        let t = self.ln_ratio;
        // E[e^(2t)] under density ∝ e^(-m t) on [0, T] = φ((2-m)T) / φ(-m T)
        let mean = (2.0 * self.d_lo.ln() + ln_phi((2.0 - m) * t) - ln_phi(-m * t)).exp();
        mean.clamp(self.d_lo * self.d_lo, self.d_hi * self.d_hi)
    }

    /// The curve's fraction passing at `d`, for `d_lo <= d <= d_hi`.
    fn interpolate(&self, d: f64, interp: Interpolation) -> f64 {
        if self.shape == Shape::Atom {
            return self.p_hi;
        }
        let frac = match interp {
            Interpolation::Log => (d / self.d_lo).ln() / self.ln_ratio,
            Interpolation::Linear => (d - self.d_lo) / (self.d_hi - self.d_lo),
        };
        self.p_lo + (self.p_hi - self.p_lo) * frac.clamp(0.0, 1.0)
    }

    /// The diameter at number fraction `u` (`n_lo <= u <= n_hi`).
    fn invert(&self, u: f64) -> f64 {
        let width = self.n_hi - self.n_lo;
        let f = if width > 0.0 {
            ((u - self.n_lo) / width).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = match self.shape {
            Shape::Atom => return self.d_lo,
            Shape::UniformD => self.d_lo + f * (self.d_hi - self.d_lo),
            Shape::UniformLnD => self.d_lo * (f * self.ln_ratio).exp(),
            // (1 - e^(-m t)) = f (1 - e^(-m T))  ⇒  t = -ln_1p(f·exp_m1(-m T)) / m
            Shape::Decaying { m, expm1_neg_mt } => {
                self.d_lo * (-(f * expm1_neg_mt).ln_1p() / m).exp()
            }
        };
        d.clamp(self.d_lo, self.d_hi)
    }
}

/// The decay rate m of the number density in t = ln(d / d_lo) (module docs).
fn segment_decay(interp: Interpolation, k: i32) -> f64 {
    match interp {
        Interpolation::Log => f64::from(k),
        Interpolation::Linear => f64::from(k - 1),
    }
}

/// ln φ(y) with φ(y) = (e^y − 1) / y, φ(0) = 1; stable for every finite y.
fn ln_phi(y: f64) -> f64 {
    if y == 0.0 {
        0.0
    } else if y > 0.0 {
        y + (-(-y).exp_m1() / y).ln()
    } else {
        (y.exp_m1() / y).ln()
    }
}

/// Fills `n_lo`/`n_hi` of `pieces` (curve in a mass basis, weight d^k) and
/// returns E[d²] by number (mm²).
///
/// The weights are normalised in logarithms so that none overflows.
fn number_cumulative(pieces: &mut [Piece], interpolation: Interpolation, k: i32) -> f64 {
    let ln_weights: Vec<f64> = pieces
        .iter()
        .map(|p| p.ln_number_weight(interpolation, k))
        .collect();
    let ln_max = ln_weights.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let weights: Vec<f64> = ln_weights.iter().map(|w| (w - ln_max).exp()).collect();
    let total: f64 = weights.iter().sum();
    let mut cumulative = 0.0;
    let mut mean_d2 = 0.0;
    for (piece, w) in pieces.iter_mut().zip(&weights) {
        piece.n_lo = cumulative / total;
        cumulative += w;
        piece.n_hi = cumulative / total;
        mean_d2 += w / total * piece.mean_d2(interpolation, k);
    }
    if let Some(last) = pieces.last_mut() {
        last.n_hi = 1.0;
    }
    mean_d2
}

/// Checks a sieve table against the rules of [`Grading::from_table`].
fn validate(points: &[(f64, f64)]) -> Result<(), GradingError> {
    let [(d_first, p_first), .., (d_last, p_last)] = *points else {
        return Err(GradingError::TooFewPoints {
            count: points.len(),
        });
    };
    let mut previous: Option<(f64, f64)> = None;
    for (i, &(d, p)) in points.iter().enumerate() {
        let row = i + 1;
        if !(d.is_finite() && d > 0.0) {
            return Err(GradingError::InvalidDiameter { row, diameter: d });
        }
        if !(p.is_finite() && (0.0..=100.0).contains(&p)) {
            return Err(GradingError::InvalidPercent { row, percent: p });
        }
        if let Some((d_prev, p_prev)) = previous {
            if d < d_prev {
                return Err(GradingError::DiameterDecreases {
                    row,
                    from: d_prev,
                    to: d,
                });
            }
            if p < p_prev {
                return Err(GradingError::PercentDecreases {
                    row,
                    diameter: d,
                    from: p_prev,
                    to: p,
                });
            }
        }
        previous = Some((d, p));
    }
    if p_first != 0.0 {
        return Err(GradingError::FirstPercentNotZero {
            diameter: d_first,
            percent: p_first,
        });
    }
    if p_last != 100.0 {
        return Err(GradingError::LastPercentNotHundred {
            row: points.len(),
            diameter: d_last,
            percent: p_last,
        });
    }
    Ok(())
}

/// A grading curve: a cumulative distribution of disk diameters (mm).
///
/// Built from a sieve table ([`Grading::from_table`]) or a shorthand
/// ([`Grading::uniform`], [`Grading::constant`], [`Grading::preset`]); once
/// built it is valid, and none of its methods panics on any input.
///
/// # Example
/// ```
/// use gapack::{Basis, Grading, Interpolation};
/// // Thesis Table 4.1: 10 % between 1.2 and 2.4 mm, 80 % exactly 2.4, 10 % up to 6.0.
/// let g = Grading::from_table(
///     &[(1.2, 0.0), (2.4, 10.0), (2.4, 90.0), (6.0, 100.0)],
///     Interpolation::Log,
///     Basis::Number,
/// )?;
/// assert_eq!(g.sample(0.5), 2.4);
/// assert!((g.cdf(2.4) - 0.9).abs() < 1e-12);
/// assert_eq!((g.d_min(), g.d_max()), (1.2, 6.0));
/// # Ok::<(), gapack::GradingError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Grading {
    basis: Basis,
    interpolation: Interpolation,
    /// Pieces with positive mass, in increasing diameter; never empty, the
    /// last one has `n_hi == 1` and `p_hi == 1`.
    pieces: Vec<Piece>,
    /// Mean disk area by number (mm²), computed once.
    mean_disk_area: f64,
}

impl Grading {
    /// From a sieve table of `(diameter_mm, percent_passing)`.
    ///
    /// # Behavior
    /// At least 2 points; diameters positive, finite, non-decreasing;
    /// percents in [0, 100], non-decreasing, the first 0 and the last 100.
    /// A repeated diameter is a step (an atom of the distribution); equal
    /// percents at different diameters are a gap with no particles.
    /// `interpolation` applies between points; `basis` says what the percent
    /// counts.
    ///
    /// # Errors
    /// The first rule broken, scanning rows in order, as a [`GradingError`]
    /// naming the 1-based row.
    pub fn from_table(
        points: &[(f64, f64)],
        interpolation: Interpolation,
        basis: Basis,
    ) -> Result<Self, GradingError> {
        validate(points)?;
        let k = basis.exponent();
        let mut pieces: Vec<Piece> = Vec::new();
        for (&(d0, p0), &(d1, p1)) in points.iter().zip(points.iter().skip(1)) {
            let (lo, hi) = (p0 / 100.0, p1 / 100.0);
            if hi <= lo {
                continue;
            }
            if d1 > d0 {
                pieces.push(Piece::segment(d0, d1, lo, hi, interpolation, k));
                continue;
            }
            match pieces.last_mut() {
                Some(last) if last.shape == Shape::Atom && last.d_lo == d0 => last.p_hi = hi,
                _ => pieces.push(Piece::atom(d0, lo, hi)),
            }
        }
        let mean_d2 = if k == 0 {
            // By number the table is the number CDF: keep its values exactly.
            let mut mean_d2 = 0.0;
            for piece in &mut pieces {
                (piece.n_lo, piece.n_hi) = (piece.p_lo, piece.p_hi);
                mean_d2 += (piece.p_hi - piece.p_lo) * piece.mean_d2(interpolation, k);
            }
            mean_d2
        } else {
            number_cumulative(&mut pieces, interpolation, k)
        };
        Ok(Grading {
            basis,
            interpolation,
            pieces,
            mean_disk_area: std::f64::consts::FRAC_PI_4 * mean_d2,
        })
    }

    /// The basis the curve is expressed in.
    pub fn basis(&self) -> Basis {
        self.basis
    }

    /// How the curve interpolates between its sieve points.
    pub fn interpolation(&self) -> Interpolation {
        self.interpolation
    }

    /// Smallest diameter with non-zero probability (mm): where the curve
    /// starts to rise, not a leading flat row of the table.
    pub fn d_min(&self) -> f64 {
        self.pieces.first().map_or(f64::NAN, |p| p.d_lo)
    }

    /// Largest diameter with non-zero probability (mm): where the curve
    /// reaches 100 %, not a trailing flat row of the table.
    pub fn d_max(&self) -> f64 {
        self.pieces.last().map_or(f64::NAN, |p| p.d_hi)
    }

    /// Mean disk area by number (mm²): the expected area π d²/4 of one
    /// drawn disk, exact (closed form per piece), whatever the basis.
    ///
    /// Useful to estimate how many disks fill a domain.
    pub fn mean_disk_area(&self) -> f64 {
        self.mean_disk_area
    }

    /// Inverse CDF by number: the diameter drawn for a gene `u` in [0, 1].
    ///
    /// # Behavior
    /// Returns the diameter of a particle drawn from the number distribution
    /// that reproduces the curve in its basis (for [`Basis::Number`] the plain
    /// inverse of the table). Exact closed form per piece, non-decreasing in
    /// `u`; `u` outside [0, 1] is clamped, NaN is read as 0.5. `u` anywhere in
    /// an atom's range, its ends included, returns the atom's diameter.
    ///
    /// # Performance
    /// A binary search over the pieces and one `exp`/`ln_1p`; no allocation.
    pub fn sample(&self, u: f64) -> f64 {
        let u = if u.is_nan() { 0.5 } else { u.clamp(0.0, 1.0) };
        let mut i = self.pieces.partition_point(|p| p.n_hi < u);
        // At a boundary shared with a following atom, the atom wins.
        if let (Some(here), Some(next)) = (self.pieces.get(i), self.pieces.get(i + 1))
            && here.shape != Shape::Atom
            && next.shape == Shape::Atom
            && next.n_lo <= u
        {
            i += 1;
        }
        self.pieces
            .get(i)
            .or(self.pieces.last())
            .map_or(f64::NAN, |p| p.invert(u))
    }

    /// The curve's CDF (fraction passing, 0..1) at `d`, in the curve's basis.
    ///
    /// Right-continuous: at an atom it includes the atom. 0 below
    /// [`Grading::d_min`], 1 from [`Grading::d_max`] on; NaN for NaN.
    pub fn cdf(&self, d: f64) -> f64 {
        if d.is_nan() {
            return f64::NAN;
        }
        let i = self.pieces.partition_point(|p| p.d_lo <= d);
        match i.checked_sub(1).and_then(|j| self.pieces.get(j)) {
            None => 0.0,
            Some(p) if d >= p.d_hi => p.p_hi,
            Some(p) => p.interpolate(d, self.interpolation),
        }
    }

    /// [`Grading::cdf_left`] and [`Grading::cdf`] at `d`, bit for bit,
    /// the curve interpolated once where they agree: everywhere but at a
    /// piece's ends (the KS sweep asks both at every distinct size).
    pub(super) fn cdf_limits(&self, d: f64) -> (f64, f64) {
        let i = self.pieces.partition_point(|p| p.d_lo <= d);
        let piece = i.checked_sub(1).and_then(|j| self.pieces.get(j));
        // The left limit looks for `d_lo < d` and `d > d_hi`: it differs
        // only where `d` is the found piece's end (the pieces are sorted,
        // so no other piece starts at `d`).
        match piece {
            Some(p) if p.d_lo == d || p.d_hi == d => (self.cdf_left(d), self.cdf(d)),
            _ => {
                let value = self.cdf(d);
                (value, value)
            }
        }
    }

    /// The left limit of the CDF at `d`: the fraction strictly finer than `d`.
    pub(super) fn cdf_left(&self, d: f64) -> f64 {
        if d.is_nan() {
            return f64::NAN;
        }
        let i = self.pieces.partition_point(|p| p.d_lo < d);
        match i.checked_sub(1).and_then(|j| self.pieces.get(j)) {
            None => 0.0,
            Some(p) if d > p.d_hi => p.p_hi,
            Some(p) => p.interpolate(d, self.interpolation),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_tables::{TABLE_3_1, TABLE_3_4, TABLE_4_1, even_sample, random_sample};
    use super::*;

    fn all_gradings() -> Vec<Grading> {
        let mut out = Vec::new();
        for table in [TABLE_3_1, TABLE_3_4, TABLE_4_1] {
            for interp in [Interpolation::Log, Interpolation::Linear] {
                for basis in [Basis::Number, Basis::Mass, Basis::Mass3d] {
                    out.push(Grading::from_table(table, interp, basis).expect("valid table"));
                }
            }
        }
        out
    }

    fn err(points: &[(f64, f64)]) -> GradingError {
        Grading::from_table(points, Interpolation::Log, Basis::Number)
            .expect_err("table must be rejected")
    }

    #[test]
    fn too_few_points_rejected() {
        assert_eq!(err(&[]), GradingError::TooFewPoints { count: 0 });
        assert_eq!(err(&[(1.0, 0.0)]), GradingError::TooFewPoints { count: 1 });
    }

    #[test]
    fn invalid_diameters_rejected() {
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let e = err(&[(1.0, 0.0), (bad, 50.0), (2.0, 100.0)]);
            assert!(
                matches!(e, GradingError::InvalidDiameter { row: 2, .. }),
                "{bad}: {e:?}"
            );
        }
    }

    #[test]
    fn decreasing_diameter_rejected() {
        let e = err(&[(1.0, 0.0), (2.0, 50.0), (1.5, 100.0)]);
        assert_eq!(
            e,
            GradingError::DiameterDecreases {
                row: 3,
                from: 2.0,
                to: 1.5
            }
        );
        assert_eq!(
            e.to_string(),
            "grading table: diameter decreases from 2 to 1.5 mm at row 3; \
             list sieve sizes from smallest to largest"
        );
    }

    #[test]
    fn invalid_percents_rejected() {
        for bad in [-0.5, 100.5, f64::NAN, f64::INFINITY] {
            let e = err(&[(1.0, 0.0), (1.5, bad), (2.0, 100.0)]);
            assert!(
                matches!(e, GradingError::InvalidPercent { row: 2, .. }),
                "{bad}: {e:?}"
            );
        }
    }

    #[test]
    fn decreasing_percent_rejected_with_readable_message() {
        let mut table = TABLE_3_4.to_vec();
        table[5].1 = 31.0; // row 6 (d = 1.255) now below row 5's 43
        let e = err(&table);
        assert_eq!(
            e,
            GradingError::PercentDecreases {
                row: 6,
                diameter: 1.255,
                from: 43.0,
                to: 31.0
            }
        );
        assert_eq!(
            e.to_string(),
            "grading table: percent passing decreases from 43 to 31 at row 6 (d = 1.255 mm)"
        );
    }

    #[test]
    fn first_must_be_zero_and_last_hundred() {
        assert_eq!(
            err(&[(1.0, 5.0), (2.0, 100.0)]),
            GradingError::FirstPercentNotZero {
                diameter: 1.0,
                percent: 5.0
            }
        );
        let e = err(&[(1.0, 0.0), (2.0, 50.0), (3.0, 99.0)]);
        assert_eq!(
            e,
            GradingError::LastPercentNotHundred {
                row: 3,
                diameter: 3.0,
                percent: 99.0
            }
        );
        assert!(e.to_string().contains("must have 100 % passing, got 99"));
    }

    #[test]
    fn all_thesis_tables_valid_in_every_mode() {
        assert_eq!(all_gradings().len(), 18);
    }

    #[test]
    fn table_3_4_even_sample_matches_curve() {
        let g = Grading::from_table(TABLE_3_4, Interpolation::Log, Basis::Number).expect("valid");
        let ks = g.ks_distance(&even_sample(&g, 20_000));
        assert!(ks < 0.001, "KS = {ks}");
        // the exact inverse puts every sieve point where the table says
        for &(d, p) in TABLE_3_4 {
            assert!((g.cdf(d) - p / 100.0).abs() < 1e-12, "cdf({d})");
        }
    }

    #[test]
    fn table_3_4_random_sample_matches_curve() {
        let g = Grading::from_table(TABLE_3_4, Interpolation::Log, Basis::Number).expect("valid");
        let ks = g.ks_distance(&random_sample(&g, 20_000, 34));
        assert!(ks < 0.02, "KS = {ks}");
    }

    #[test]
    fn number_log_sample_is_devroye_formula() {
        // 100u = 37 falls between (1.235, 31) and (1.245, 43)
        let g = Grading::from_table(TABLE_3_4, Interpolation::Log, Basis::Number).expect("valid");
        let expected =
            (1.235f64.ln() + (37.0 - 31.0) / (43.0 - 31.0) * (1.245f64.ln() - 1.235f64.ln())).exp();
        assert!((g.sample(0.37) - expected).abs() < 1e-12);
        for i in 0..=1000 {
            let u = f64::from(i) / 1000.0;
            assert!((g.cdf(g.sample(u)) - u).abs() < 1e-12, "u = {u}");
        }
    }

    #[test]
    fn table_4_1_step_holds_eighty_percent() {
        let g = Grading::from_table(TABLE_4_1, Interpolation::Log, Basis::Number).expect("valid");
        let n = 100_000;
        let draws = random_sample(&g, n, 41);
        let at_step = draws.iter().filter(|&&d| d == 2.4).count() as f64 / n as f64;
        assert!((at_step - 0.80).abs() < 0.01, "fraction at 2.4 = {at_step}");
        assert!(g.ks_distance(&draws) < 0.02);
        // the atom's whole range, ends included, returns the atom
        assert_eq!(g.sample(0.1), 2.4);
        assert_eq!(g.sample(0.9), 2.4);
        assert!(g.sample(0.0999) < 2.4 && g.sample(0.9001) > 2.4);
        // right-continuous CDF with a jump of 0.8
        assert!((g.cdf(2.4) - 0.9).abs() < 1e-12);
        assert!((g.cdf(2.4 - 1e-9) - 0.1).abs() < 1e-6);
        assert!((g.cdf_left(2.4) - 0.1).abs() < 1e-12);
    }

    #[test]
    fn repeated_step_rows_merge_into_one_atom() {
        let split = [
            (1.2, 0.0),
            (2.4, 10.0),
            (2.4, 50.0),
            (2.4, 90.0),
            (6.0, 100.0),
        ];
        let a = Grading::from_table(&split, Interpolation::Log, Basis::Mass).expect("valid");
        let b = Grading::from_table(TABLE_4_1, Interpolation::Log, Basis::Mass).expect("valid");
        assert_eq!(a, b);
    }

    #[test]
    fn step_at_gap_boundary_returns_atom() {
        // 50 % between 1 and 2 mm, nothing between 2 and 3, 50 % exactly 3
        let g = Grading::from_table(
            &[(1.0, 0.0), (2.0, 50.0), (3.0, 50.0), (3.0, 100.0)],
            Interpolation::Linear,
            Basis::Number,
        )
        .expect("valid");
        assert_eq!(g.sample(0.5), 3.0);
        assert!((g.sample(0.4999999) - 2.0).abs() < 1e-5);
        assert_eq!(g.cdf(2.5), 0.5);
        assert_eq!((g.d_min(), g.d_max()), (1.0, 3.0));
    }

    #[test]
    fn flat_ends_do_not_count_for_d_min_d_max() {
        let g = Grading::from_table(
            &[(0.5, 0.0), (1.0, 0.0), (2.0, 100.0), (4.0, 100.0)],
            Interpolation::Log,
            Basis::Number,
        )
        .expect("valid");
        assert_eq!((g.d_min(), g.d_max()), (1.0, 2.0));
        assert_eq!(g.sample(0.0), 1.0);
        assert_eq!(g.sample(1.0), 2.0);
    }

    #[test]
    fn cdf_is_monotone_and_spans_zero_to_one() {
        for g in all_gradings() {
            let (lo, hi) = (g.d_min(), g.d_max());
            assert_eq!(g.cdf(lo * 0.999), 0.0);
            assert_eq!(g.cdf(0.0), 0.0);
            assert_eq!(g.cdf(-1.0), 0.0);
            assert_eq!(g.cdf(hi), 1.0);
            assert_eq!(g.cdf(hi * 10.0), 1.0);
            assert_eq!(g.cdf(f64::INFINITY), 1.0);
            assert!(g.cdf(f64::NAN).is_nan());
            let mut prev = 0.0;
            for i in 0..=10_000 {
                let d = lo * 0.9 + (hi * 1.1 - lo * 0.9) * f64::from(i) / 10_000.0;
                let c = g.cdf(d);
                assert!((0.0..=1.0).contains(&c));
                assert!(c >= prev, "{g:?}: cdf decreases at {d}");
                assert!(g.cdf_left(d) <= c);
                prev = c;
            }
        }
    }

    #[test]
    fn cdf_limits_are_the_two_limits_bit_for_bit() {
        let gap = Grading::from_table(
            &[(1.0, 0.0), (2.0, 50.0), (3.0, 50.0), (3.0, 100.0)],
            Interpolation::Linear,
            Basis::Number,
        )
        .expect("valid");
        for g in all_gradings().into_iter().chain([gap]) {
            let (lo, hi) = (g.d_min(), g.d_max());
            // A grid, and every piece's ends and their neighbours: the
            // table's points and steps, where the two limits part.
            let mut ds: Vec<f64> = (0..=2_000)
                .map(|i| lo * 0.9 + (hi * 1.1 - lo * 0.9) * f64::from(i) / 2_000.0)
                .collect();
            for p in &g.pieces {
                for d in [p.d_lo, p.d_hi] {
                    ds.extend([d.next_down(), d, d.next_up()]);
                }
            }
            let mut parted = 0;
            for d in ds {
                let (left, at) = g.cdf_limits(d);
                assert_eq!(left.to_bits(), g.cdf_left(d).to_bits(), "{g:?} at {d}");
                assert_eq!(at.to_bits(), g.cdf(d).to_bits(), "{g:?} at {d}");
                parted += usize::from(left != at);
            }
            // A curve with a step parts its limits there.
            let steps = g.pieces.iter().any(|p| p.shape == Shape::Atom);
            assert!(!steps || parted > 0, "{g:?}");
        }
    }

    #[test]
    fn sample_is_monotone_and_within_range() {
        for g in all_gradings() {
            let mut prev = g.sample(0.0);
            assert_eq!(prev, g.d_min());
            assert_eq!(g.sample(1.0), g.d_max());
            for i in 1..=100_000 {
                let d = g.sample(f64::from(i) / 100_000.0);
                assert!(d >= prev, "{g:?}: sample decreases at i = {i}");
                prev = d;
            }
        }
    }

    #[test]
    fn sample_never_panics_on_odd_u() {
        let g = Grading::from_table(TABLE_4_1, Interpolation::Linear, Basis::Mass3d).expect("ok");
        assert_eq!(g.sample(-3.0), g.d_min());
        assert_eq!(g.sample(f64::NEG_INFINITY), g.d_min());
        assert_eq!(g.sample(7.0), g.d_max());
        assert_eq!(g.sample(f64::INFINITY), g.d_max());
        assert_eq!(g.sample(f64::NAN), g.sample(0.5));
    }

    #[test]
    fn log_and_linear_medians_differ_as_expected() {
        let table = [(1.0, 0.0), (4.0, 100.0)];
        let log = Grading::from_table(&table, Interpolation::Log, Basis::Number).expect("ok");
        let lin = Grading::from_table(&table, Interpolation::Linear, Basis::Number).expect("ok");
        // geometric vs arithmetic mid-point
        assert!((log.sample(0.5) - 2.0).abs() < 1e-12);
        assert!((lin.sample(0.5) - 2.5).abs() < 1e-12);
        assert!((log.cdf(2.0) - 0.5).abs() < 1e-12);
        assert!((lin.cdf(2.5) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn mass_basis_sampling_matches_closed_form() {
        // Linear in d by area between a and b: number density ∝ 1/d², so the
        // number CDF is (1/a − 1/d)/(1/a − 1/b).
        let (a, b) = (1.0, 3.0);
        let g = Grading::from_table(&[(a, 0.0), (b, 100.0)], Interpolation::Linear, Basis::Mass)
            .expect("ok");
        // Log in d by 3D mass: number density in ln d ∝ d^-3, CDF (a^-3 − d^-3)/(a^-3 − b^-3).
        let g3 = Grading::from_table(&[(a, 0.0), (b, 100.0)], Interpolation::Log, Basis::Mass3d)
            .expect("ok");
        for i in 0..=100 {
            let u = f64::from(i) / 100.0;
            let d = 1.0 / (1.0 / a - u * (1.0 / a - 1.0 / b));
            assert!((g.sample(u) - d).abs() < 1e-12 * d, "u = {u}");
            let d3 = (a.powi(-3) - u * (a.powi(-3) - b.powi(-3))).powf(-1.0 / 3.0);
            assert!((g3.sample(u) - d3).abs() < 1e-12 * d3, "u = {u}");
        }
    }

    #[test]
    fn mass_atom_converts_to_number_atom() {
        // Table 4.1 by area: the atom's number share is (0.8/2.4²) / Σ
        let g = Grading::from_table(TABLE_4_1, Interpolation::Log, Basis::Mass).expect("ok");
        let w = |p: &Piece| p.n_hi - p.n_lo;
        let [below, atom, above] = g.pieces.as_slice() else {
            panic!("three pieces expected: {:?}", g.pieces)
        };
        // closed forms: 0.1 · d^-2 φ(-2T) for the log segments
        let seg = |lo: f64, hi: f64| {
            let t = f64::ln(hi / lo);
            0.1 * lo.powi(-2) * (1.0 - (-2.0 * t).exp()) / (2.0 * t)
        };
        let (wb, wa, wu) = (seg(1.2, 2.4), 0.8 / 2.4f64.powi(2), seg(2.4, 6.0));
        let total = wb + wa + wu;
        assert!((w(below) - wb / total).abs() < 1e-12);
        assert!((w(atom) - wa / total).abs() < 1e-12);
        assert!((w(above) - wu / total).abs() < 1e-12);
    }

    #[test]
    fn linear_mass_segments_convert_by_closed_form() {
        // Mass uniform in d on [a, b]: number weight Δp/(b−a)·(a^(1−k) − b^(1−k))/(k−1),
        // number CDF inside ∝ a^(1−k) − d^(1−k). Segments of different ratios.
        let table = [(1.0, 0.0), (2.0, 50.0), (3.0, 100.0)];
        for (basis, k) in [(Basis::Mass, 2), (Basis::Mass3d, 3)] {
            let g = Grading::from_table(&table, Interpolation::Linear, basis).expect("ok");
            let e = f64::from(1 - k);
            let weight = |a: f64, b: f64| 0.5 / (b - a) * (a.powf(e) - b.powf(e)) / -e;
            let share = weight(1.0, 2.0) / (weight(1.0, 2.0) + weight(2.0, 3.0));
            assert!((g.pieces[0].n_hi - share).abs() < 1e-12, "{basis:?}");
            for f in [0.1, 0.5, 0.9] {
                let d = (1.0 - f * (1.0 - 2f64.powf(e))).powf(1.0 / e);
                assert!((g.sample(f * share) - d).abs() < 1e-12, "{basis:?} f = {f}");
                let d = (2f64.powf(e) - f * (2f64.powf(e) - 3f64.powf(e))).powf(1.0 / e);
                let u = share + f * (1.0 - share);
                assert!((g.sample(u) - d).abs() < 1e-12, "{basis:?} f = {f}");
            }
        }
    }

    #[test]
    fn mass_and_mass3d_samples_fit_their_basis_only() {
        for basis in [Basis::Mass, Basis::Mass3d] {
            for interp in [Interpolation::Log, Interpolation::Linear] {
                for table in [TABLE_3_1, TABLE_4_1] {
                    let g = Grading::from_table(table, interp, basis).expect("ok");
                    let by_number = Grading::from_table(table, interp, Basis::Number).expect("ok");
                    let draws = random_sample(&g, 50_000, 7);
                    let ks = g.ks_distance(&draws);
                    let ks_number = by_number.ks_distance(&draws);
                    // and number draws do not fit the mass curve
                    let ks_swapped = g.ks_distance(&random_sample(&by_number, 50_000, 8));
                    assert!(ks < 0.02, "{basis:?} {interp:?}: KS in own basis = {ks}");
                    assert!(
                        ks_number > 0.08,
                        "{basis:?} {interp:?}: vs number: {ks_number}"
                    );
                    assert!(
                        ks_swapped > 0.08,
                        "{basis:?} {interp:?}: swapped: {ks_swapped}"
                    );
                }
            }
        }
    }

    #[test]
    fn mean_disk_area_exact_cases() {
        let area = |d: f64| std::f64::consts::FRAC_PI_4 * d * d;
        let c = Grading::from_table(&[(1.3, 0.0), (1.3, 100.0)], Interpolation::Log, Basis::Mass)
            .expect("ok");
        assert!((c.mean_disk_area() - area(1.3)).abs() < 1e-12);
        // uniform in d by number: E[d²] = (a² + ab + b²)/3
        let (a, b) = (1.2, 2.4);
        let u = Grading::from_table(
            &[(a, 0.0), (b, 100.0)],
            Interpolation::Linear,
            Basis::Number,
        )
        .expect("ok");
        let exact = std::f64::consts::FRAC_PI_4 * (a * a + a * b + b * b) / 3.0;
        assert!((u.mean_disk_area() / exact - 1.0).abs() < 1e-12);
        // uniform in ln d by number: E[d²] = (b² − a²) / (2 ln(b/a))
        let l = Grading::from_table(&[(a, 0.0), (b, 100.0)], Interpolation::Log, Basis::Number)
            .expect("ok");
        let exact = std::f64::consts::FRAC_PI_4 * (b * b - a * a) / (2.0 * (b / a).ln());
        assert!((l.mean_disk_area() / exact - 1.0).abs() < 1e-12);
        // linear by area: number ∝ 1/d², E[d²] = (b − a)/(1/a − 1/b) = ab
        let m = Grading::from_table(&[(a, 0.0), (b, 100.0)], Interpolation::Linear, Basis::Mass)
            .expect("ok");
        assert!((m.mean_disk_area() / area((a * b).sqrt()) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn mean_disk_area_matches_quadrature_and_monte_carlo() {
        for g in all_gradings() {
            let area = |d: f64| std::f64::consts::FRAC_PI_4 * d * d;
            let n = 400_000;
            let quad = even_sample(&g, n).iter().map(|&d| area(d)).sum::<f64>() / n as f64;
            let rel = (g.mean_disk_area() / quad - 1.0).abs();
            assert!(rel < 1e-5, "{g:?}: quadrature rel err {rel}");
            let n = 400_000;
            let mc = random_sample(&g, n, 99)
                .iter()
                .map(|&d| area(d))
                .sum::<f64>()
                / n as f64;
            let rel = (g.mean_disk_area() / mc - 1.0).abs();
            assert!(rel < 0.005, "{g:?}: Monte Carlo rel err {rel}");
        }
    }

    #[test]
    fn extreme_diameter_ratio_stays_finite() {
        for basis in [Basis::Number, Basis::Mass, Basis::Mass3d] {
            for interp in [Interpolation::Log, Interpolation::Linear] {
                let g = Grading::from_table(&[(1e-150, 0.0), (1e150, 100.0)], interp, basis)
                    .expect("ok");
                let mut prev = 0.0;
                for i in 0..=100 {
                    let d = g.sample(f64::from(i) / 100.0);
                    assert!(
                        d.is_finite() && d >= prev && d > 0.0,
                        "{basis:?} {interp:?}"
                    );
                    prev = d;
                }
                assert!(g.mean_disk_area().is_finite());
            }
        }
    }

    #[test]
    fn ln_phi_is_accurate() {
        for y in [-700.0, -30.0, -1.0, -1e-9, 0.0, 1e-9, 1.0, 30.0, 700.0] {
            let expected = if y == 0.0 {
                0.0
            } else {
                (f64::exp_m1(y) / y).ln()
            };
            assert!(
                (ln_phi(y) - expected).abs() < 1e-12 * expected.abs().max(1.0),
                "{y}"
            );
        }
        assert!(ln_phi(5000.0).is_finite());
    }
}
