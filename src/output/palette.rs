//! The colours of materials and chart series (the Okabe–Ito palette, told
//! apart by colour-blind readers too), of disks by diameter, and of heat maps.

/// Colours in order, as RGB.
pub(crate) const PALETTE: [[u8; 3]; 8] = [
    [0, 114, 178],
    [213, 94, 0],
    [0, 158, 115],
    [204, 121, 167],
    [230, 159, 0],
    [86, 180, 233],
    [0, 0, 0],
    [240, 228, 66],
];

/// Colour `i` of the palette (it repeats after eight).
pub(crate) fn colour(i: usize) -> [u8; 3] {
    PALETTE[i % PALETTE.len()]
}

/// Fill of the smallest and of the largest disks (light to dark blue).
const LIGHT: [f64; 3] = [198.0, 219.0, 239.0];
const DARK: [f64; 3] = [8.0, 48.0, 107.0];

/// The disk ramp at `t` in [0, 1], light to dark blue (clamped; NaN is mid-tone).
pub(crate) fn ramp(t: f64) -> [u8; 3] {
    let t = if t.is_nan() { 0.5 } else { t.clamp(0.0, 1.0) };
    [0, 1, 2].map(|i| (LIGHT[i] + t * (DARK[i] - LIGHT[i])).round() as u8)
}

/// Fill of a disk of diameter `d`: light at `d_min`, dark at `d_max`;
/// mid-tone for a single size (`d_min == d_max`) or a NaN diameter.
pub(crate) fn diameter_colour(d: f64, (d_min, d_max): (f64, f64)) -> [u8; 3] {
    if d_max > d_min {
        ramp((d - d_min) / (d_max - d_min))
    } else {
        ramp(0.5)
    }
}

/// Viridis (matplotlib's perceptually uniform sequential map) at 0, 0.1, …, 1.
const VIRIDIS: [[f64; 3]; 11] = [
    [68.0, 1.0, 84.0],
    [72.0, 36.0, 117.0],
    [65.0, 68.0, 135.0],
    [53.0, 95.0, 141.0],
    [42.0, 120.0, 142.0],
    [33.0, 145.0, 140.0],
    [34.0, 168.0, 132.0],
    [68.0, 191.0, 112.0],
    [122.0, 209.0, 81.0],
    [189.0, 223.0, 38.0],
    [253.0, 231.0, 37.0],
];

/// Viridis at `t` in [0, 1] (clamped; NaN is mid-tone), dark purple to
/// yellow: linear between the eleven stops, monotone in lightness, legible
/// in grey and to colour-blind readers.
pub(crate) fn viridis(t: f64) -> [u8; 3] {
    let t = if t.is_nan() { 0.5 } else { t.clamp(0.0, 1.0) };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    [0, 1, 2].map(|k| (a[k] + f * (b[k] - a[k])).round() as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diameters_run_light_to_dark() {
        assert_eq!(diameter_colour(1.0, (1.0, 2.0)), [198, 219, 239]);
        assert_eq!(diameter_colour(2.0, (1.0, 2.0)), [8, 48, 107]);
        assert_eq!(diameter_colour(9.0, (1.0, 2.0)), [8, 48, 107]);
        assert_eq!(
            diameter_colour(1.2, (1.2, 1.2)),
            diameter_colour(1.5, (1.0, 2.0))
        );
        assert_eq!(
            diameter_colour(f64::NAN, (1.0, 2.0)),
            diameter_colour(1.5, (1.0, 2.0))
        );
    }

    #[test]
    fn viridis_hits_its_stops_and_gets_lighter() {
        assert_eq!(viridis(0.0), [68, 1, 84]);
        assert_eq!(viridis(0.5), [33, 145, 140]);
        assert_eq!(viridis(1.0), [253, 231, 37]);
        assert_eq!(viridis(7.0), viridis(1.0));
        assert_eq!(viridis(f64::NAN), viridis(0.5));
        let luma =
            |[r, g, b]: [u8; 3]| 0.3 * f64::from(r) + 0.59 * f64::from(g) + 0.11 * f64::from(b);
        for k in 0..100 {
            let (a, b) = (f64::from(k) / 100.0, f64::from(k + 1) / 100.0);
            assert!(luma(viridis(a)) <= luma(viridis(b)), "{a}");
        }
    }
}
