//! The colours of materials and chart series: the Okabe–Ito palette, told
//! apart by colour-blind readers too.

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
