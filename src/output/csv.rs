//! CSV tables: `packing.csv` (one row per packed disk, `id,x,y,r` in mm) and
//! `convergence.csv` (one row per generation of a GA run).

use super::error::OutputError;
use crate::ga::Generation;
use crate::packer::Packing;

/// File name of the disk table.
pub const PACKING_CSV: &str = "packing.csv";

/// File name of the GA's convergence table.
pub const CONVERGENCE_CSV: &str = "convergence.csv";

/// One row per generation: `generation,best,mean,worst,evaluations,seconds`,
/// where best, mean and worst are porosities (best: the best genome so far;
/// mean and worst: of the generation's population) and `evaluations` counts
/// distinct genomes evaluated so far.
///
/// # Errors
/// [`OutputError::Csv`] if the CSV writer fails (it does not on memory).
pub fn convergence_csv(history: &[Generation]) -> Result<Vec<u8>, OutputError> {
    let mut writer = ::csv::Writer::from_writer(Vec::new());
    writer.write_record([
        "generation",
        "best",
        "mean",
        "worst",
        "evaluations",
        "seconds",
    ])?;
    for g in history {
        writer.write_record([
            g.index.to_string(),
            g.best.value.to_string(),
            g.mean_value.to_string(),
            g.worst_value.to_string(),
            g.evaluations.to_string(),
            g.seconds.to_string(),
        ])?;
    }
    writer
        .into_inner()
        .map_err(|e| OutputError::Csv(e.into_error().into()))
}

/// The packed disks (not the wall disks) as CSV: header `id,x,y,r`, `id` from
/// 0 in placement order, lengths in mm.
///
/// Numbers use Rust's shortest round-trip formatting, so they read back
/// exactly and the same packing always gives the same bytes.
///
/// # Errors
/// [`OutputError::Csv`] if the CSV writer fails (it does not on memory).
pub fn packing_csv(packing: &Packing) -> Result<Vec<u8>, OutputError> {
    let mut writer = ::csv::Writer::from_writer(Vec::new());
    writer.write_record(["id", "x", "y", "r"])?;
    for (id, disk) in packing.disks.iter().enumerate() {
        writer.write_record([
            id.to_string(),
            disk.c.x.to_string(),
            disk.c.y.to_string(),
            disk.r.to_string(),
        ])?;
    }
    writer
        .into_inner()
        .map_err(|e| OutputError::Csv(e.into_error().into()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disk, Domain, WallMode};
    use crate::packer::PackStats;

    #[test]
    fn rows_in_placement_order_with_round_trip_numbers() {
        let packing = Packing {
            domain: Domain::rectangle(10.0, 10.0).expect("valid rectangle"),
            walls: WallMode::Disks,
            boundary: vec![Disk::new(0.0, 0.0, 0.5)],
            disks: vec![Disk::new(1.0, 2.0, 0.5), Disk::new(0.1 + 0.2, 7.25, 1e-7)],
            stats: PackStats::default(),
        };
        let text = String::from_utf8(packing_csv(&packing).expect("csv")).expect("utf-8");
        assert_eq!(
            text,
            "id,x,y,r\n0,1,2,0.5\n1,0.30000000000000004,7.25,0.0000001\n"
        );
        let x: f64 = text
            .lines()
            .nth(2)
            .and_then(|l| l.split(',').nth(1))
            .map_or(0.0, |v| v.parse().unwrap_or(0.0));
        assert_eq!(x, 0.1 + 0.2);
    }
}
