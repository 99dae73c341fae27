//! A parameter study's files: `sweep.csv` (one row per run, written and
//! read back to resume) and its chart (`sweep.svg`, `sweep.png`).

use super::error::OutputError;
use super::plot::{Drawable, SweepChart};
use super::run::Files;
use crate::study::{Measures, Row, Status, SweepSettings};

/// File name of a study's table.
pub const SWEEP_CSV: &str = "sweep.csv";
/// File name of a study's chart.
pub const SWEEP_SVG: &str = "sweep.svg";
/// File name of a study's chart as an image.
pub const SWEEP_PNG: &str = "sweep.png";

/// The columns after the swept keys'.
const MEASURE_COLUMNS: [&str; 8] = [
    "seed",
    "particles",
    "porosity",
    "psd_ks",
    "coordination",
    "target_error",
    "seconds",
    "status",
];

/// One row per run of a study, in product order:
/// `run,<each swept key>,seed,particles,porosity,psd_ks,coordination,target_error,seconds,status`
/// (`status` finished | `failed: <reason>` | not run; the measures empty
/// unless finished, `target_error` empty without a target). Numbers are
/// written in their shortest exact form, so [`read_sweep_csv`] reads back
/// the very values.
///
/// # Errors
/// [`OutputError::Csv`] if the CSV writer fails (it does not on memory).
pub fn sweep_csv(keys: &[String], rows: &[Row]) -> Result<Vec<u8>, OutputError> {
    let mut writer = ::csv::Writer::from_writer(Vec::new());
    let header: Vec<&str> = ["run"]
        .into_iter()
        .chain(keys.iter().map(String::as_str))
        .chain(MEASURE_COLUMNS)
        .collect();
    writer.write_record(&header)?;
    for r in rows {
        let mut record: Vec<String> = Vec::with_capacity(header.len());
        record.push(r.run.clone());
        record.extend(r.values.iter().cloned());
        record.push(r.seed.to_string());
        match &r.status {
            Status::Finished(m) => record.extend([
                m.particles.to_string(),
                m.porosity.to_string(),
                m.psd_ks.to_string(),
                m.coordination.to_string(),
                m.target_error.map_or_else(String::new, |e| e.to_string()),
                m.seconds.to_string(),
            ]),
            _ => record.extend(std::iter::repeat_n(String::new(), 6)),
        }
        record.push(r.status.text().replace(['\n', '\r'], " "));
        writer.write_record(&record)?;
    }
    writer
        .into_inner()
        .map_err(|e| OutputError::Csv(e.into_error().into()))
}

/// The rows of a `sweep.csv` of a study of `keys` swept keys, as far as
/// they can be read: a row of another shape, or cut short (a file
/// truncated mid-row lacks its status), is left out, and so is every row
/// after text that is not CSV. A file of another study's shape gives none.
pub fn read_sweep_csv(bytes: &[u8], keys: usize) -> Vec<Row> {
    let columns = 1 + keys + MEASURE_COLUMNS.len();
    let mut reader = ::csv::ReaderBuilder::new()
        .flexible(true)
        .from_reader(bytes);
    let header_fits = reader
        .headers()
        .is_ok_and(|h| h.len() == columns && h.iter().skip(1 + keys).eq(MEASURE_COLUMNS));
    if !header_fits {
        return Vec::new();
    }
    reader
        .records()
        .map_while(Result::ok)
        .filter_map(|record| {
            if record.len() != columns {
                return None;
            }
            let cells: Vec<&str> = record.iter().collect();
            let tail = &cells[1 + keys..];
            let status = match tail[7] {
                "finished" => {
                    let f = |s: &str| s.parse::<f64>().ok();
                    let target_error = match tail[5] {
                        "" => None,
                        e => Some(f(e)?),
                    };
                    Status::Finished(Measures {
                        particles: tail[1].parse().ok()?,
                        porosity: f(tail[2])?,
                        psd_ks: f(tail[3])?,
                        coordination: f(tail[4])?,
                        target_error,
                        seconds: f(tail[6])?,
                    })
                }
                "not run" => Status::NotRun,
                other => Status::Failed(other.strip_prefix("failed: ")?.to_owned()),
            };
            Some(Row {
                run: cells[0].to_owned(),
                values: cells[1..1 + keys].iter().map(|&v| v.to_owned()).collect(),
                seed: tail[0].parse().ok()?,
                status,
            })
        })
        .collect()
}

/// The files of a study: `sweep.csv`, `sweep.svg`, `sweep.png`.
///
/// # Errors
/// [`OutputError`] when the table or the chart cannot be made.
pub fn render_sweep(settings: &SweepSettings, rows: &[Row]) -> Result<Files, OutputError> {
    let keys: Vec<String> = settings.keys.iter().map(|k| k.path.clone()).collect();
    let chart = SweepChart::new(settings, rows);
    Ok(vec![
        (SWEEP_CSV.to_owned(), sweep_csv(&keys, rows)?),
        (SWEEP_SVG.to_owned(), chart.to_svg()?.into_bytes()),
        (SWEEP_PNG.to_owned(), chart.to_png()?),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows() -> Vec<Row> {
        let finished = |porosity: f64, target_error: Option<f64>| {
            Status::Finished(Measures {
                particles: 1109,
                porosity,
                psd_ks: 0.061_234_567_890_123,
                coordination: 2.6,
                target_error,
                seconds: 0.0067,
            })
        };
        vec![
            Row {
                run: "width_mm=2,preset=20-40,seed=0".to_owned(),
                values: vec!["2".to_owned(), "20/40".to_owned()],
                seed: 0,
                status: finished(0.1 + 0.2, Some(0.012_345_678_901_234_5)),
            },
            Row {
                run: "width_mm=0.2,preset=20-40,seed=0".to_owned(),
                values: vec!["0.2".to_owned(), "20/40".to_owned()],
                seed: 0,
                status: Status::Failed(
                    "fracture.width_mm: the domain, wide 0.2, holds no disk, \"quoted\"".to_owned(),
                ),
            },
            Row {
                run: "width_mm=3,preset=20-40,seed=0".to_owned(),
                values: vec!["3".to_owned(), "20/40".to_owned()],
                seed: 0,
                status: Status::NotRun,
            },
            Row {
                run: "width_mm=3,preset=30-50,seed=1".to_owned(),
                values: vec!["3".to_owned(), "30/50".to_owned()],
                seed: 1,
                status: finished(0.25, None),
            },
        ]
    }

    fn keys() -> Vec<String> {
        vec!["fracture.width_mm".to_owned(), "grading.preset".to_owned()]
    }

    #[test]
    fn rows_read_back_bit_for_bit() {
        let bytes = sweep_csv(&keys(), &rows()).expect("csv");
        let text = String::from_utf8(bytes.clone()).expect("utf-8");
        assert!(text.starts_with(
            "run,fracture.width_mm,grading.preset,seed,particles,porosity,psd_ks,coordination,target_error,seconds,status\n"
        ));
        assert!(text.contains(",,,,,,not run\n"), "{text}");
        assert_eq!(read_sweep_csv(&bytes, 2), rows());
        // Another study's shape gives nothing.
        assert!(read_sweep_csv(&bytes, 1).is_empty());
    }

    #[test]
    fn a_truncated_table_gives_the_rows_it_holds_whole() {
        let bytes = sweep_csv(&keys(), &rows()).expect("csv");
        let text = String::from_utf8(bytes).expect("utf-8");
        let whole = rows();
        // Cut inside the last row, anywhere: the first three stay.
        let last = text.trim_end().rfind('\n').expect("rows") + 1;
        for cut in last + 1..text.trim_end().len() - 1 {
            let read = read_sweep_csv(&text.as_bytes()[..cut], 2);
            assert_eq!(read, whole[..3], "cut at {cut}: {:?}", &text[last..cut]);
        }
        // Cut inside the failed row's quoted reason: the first row whole,
        // the second at most as a failure (which a resume runs again).
        let quote = text.find("\"quoted").expect("reason");
        let read = read_sweep_csv(&text.as_bytes()[..quote], 2);
        assert_eq!(read[0], whole[0]);
        assert!(
            read[1..]
                .iter()
                .all(|r| matches!(r.status, Status::Failed(_))),
            "{read:?}"
        );
    }
}
