//! The colours of materials and chart series (the Okabe–Ito palette, told
//! apart by colour-blind readers too), of disks by diameter, of heat maps,
//! and of particles by orientation (a cyclic scale).

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

/// Lightness and chroma of the cyclic scale (OKLCh): the largest chroma
/// whose whole hue circle lies inside sRGB at this lightness, light enough
/// for the near-black edge lines to show on every hue.
const CYCLIC_L: f64 = 0.72;
const CYCLIC_C: f64 = 0.12;

/// The cyclic scale at `t` (one turn per unit: `t` and `t + 1` are the
/// same colour; NaN is the colour of 0): a hue circle at constant
/// lightness and chroma in OKLab, so that no direction looks heavier than
/// another and the colours of 0 and 1 meet without a seam. For particle
/// orientations, `t` is the angle over its period.
pub(crate) fn cyclic(t: f64) -> [u8; 3] {
    let t = if t.is_finite() {
        t.rem_euclid(1.0)
    } else {
        0.0
    };
    // Hue from red-orange (30°) so that 0 is a warm colour.
    let h = std::f64::consts::TAU * t + 30f64.to_radians();
    let (a, b) = (CYCLIC_C * h.cos(), CYCLIC_C * h.sin());
    let l = (CYCLIC_L + 0.396_337_777_4 * a + 0.215_803_757_3 * b).powi(3);
    let m = (CYCLIC_L - 0.105_561_345_8 * a - 0.063_854_172_8 * b).powi(3);
    let s = (CYCLIC_L - 0.089_484_177_5 * a - 1.291_485_548 * b).powi(3);
    let linear = [
        4.076_741_662_1 * l - 3.307_711_591_3 * m + 0.230_969_929_2 * s,
        -1.268_438_004_6 * l + 2.609_757_401_1 * m - 0.341_319_396_5 * s,
        -0.004_196_086_3 * l - 0.703_418_614_7 * m + 1.707_614_701 * s,
    ];
    linear.map(|c| {
        let c = c.clamp(0.0, 1.0);
        let srgb = if c <= 0.003_130_8 {
            12.92 * c
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        };
        (255.0 * srgb).round() as u8
    })
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

    #[test]
    fn the_cyclic_scale_closes_and_keeps_its_lightness() {
        assert_eq!(cyclic(0.0), cyclic(1.0));
        assert_eq!(cyclic(0.25), cyclic(-0.75));
        assert_eq!(cyclic(f64::NAN), cyclic(0.0));
        let luma = |[r, g, b]: [u8; 3]| {
            0.2126 * f64::from(r) + 0.7152 * f64::from(g) + 0.0722 * f64::from(b)
        };
        let mut previous = cyclic(0.0);
        for k in 1..=360 {
            let c = cyclic(f64::from(k) / 360.0);
            // Neighbours differ little (no seam), quarters differ much.
            let step = (0..3)
                .map(|i| (i32::from(c[i]) - i32::from(previous[i])).abs())
                .max();
            assert!(step <= Some(6), "{k}: {previous:?} → {c:?}");
            assert!((100.0..=200.0).contains(&luma(c)), "{k}: {c:?}");
            previous = c;
        }
        let (a, b) = (cyclic(0.0), cyclic(0.5));
        assert!(
            (0..3)
                .map(|i| (i32::from(a[i]) - i32::from(b[i])).abs())
                .sum::<i32>()
                > 120
        );
    }
}
