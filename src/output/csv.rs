//! `packing.csv`: one row per packed disk, `id,x,y,r` in mm.

use super::error::OutputError;
use crate::packer::Packing;

/// File name of the disk table.
pub const PACKING_CSV: &str = "packing.csv";

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
