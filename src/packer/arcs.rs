//! Arcs of a circle: the ones obstacles block, then the free ones between.
//!
//! Two angle measures: radians, to sample a point uniformly by arc length,
//! and a pseudo-angle, monotone in the angle but free of trigonometry, which
//! is enough to tell whether any arc is free (a bisection asks that many
//! times).

use std::f64::consts::TAU;

/// How angles are measured around the circle, counter-clockwise from +x.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Measure {
    /// Radians in [0, 2π).
    Radians,
    /// A pseudo-angle in [0, 4): `y / (|x| + |y|)` unfolded by quadrant.
    Pseudo,
}

impl Measure {
    /// A full turn.
    pub fn full(self) -> f64 {
        match self {
            Measure::Radians => TAU,
            Measure::Pseudo => 4.0,
        }
    }

    /// The measure of direction (`x`, `y`), which need not be a unit vector.
    pub fn of(self, x: f64, y: f64) -> f64 {
        match self {
            Measure::Radians => y.atan2(x).rem_euclid(TAU),
            Measure::Pseudo => {
                let sum = x.abs() + y.abs();
                let p = if sum > 0.0 { y / sum } else { 0.0 };
                if x < 0.0 {
                    2.0 - p
                } else if y < 0.0 {
                    4.0 + p
                } else {
                    p
                }
            }
        }
    }

    /// A direction (not a unit vector for the pseudo-angle) of measure `a`.
    pub fn direction(self, a: f64) -> (f64, f64) {
        match self {
            Measure::Radians => (a.cos(), a.sin()),
            Measure::Pseudo => {
                let a = a.rem_euclid(4.0);
                if a < 1.0 {
                    (1.0 - a, a)
                } else if a < 3.0 {
                    let p = 2.0 - a;
                    (p.abs() - 1.0, p)
                } else {
                    let p = a - 4.0;
                    (1.0 + p, p)
                }
            }
        }
    }
}

/// The blocked arcs of one circle, then (after [`Arcs::free`]) its free arcs.
#[derive(Debug, Clone)]
pub(super) struct Arcs {
    measure: Measure,
    list: Vec<(f64, f64)>,
}

impl Arcs {
    /// No arcs, in `measure`.
    pub fn new(measure: Measure) -> Self {
        Arcs {
            measure,
            list: Vec::new(),
        }
    }

    /// Start again, in `measure`.
    pub fn clear(&mut self, measure: Measure) {
        self.measure = measure;
        self.list.clear();
    }

    /// The measure in use.
    pub fn measure(&self) -> Measure {
        self.measure
    }

    /// Block the arc from direction `from` counter-clockwise to direction `to`.
    pub fn block(&mut self, from: (f64, f64), to: (f64, f64)) {
        let (a, b) = (self.measure.of(from.0, from.1), self.measure.of(to.0, to.1));
        if b >= a {
            self.list.push((a, b));
        } else {
            self.list.push((a, self.measure.full()));
            self.list.push((0.0, b));
        }
    }

    /// Block the arc of measures `lo` to `hi` (`lo` in [0, full), `hi` ≥ `lo`,
    /// less than a full turn further).
    pub fn block_range(&mut self, lo: f64, hi: f64) {
        let full = self.measure.full();
        if hi > full {
            self.list.push((lo, full));
            self.list.push((0.0, hi - full));
        } else {
            self.list.push((lo, hi));
        }
    }

    /// Turn the blocked arcs into the free ones, in place; returns their total measure.
    pub fn free(&mut self) -> f64 {
        self.list.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let mut free = Vec::with_capacity(self.list.len() + 1);
        let mut cursor = 0.0;
        for &(lo, hi) in &self.list {
            if lo > cursor {
                free.push((cursor, lo));
            }
            cursor = f64::max(cursor, hi);
        }
        let full = self.measure.full();
        if cursor < full {
            free.push((cursor, full));
        }
        self.list = free;
        self.list.iter().map(|(lo, hi)| hi - lo).sum()
    }

    /// The measure at length `s` along the free arcs.
    pub fn point(&self, mut s: f64) -> f64 {
        for &(lo, hi) in &self.list {
            if s <= hi - lo {
                return lo + s;
            }
            s -= hi - lo;
        }
        self.list.last().map_or(0.0, |&(_, hi)| hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pseudo_angle_is_monotone_and_inverts() {
        let mut last = -1.0;
        for k in 0..720 {
            let t = k as f64 * TAU / 720.0;
            let p = Measure::Pseudo.of(t.cos(), t.sin());
            assert!(p > last || k == 0, "not monotone at {t}");
            last = p;
            let (x, y) = Measure::Pseudo.direction(p);
            let back = y.atan2(x).rem_euclid(TAU);
            assert!(
                (back - t).abs() < 1e-9 || (back - t).abs() > TAU - 1e-9,
                "{t} -> {back}"
            );
        }
    }

    #[test]
    fn free_arcs_complement_the_blocked_ones_in_both_measures() {
        for m in [Measure::Radians, Measure::Pseudo] {
            let mut arcs = Arcs::new(m);
            let dir = |t: f64| (t.cos(), t.sin());
            arcs.block(dir(-0.5), dir(0.5));
            arcs.block(dir(1.0), dir(2.0));
            arcs.block(dir(1.5), dir(2.5));
            let free = arcs.free();
            // Free: (0.5, 1.0) and (2.5, 2π − 0.5).
            let m_of = |t: f64| m.of(t.cos(), t.sin());
            let want = (m_of(1.0) - m_of(0.5)) + (m_of(TAU - 0.5) - m_of(2.5));
            assert!((free - want).abs() < 1e-12, "{m:?}: {free} vs {want}");
            assert_eq!(arcs.list.len(), 2);
        }
        let mut arcs = Arcs::new(Measure::Radians);
        arcs.block_range(0.0, 1.0);
        arcs.block_range(3.0, TAU + 0.5);
        arcs.free();
        assert!((arcs.point(0.1) - 1.1).abs() < 1e-12);
        assert!((arcs.point(2.0) - 3.0).abs() < 1e-12);
    }
}
