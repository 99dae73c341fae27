//! Fuzz what `gapack verify` and `gapack plot` do with a packing table they
//! are given without a config: read it, frame the disks in their bounding
//! box, check it, and draw its pictures.
//!
//! The contract: no input panics, hangs or allocates without bound; a table
//! that is refused gives an error that formats as `fuzz:LINE:COLUMN: reason`.
#![no_main]

use gapack::layering::Material;
use gapack::output::{diameter_range, read_packing_csv, render_pictures};
use gapack::{Domain, Packing, Point, check};
use libfuzzer_sys::fuzz_target;

/// Tables of more disks are only read and checked (drawing one takes long).
const DRAW_DISKS: usize = 2000;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let table = match read_packing_csv(text, "fuzz") {
        Ok(table) => table,
        Err(error) => {
            let message = error.to_string();
            assert!(message.starts_with("fuzz:"), "{message}");
            return;
        }
    };
    let (mut lo, mut hi) = (
        Point::new(f64::INFINITY, f64::INFINITY),
        Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    for d in &table.disks {
        lo = Point::new(lo.x.min(d.c.x - d.r), lo.y.min(d.c.y - d.r));
        hi = Point::new(hi.x.max(d.c.x + d.r), hi.y.max(d.c.y + d.r));
    }
    let corners = [lo, Point::new(hi.x, lo.y), hi, Point::new(lo.x, hi.y)];
    let Ok(domain) = Domain::polygon(&corners) else {
        return;
    };
    let c = check(&table.disks, &domain, None);
    assert_eq!(c.particles, table.disks.len());
    let mut packing = Packing::of_disks(domain, table.disks.clone());
    packing.materials = table.materials.clone();
    if table.disks.len() > DRAW_DISKS {
        return;
    }
    let materials: Vec<Material> = table
        .material_names
        .iter()
        .map(|name| Material {
            name: name.clone(),
            properties: Vec::new(),
        })
        .collect();
    let diameters = diameter_range(&packing);
    let _ = render_pictures(&packing, &materials, diameters, None);
});
