//! The library's values as Python ones: the domain, the materials, a
//! search's history, output format names, and the independent check.

use gapack::config::{Config, ConfigName};
use gapack::fracture::Extent;
use gapack::ga::Generation;
use gapack::layering::Material;
use gapack::output::Format;
use gapack::{
    Cancel, Cancelled, Check, Disk, Domain, GradingCheck, Grain, Outline, Packing, Shape,
    check_cancellable, grading_sizes, psd_ks,
};
use numpy::{PyArray1, PyArray2, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use std::sync::Mutex;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use crate::errors::{gapack_error, input_error};

/// Every output format, in the order `[output] formats` documents them.
const FORMATS: [Format; 15] = [
    Format::Csv,
    Format::Json,
    Format::Vtk,
    Format::Vtp,
    Format::Npz,
    Format::Lammps,
    Format::Yade,
    Format::Pfc,
    Format::Mercury,
    Format::LiggghtsSuperquadric,
    Format::Esys,
    Format::LammpsClumps,
    Format::LiggghtsClumps,
    Format::Svg,
    Format::Png,
];

/// Fails to compile when a format is added, until [`FORMATS`] lists it.
const fn listed(format: Format) -> bool {
    match format {
        Format::Csv
        | Format::Json
        | Format::Vtk
        | Format::Vtp
        | Format::Npz
        | Format::Lammps
        | Format::Yade
        | Format::Pfc
        | Format::Mercury
        | Format::LiggghtsSuperquadric
        | Format::Esys
        | Format::LammpsClumps
        | Format::LiggghtsClumps
        | Format::Svg
        | Format::Png => true,
    }
}

/// The names of every output format (`gapack.FORMATS`).
pub(crate) fn format_names() -> Vec<&'static str> {
    FORMATS
        .iter()
        .filter(|f| listed(**f))
        .map(|f| f.config_name())
        .collect()
}

/// The formats `names` names, in order; an unknown or repeated name is a
/// `ValueError` naming the valid ones.
pub(crate) fn formats(names: &[String]) -> PyResult<Vec<Format>> {
    let mut chosen = Vec::with_capacity(names.len());
    for name in names {
        let Some(format) = FORMATS.iter().find(|f| f.config_name() == name) else {
            return Err(PyValueError::new_err(format!(
                "formats: unknown format {name:?}; valid: {}",
                format_names().join(", ")
            )));
        };
        if chosen.contains(format) {
            return Err(PyValueError::new_err(format!(
                "formats: {name:?} is given twice"
            )));
        }
        chosen.push(*format);
    }
    Ok(chosen)
}

/// A point as `[x, y]`.
fn pair(p: gapack::Point) -> [f64; 2] {
    [p.x, p.y]
}

/// The domain as a dict: `shape` and its sizes as the config names them,
/// `area` (mm²), `bounds` (`[[x0, y0], [x1, y1]]`), `walls`, `periodic`,
/// and `outline`, an (n, 2) array of its boundary (circles in 256 segments).
pub(crate) fn domain<'py>(
    py: Python<'py>,
    domain: &Domain,
    walls: gapack::WallMode,
) -> PyResult<Bound<'py, PyDict>> {
    let told = PyDict::new(py);
    match domain.shape() {
        Shape::Rectangle { width, height } => {
            told.set_item("shape", "rectangle")?;
            told.set_item("width", width)?;
            told.set_item("height", height)?;
        }
        Shape::Polygon { vertices } => {
            told.set_item("shape", "polygon")?;
            let v: Vec<[f64; 2]> = vertices.iter().map(|p| pair(*p)).collect();
            told.set_item("vertices", v)?;
        }
        Shape::Circle { center, radius } => {
            told.set_item("shape", "circle")?;
            told.set_item("center", pair(*center))?;
            told.set_item("radius", radius)?;
        }
        Shape::Trapezoid {
            bottom,
            top,
            height,
        } => {
            told.set_item("shape", "trapezoid")?;
            told.set_item("bottom", bottom)?;
            told.set_item("top", top)?;
            told.set_item("height", height)?;
        }
    }
    told.set_item("area", domain.area())?;
    let (lo, hi) = domain.bounds();
    told.set_item("bounds", [pair(lo), pair(hi)])?;
    told.set_item("walls", walls.config_name())?;
    told.set_item("periodic", domain.is_periodic())?;
    let outline: Vec<Vec<f64>> = domain
        .outline(256)
        .into_iter()
        .map(|p| vec![p.x, p.y])
        .collect();
    let outline = PyArray2::from_vec2(py, &outline)
        .map_err(|e| PyValueError::new_err(format!("domain outline: {e}")))?;
    told.set_item("outline", outline)?;
    Ok(told)
}

/// The materials as a list of dicts: `id` (index + 1, as the DEM files
/// number them), `name`, and the properties the config gives (`density`, …).
pub(crate) fn materials<'py>(
    py: Python<'py>,
    materials: &[Material],
) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for (i, m) in materials.iter().enumerate() {
        let told = PyDict::new(py);
        told.set_item("id", i + 1)?;
        told.set_item("name", &m.name)?;
        for (key, value) in &m.properties {
            told.set_item(key, value)?;
        }
        list.append(told)?;
    }
    Ok(list)
}

/// A search's history as a dict of arrays, one entry per generation (0 is
/// the initial population), as `convergence.csv` has them: `generation`,
/// `best`, `mean`, `worst`, `evaluations`, `seconds`, and `feasible`
/// (whether the best so far honours the grading).
pub(crate) fn history<'py>(
    py: Python<'py>,
    history: &[Generation],
) -> PyResult<Bound<'py, PyDict>> {
    let told = PyDict::new(py);
    let column = |f: fn(&Generation) -> f64| history.iter().map(f).collect::<Vec<f64>>();
    let index: Vec<i64> = history.iter().map(|g| g.index as i64).collect();
    told.set_item("generation", PyArray1::from_vec(py, index))?;
    told.set_item("best", PyArray1::from_vec(py, column(|g| g.best.value)))?;
    told.set_item("mean", PyArray1::from_vec(py, column(|g| g.mean_value)))?;
    told.set_item("worst", PyArray1::from_vec(py, column(|g| g.worst_value)))?;
    let evaluations: Vec<i64> = history.iter().map(|g| g.evaluations as i64).collect();
    told.set_item("evaluations", PyArray1::from_vec(py, evaluations))?;
    told.set_item("seconds", PyArray1::from_vec(py, column(|g| g.seconds)))?;
    let feasible: Vec<bool> = history.iter().map(|g| g.best.is_feasible()).collect();
    told.set_item("feasible", PyArray1::from_vec(py, feasible))?;
    Ok(told)
}

/// How often a waiting check looks for a `KeyboardInterrupt`.
const POLL: Duration = Duration::from_millis(20);

/// Run `work` on a thread of its own, the GIL released, while this thread
/// looks for a `KeyboardInterrupt` every [`POLL`]: one raises `work`'s
/// token (the check polls it once per disk), and is returned once `work`
/// has stopped.
///
/// # Errors
/// The `KeyboardInterrupt` (or any error a signal handler raised); a
/// `GapackError` if the check's thread panicked.
fn interruptible(
    py: Python<'_>,
    work: impl FnOnce(&Cancel) -> Result<Check, Cancelled> + Send,
) -> PyResult<Check> {
    let cancel = Cancel::new();
    let (tx, rx) = mpsc::channel::<()>();
    // Waited on with the GIL released, hence from a closure that must be Send.
    let rx = Mutex::new(rx);
    let mut interrupt: Option<PyErr> = None;
    let joined = std::thread::scope(|scope| {
        let token = &cancel;
        let worker = scope.spawn(move || {
            let done = work(token);
            // The sender dropped says the work is over; nothing is sent.
            drop(tx);
            done
        });
        loop {
            let got = py.detach(|| match rx.lock() {
                Ok(rx) => rx.recv_timeout(POLL),
                Err(_) => Err(RecvTimeoutError::Disconnected),
            });
            // Nothing is sent: anything but a timeout means the work is over.
            if !matches!(got, Err(RecvTimeoutError::Timeout)) {
                break;
            }
            if let Err(e) = py.check_signals() {
                cancel.cancel();
                interrupt = Some(e);
                break;
            }
        }
        py.detach(move || worker.join())
    });
    if let Some(e) = interrupt {
        return Err(e);
    }
    match joined {
        Ok(Ok(check)) => Ok(check),
        // Only the interrupt above raises the token.
        Ok(Err(stopped)) => Err(gapack_error(py, &format!("the check stopped: {stopped}"))),
        Err(_) => Err(gapack_error(py, "the check failed unexpectedly")),
    }
}

/// `gapack.verify`: the independent check of the disks against the
/// config's domain and grading (each material against its own curve in a
/// size-graded config, when `material` is given), as a dict.
pub(crate) fn verify(
    py: Python<'_>,
    config: &Config,
    origin: &str,
    [x, y, r]: [PyReadonlyArray1<'_, f64>; 3],
    material: Option<PyReadonlyArray1<'_, i64>>,
    shapes: Option<[PyReadonlyArray1<'_, f64>; 5]>,
) -> PyResult<Py<PyAny>> {
    if let Some(run) = &config.fracture
        && (run.batch || matches!(run.extent, Extent::Window { .. }))
    {
        return Err(input_error(
            py,
            &format!(
                "{origin}: a batch of wells or a window packing is checked against its own well or window: use `gapack verify PACKING.csv --config CONFIG --well NAME` next to its run's summary.json"
            ),
        ));
    }
    let (x, y, r) = (x.as_slice()?, y.as_slice()?, r.as_slice()?);
    if x.len() != y.len() || x.len() != r.len() {
        return Err(PyValueError::new_err(format!(
            "x, y and r must have one length, got {}, {} and {}",
            x.len(),
            y.len(),
            r.len()
        )));
    }
    // An empty table is no packing: "valid" with porosity 1 would pass
    // whatever went wrong upstream.
    if x.is_empty() {
        return Err(PyValueError::new_err(
            "no disks to verify: x, y and r are empty",
        ));
    }
    let materials: Option<Vec<u16>> = match &material {
        None => None,
        Some(m) => {
            let m = m.as_slice()?;
            if m.len() != x.len() {
                return Err(PyValueError::new_err(format!(
                    "material must have the length of x, {}, got {}",
                    x.len(),
                    m.len()
                )));
            }
            let count = config.materials.len() as i64;
            if let Some(bad) = m.iter().find(|&&i| i < 0 || i >= count) {
                return Err(PyValueError::new_err(format!(
                    "material: {bad} is not an index into the config's {count} materials"
                )));
            }
            Some(m.iter().map(|&i| i as u16).collect())
        }
    };
    let disks = disks_of(x, y, r);
    // Superellipses: angle, a, b, alpha, beta, each of the length of x (an
    // outline its constructor refuses is a malformed particle).
    let grains: Vec<Grain> = match &shapes {
        None => Vec::new(),
        Some(columns) => {
            let columns = columns
                .iter()
                .map(|c| c.as_slice())
                .collect::<Result<Vec<_>, _>>()?;
            for (name, c) in ["angle", "a", "b", "alpha", "beta"].iter().zip(&columns) {
                if c.len() != x.len() {
                    return Err(PyValueError::new_err(format!(
                        "{name} must have the length of x, {}, got {}",
                        x.len(),
                        c.len()
                    )));
                }
            }
            (0..x.len())
                .map(|i| {
                    let outline = Outline::Superellipse {
                        a: columns[1][i],
                        b: columns[2][i],
                        alpha: columns[3][i],
                        beta: columns[4][i],
                    };
                    Grain::new(outline, columns[0][i])
                })
                .collect()
        }
    };
    let scene = &config.scene;
    let graded = scene.gradient.is_some();
    let result = interruptible(py, |cancel| {
        let grading = (!graded).then_some(&scene.grading);
        let mut result = if grains.is_empty() {
            check_cancellable(&disks, &[], &scene.domain, grading, None, cancel)?
        } else {
            // The grading on the size it measures, as `gapack verify` does.
            let packing =
                Packing::of_disks(scene.domain.clone(), disks.clone()).with_grains(grains.clone());
            let sizes = grading_sizes(&packing, scene);
            check_cancellable(
                &disks,
                &grains,
                &scene.domain,
                grading,
                Some(&sizes),
                cancel,
            )?
        };
        if graded && let Some(materials) = materials {
            let mut packing = Packing::of_disks(scene.domain.clone(), disks);
            packing.walls = scene.walls;
            packing.materials = materials;
            result.grading = GradingCheck::of(result.particles - result.malformed, || {
                psd_ks(&packing, scene)
            });
        }
        Ok(result)
    })?;
    let told = PyDict::new(py);
    let kept = result.grading_kept();
    let verdict = match (result.valid() && kept, result.grading) {
        (false, _) => "FAILED",
        (true, GradingCheck::TooFewDisks(_) | GradingCheck::NotAsked) => {
            "valid, grading not checked"
        }
        (true, _) => "valid",
    };
    told.set_item("verdict", verdict)?;
    told.set_item("valid", result.valid())?;
    told.set_item("grading_kept", kept)?;
    told.set_item("particles", result.particles)?;
    told.set_item("malformed", result.malformed)?;
    told.set_item("overlaps", result.overlaps)?;
    told.set_item("overlaps_complete", result.overlaps_complete)?;
    told.set_item("worst_overlap", result.worst_overlap)?;
    told.set_item("outside", result.outside)?;
    told.set_item("worst_outside", result.worst_outside)?;
    told.set_item("domain_area", result.domain_area)?;
    told.set_item("solid_area", result.solid_area)?;
    told.set_item("porosity", result.porosity)?;
    told.set_item("psd_ks", result.grading.ks())?;
    told.set_item("ks_limit", result.ks_limit)?;
    Ok(told.into_any().unbind())
}

/// The disks of the columns `x`, `y` and `r` (of one length).
pub(crate) fn disks_of(x: &[f64], y: &[f64], r: &[f64]) -> Vec<Disk> {
    x.iter()
        .zip(y)
        .zip(r)
        .map(|((&x, &y), &r)| Disk::new(x, y, r))
        .collect()
}
