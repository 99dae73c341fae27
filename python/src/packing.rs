//! `gapack.Packing`: a finished `pack`, `optimise` or `layer` run, its
//! disks as numpy arrays, and the files it writes on demand.

use std::path::PathBuf;
use std::sync::OnceLock;

use gapack::jobs::{
    self, Cancel, DirStore, Job, JobKind, MemoryStore, Outcome, Plan, Report, Request,
};
use gapack::output::{Colouring, SUMMARY_JSON, packing_png_coloured};
use gapack::{Disk, Grain, Outline, Packing as Packed, Scene};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList, PyType};

use crate::convert;
use crate::errors::{gapack_error, job_error};

/// A packing made by `gapack.pack`, `gapack.optimise` or `gapack.layer`.
///
/// `x`, `y` and `r` are the disks' centres and radii (mm, float64, in
/// placement order), made once when the run ends and read-only: the same
/// arrays on every access, and what `write` writes. `material` is each
/// disk's material (an index into `materials`, int32) when the config has
/// `[[materials]]`, else `None`. A packing of particles that are not disks
/// (a `[shape]`) also has `angle`, `a`, `b`, `alpha`, `beta` and
/// `template` (see each), `None` for disks; `r` is then each particle's
/// area-equivalent radius.
#[pyclass(frozen, module = "gapack", name = "Packing")]
pub(crate) struct Packing {
    /// The job's plan, with the config's own `[output]`.
    plan: Plan,
    /// The outcome, its packing's disks and materials moved out into the arrays.
    outcome: Outcome,
    /// The config's file, if it came from one (names the default folder).
    path: Option<PathBuf>,
    /// The config's TOML text, as the run read it.
    text: String,
    x: Py<PyArray1<f64>>,
    y: Py<PyArray1<f64>>,
    r: Py<PyArray1<f64>>,
    material: Option<Py<PyArray1<i32>>>,
    /// With shapes: the angles, and the superellipse and polygon columns.
    shapes: Option<Shapes>,
    summary: Py<PyAny>,
    history: Option<Py<PyDict>>,
    warnings: Vec<String>,
    /// The picture a notebook shows (`_repr_png_`), drawn on first demand.
    picture: OnceLock<Vec<u8>>,
}

/// The shape columns of a packing of particles that are not disks, as
/// `packing.csv` has them: NaN (or -1 for `template`) where a particle is
/// of the other family.
struct Shapes {
    angle: Py<PyArray1<f64>>,
    a: Py<PyArray1<f64>>,
    b: Py<PyArray1<f64>>,
    alpha: Py<PyArray1<f64>>,
    beta: Py<PyArray1<f64>>,
    template: Py<PyArray1<i32>>,
}

impl Shapes {
    /// The columns of `grains`; `None` when there are none (disks).
    fn of(py: Python<'_>, grains: &[Grain]) -> PyResult<Option<Shapes>> {
        if grains.is_empty() {
            return Ok(None);
        }
        let n = grains.len();
        let mut cols: [Vec<f64>; 5] = std::array::from_fn(|_| Vec::with_capacity(n));
        let mut template = Vec::with_capacity(n);
        for g in grains {
            let (row, t) = match g.outline {
                Outline::Superellipse { a, b, alpha, beta } => ([a, b, alpha, beta], -1),
                Outline::Polygon { template, .. } => ([f64::NAN; 4], i32::from(template)),
            };
            cols[0].push(g.angle);
            for (col, v) in cols[1..].iter_mut().zip(row) {
                col.push(v);
            }
            template.push(t);
        }
        let [angle, a, b, alpha, beta] = cols.map(|c| frozen(PyArray1::from_vec(py, c)));
        Ok(Some(Shapes {
            angle: angle?,
            a: a?,
            b: b?,
            alpha: alpha?,
            beta: beta?,
            template: frozen(PyArray1::from_vec(py, template))?,
        }))
    }
}

/// The packing of a one-packing report.
fn packed_mut(report: &mut Report) -> Option<&mut Packed> {
    match report {
        Report::Pack { packing, .. }
        | Report::Layer { packing, .. }
        | Report::Optimise { packing, .. } => Some(packing),
        _ => None,
    }
}

/// The colouring named `name`, as `[output] colour` names them (and
/// `radius` or `diameter` for `size`).
fn colouring(name: &str) -> PyResult<Colouring> {
    match name {
        "size" | "radius" | "diameter" => Ok(Colouring::Size),
        "material" => Ok(Colouring::Material),
        "orientation" => Ok(Colouring::Orientation),
        _ => Err(PyValueError::new_err(format!(
            "color_by: \"material\", \"size\" or \"orientation\", got {name:?}"
        ))),
    }
}

/// The function `name` of the package's notebook half (`gapack/_notebook.py`).
fn notebook<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("gapack._notebook")?.getattr(name)
}

/// `array`, read-only.
fn frozen<'py, T: numpy::Element>(array: Bound<'py, PyArray1<T>>) -> PyResult<Py<PyArray1<T>>> {
    let flags = PyDict::new(array.py());
    flags.set_item("write", false)?;
    array.call_method("setflags", (), Some(&flags))?;
    Ok(array.unbind())
}

impl Packing {
    /// The packing of `outcome` (a run of `plan`), whose `summary.json` is in `store`.
    pub(crate) fn new(
        py: Python<'_>,
        plan: Plan,
        mut outcome: Outcome,
        (text, path): (String, Option<PathBuf>),
        store: &MemoryStore,
        warnings: Vec<String>,
    ) -> PyResult<Packing> {
        // Nothing is written yet: the result lines name the config.
        outcome.location.clone_from(&plan.origin);
        let Some(packed) = packed_mut(&mut outcome.report) else {
            return Err(gapack_error(py, "the job returned no packing"));
        };
        // The disks move into three arrays, one pass, no copy left behind:
        // `write` puts them back from the arrays.
        let disks = std::mem::take(&mut packed.disks);
        let materials = std::mem::take(&mut packed.materials);
        let n = disks.len();
        let (mut x, mut y, mut r) = (
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
        );
        for d in &disks {
            x.push(d.c.x);
            y.push(d.c.y);
            r.push(d.r);
        }
        drop(disks);
        let shapes = Shapes::of(py, &packed.grains)?;
        let material = if plan.config.materials.is_empty() {
            None
        } else {
            let m: Vec<i32> = materials.iter().map(|&m| i32::from(m)).collect();
            Some(frozen(PyArray1::from_vec(py, m))?)
        };
        let history = match &outcome.report {
            Report::Optimise { history, .. } => Some(convert::history(py, history)?.unbind()),
            _ => None,
        };
        let Some(summary) = store.files.get(SUMMARY_JSON) else {
            return Err(gapack_error(py, "the job wrote no summary.json"));
        };
        // Every table of it a `gapack.Summary`: a dict, read by key or attribute.
        let hook = PyDict::new(py);
        hook.set_item(
            "object_hook",
            py.import("gapack._notebook")?.getattr("Summary")?,
        )?;
        let summary = py
            .import("json")?
            .call_method("loads", (String::from_utf8_lossy(summary),), Some(&hook))?
            .unbind();
        Ok(Packing {
            x: frozen(PyArray1::from_vec(py, x))?,
            y: frozen(PyArray1::from_vec(py, y))?,
            r: frozen(PyArray1::from_vec(py, r))?,
            material,
            shapes,
            plan,
            outcome,
            path,
            text,
            summary,
            history,
            warnings,
            picture: OnceLock::new(),
        })
    }

    /// The scene the packing was made from: a search's own (the sizes it
    /// found), else the config's.
    fn scene(&self) -> &Scene {
        match &self.outcome.report {
            Report::Optimise { scene, .. } => scene,
            _ => &self.plan.config.scene,
        }
    }

    /// The PNG drawing of `packing.png`, coloured as `colour` asks
    /// (`None`: as the config's `[output] colour`).
    fn draw(&self, py: Python<'_>, colour: Option<Colouring>) -> PyResult<Vec<u8>> {
        let mut outcome = self.whole(py)?;
        let Some(packed) = packed_mut(&mut outcome.report) else {
            return Err(gapack_error(py, "the job returned no packing"));
        };
        let scene = self.scene();
        let diameters = (scene.d_min(), scene.d_max());
        let materials = &self.plan.config.materials;
        let colour = colour.or(self.plan.config.output.colour);
        py.detach(|| packing_png_coloured(packed, materials, diameters, colour))
            .map_err(|e| gapack_error(py, &format!("cannot draw the packing: {e}")))
    }

    /// The outcome with its disks and materials read back from the arrays.
    fn whole(&self, py: Python<'_>) -> PyResult<Outcome> {
        let (x, y, r) = (
            self.x.bind(py).readonly(),
            self.y.bind(py).readonly(),
            self.r.bind(py).readonly(),
        );
        let (x, y, r) = (x.as_slice()?, y.as_slice()?, r.as_slice()?);
        let mut outcome = self.outcome.clone();
        let Some(packed) = packed_mut(&mut outcome.report) else {
            return Err(gapack_error(py, "the job returned no packing"));
        };
        packed.disks = x
            .iter()
            .zip(y)
            .zip(r)
            .map(|((&x, &y), &r)| Disk::new(x, y, r))
            .collect();
        if let Some(m) = &self.material {
            let m = m.bind(py).readonly();
            packed.materials = m.as_slice()?.iter().map(|&m| m as u16).collect();
        }
        Ok(outcome)
    }
}

#[pymethods]
impl Packing {
    /// x of each disk's centre (mm).
    #[getter]
    fn x(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.x.clone_ref(py)
    }

    /// y of each disk's centre (mm).
    #[getter]
    fn y(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.y.clone_ref(py)
    }

    /// Each disk's radius (mm).
    #[getter]
    fn r(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.r.clone_ref(py)
    }

    /// Each particle's angle (radians, counter-clockwise from the x axis to
    /// its own x axis), or `None` for disks.
    #[getter]
    fn angle(&self, py: Python<'_>) -> Option<Py<PyArray1<f64>>> {
        self.shapes.as_ref().map(|s| s.angle.clone_ref(py))
    }

    /// Each superellipse's semi-axis along its own x axis (mm; NaN for a
    /// polygon), or `None` for disks.
    #[getter]
    fn a(&self, py: Python<'_>) -> Option<Py<PyArray1<f64>>> {
        self.shapes.as_ref().map(|s| s.a.clone_ref(py))
    }

    /// Each superellipse's semi-axis along its own y axis (mm; NaN for a
    /// polygon), or `None` for disks.
    #[getter]
    fn b(&self, py: Python<'_>) -> Option<Py<PyArray1<f64>>> {
        self.shapes.as_ref().map(|s| s.b.clone_ref(py))
    }

    /// Each superellipse's exponent of x, |x'/a|^alpha + |y'/b|^beta ≤ 1
    /// (NaN for a polygon), or `None` for disks.
    #[getter]
    fn alpha(&self, py: Python<'_>) -> Option<Py<PyArray1<f64>>> {
        self.shapes.as_ref().map(|s| s.alpha.clone_ref(py))
    }

    /// Each superellipse's exponent of y (NaN for a polygon), or `None`
    /// for disks.
    #[getter]
    fn beta(&self, py: Python<'_>) -> Option<Py<PyArray1<f64>>> {
        self.shapes.as_ref().map(|s| s.beta.clone_ref(py))
    }

    /// Each rounded polygon's template, an index into `[[shape.templates]]`
    /// (int32; -1 for a superellipse), or `None` for disks. Its vertices
    /// and rounding are in `packing.csv` (`write`).
    #[getter]
    fn template(&self, py: Python<'_>) -> Option<Py<PyArray1<i32>>> {
        self.shapes.as_ref().map(|s| s.template.clone_ref(py))
    }

    /// Each disk's material, an index into `materials` (int32), or `None`
    /// when the config has no `[[materials]]`.
    #[getter]
    fn material(&self, py: Python<'_>) -> Option<Py<PyArray1<i32>>> {
        self.material.as_ref().map(|m| m.clone_ref(py))
    }

    /// The config's materials, in order: `id` (index + 1), `name`, and
    /// their properties (`density`, …).
    #[getter]
    fn materials<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        convert::materials(py, &self.plan.config.materials)
    }

    /// The domain: `shape` and its sizes, `area`, `bounds`, `walls`,
    /// `periodic`, `outline` (an (n, 2) array).
    #[getter]
    fn domain<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let report = &self.outcome.report;
        let packed = match report {
            Report::Pack { packing, .. }
            | Report::Layer { packing, .. }
            | Report::Optimise { packing, .. } => packing,
            _ => return Err(gapack_error(py, "the job returned no packing")),
        };
        convert::domain(py, &packed.domain, packed.walls)
    }

    /// What `summary.json` records (a dict, as the file has it).
    #[getter]
    fn summary(&self, py: Python<'_>) -> Py<PyAny> {
        self.summary.clone_ref(py)
    }

    /// An optimise's convergence history: a dict of arrays, one entry per
    /// generation (`generation`, `best`, `mean`, `worst`, `evaluations`,
    /// `seconds`, `feasible`); `None` for other jobs.
    #[getter]
    fn history(&self, py: Python<'_>) -> Option<Py<PyDict>> {
        self.history.as_ref().map(|h| h.clone_ref(py))
    }

    /// The job that made it: `pack`, `optimise` or `layer`.
    #[getter]
    fn job(&self) -> &'static str {
        self.plan.kind.name()
    }

    /// The seed of the run.
    #[getter]
    fn seed(&self) -> u64 {
        self.plan.seed()
    }

    /// The config's TOML text, as the run read it.
    #[getter]
    fn toml(&self) -> &str {
        &self.text
    }

    /// The config's name: its path as given, `<string>` or `<dict>`.
    #[getter]
    fn config(&self) -> &str {
        &self.plan.origin
    }

    /// Whether the run was stopped (Ctrl-C, `KeyboardInterrupt`) and this
    /// is the best it had found.
    #[getter]
    fn interrupted(&self) -> bool {
        self.outcome.interrupted
    }

    /// The warnings the run gave, in order (also issued as `GapackWarning`).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// The result line(s) the command line prints for this run.
    #[getter]
    fn lines(&self) -> Vec<String> {
        self.outcome.lines()
    }

    /// Write the run's files into `dir` (default: the config's `[output]
    /// dir`, else `out/<config name>`, as the command line), as the command
    /// line writes them: `summary.json`, what `formats` asks for (default:
    /// the config's `[output] formats`), and `manifest.json`, all at once,
    /// removing the files an earlier run left there. Returns the files'
    /// names, relative to `dir`. Same config, seed and formats: the same
    /// bytes as `gapack pack|optimise|layer CONFIG --seed N --out DIR`,
    /// but for the times recorded.
    #[pyo3(signature = (dir=None, formats=None))]
    fn write(
        &self,
        py: Python<'_>,
        dir: Option<PathBuf>,
        formats: Option<Vec<String>>,
    ) -> PyResult<Vec<String>> {
        let mut output = self.plan.config.output.clone();
        if let Some(names) = formats {
            output.formats = convert::formats(&names)?;
        }
        let dir =
            dir.unwrap_or_else(|| jobs::output_dir(None, &self.plan.config, self.path.as_deref()));
        if dir.as_os_str().is_empty() {
            return Err(PyValueError::new_err("dir: an empty path"));
        }
        let outcome = self.whole(py)?;
        let plan = &self.plan;
        py.detach(|| {
            let mut store = DirStore::new(&dir);
            jobs::write(plan, &outcome, &output, &mut store)
        })
        .map_err(|e| job_error(py, e))
    }

    /// The packing as a PNG image (bytes), drawn as `write` draws
    /// `packing.png`: 1600 px on the longer side, a legend strip below.
    /// `color_by`: `"material"`, `"size"` (`"radius"`, `"diameter"`) or
    /// `"orientation"` (particles that are not disks); `None`: as the
    /// config's `[output] colour` (by material when there are materials).
    #[pyo3(signature = (color_by=None))]
    fn png<'py>(&self, py: Python<'py>, color_by: Option<&str>) -> PyResult<Bound<'py, PyBytes>> {
        let colour = color_by.map(colouring).transpose()?;
        let png = self.draw(py, colour)?;
        Ok(PyBytes::new(py, &png))
    }

    /// The meshless support size of each particle (mm, in the order of
    /// `x`): the distance from its centre to its `k`-th nearest
    /// neighbour's centre, h6 by default, as `[output] per_particle =
    /// ["h6"]` writes it; found with the measures' own neighbour index,
    /// periodic images counted once. NaN for every particle of a packing
    /// of `k` particles or fewer.
    #[pyo3(signature = (k=6))]
    fn h6<'py>(&self, py: Python<'py>, k: usize) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let mut outcome = self.whole(py)?;
        let Some(packed) = packed_mut(&mut outcome.report) else {
            return Err(gapack_error(py, "the job returned no packing"));
        };
        let packed = &*packed;
        let h = py.detach(|| gapack::meshless::hk(packed, k));
        Ok(PyArray1::from_vec(py, h))
    }

    /// The picture Jupyter shows: [`png`](Self::png) with the config's
    /// colouring, drawn once and kept.
    fn _repr_png_<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        if let Some(png) = self.picture.get() {
            return Ok(PyBytes::new(py, png));
        }
        let png = self.draw(py, None)?;
        Ok(PyBytes::new(py, self.picture.get_or_init(|| png)))
    }

    /// The picture inline and a table of the key figures, for Jupyter.
    fn _repr_html_<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        notebook(slf.py(), "html")?.call1((slf,))
    }

    /// Draw the particles on a matplotlib axes (a new figure's when `ax` is
    /// `None`), filled by `color_by` (`"material"`, `"radius"`, or any
    /// column of `to_pandas()`); other keywords go to the collection.
    /// Returns the axes. matplotlib is optional: an `ImportError` saying so
    /// when it is missing.
    #[pyo3(signature = (ax=None, color_by="material", **kw))]
    fn plot<'py>(
        slf: &Bound<'py, Self>,
        ax: Option<Bound<'py, PyAny>>,
        color_by: &str,
        kw: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        notebook(slf.py(), "plot")?.call((slf, ax, color_by), kw)
    }

    /// The particles as a pandas DataFrame, one row per particle with the
    /// columns of `packing.csv` (`id`, `x`, `y`, `r`, the shape columns,
    /// `material` as a categorical of the materials' names).
    fn to_pandas<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        notebook(slf.py(), "to_pandas")?.call1((slf,))
    }

    /// A packing of the disks of a DataFrame (`x`, `y`, `r` and optionally
    /// `material`, names or indices), in `domain` (a dict shaped like the
    /// config's `[domain]` table) or `config` (a config, whose domain,
    /// grading and materials are used); by default the config that
    /// `to_pandas` recorded in `df.attrs`. Checked and measured as a run's
    /// packing: overlapping disks or disks outside raise `GapackError`.
    #[classmethod]
    #[pyo3(signature = (df, domain=None, *, config=None, seed=None))]
    fn from_pandas<'py>(
        cls: &Bound<'py, PyType>,
        df: Bound<'py, PyAny>,
        domain: Option<Bound<'py, PyAny>>,
        config: Option<Bound<'py, PyAny>>,
        seed: Option<u64>,
    ) -> PyResult<Bound<'py, PyAny>> {
        notebook(cls.py(), "from_pandas")?.call1((df, domain, config, seed))
    }

    /// The packing of disks made elsewhere, `x`, `y`, `r` (mm) and their
    /// `material` indices, against the config `text` (named `origin`) as a
    /// pack job's: measured, checked and its summary made as a run's.
    /// `material` holds each disk's index into the config's materials, or
    /// `material_names` each disk's material by name.
    #[staticmethod]
    #[pyo3(signature = (x, y, r, text, origin, seed=None, material=None, material_names=None))]
    #[allow(clippy::too_many_arguments)]
    fn _from_arrays(
        py: Python<'_>,
        x: PyReadonlyArray1<'_, f64>,
        y: PyReadonlyArray1<'_, f64>,
        r: PyReadonlyArray1<'_, f64>,
        text: &str,
        origin: &str,
        seed: Option<u64>,
        material: Option<PyReadonlyArray1<'_, i64>>,
        material_names: Option<Vec<String>>,
    ) -> PyResult<Packing> {
        let (x, y, r) = (x.as_slice()?, y.as_slice()?, r.as_slice()?);
        if x.len() != y.len() || x.len() != r.len() {
            return Err(PyValueError::new_err("x, y and r must have one length"));
        }
        let request = Request {
            seed,
            ..Request::new(JobKind::Pack)
        };
        let mut plan = Plan::load(text, origin, &request).map_err(|e| job_error(py, e))?;
        if matches!(plan.job, Job::Wells { .. }) {
            return Err(PyValueError::new_err(
                "a [fracture] config packs wells, not one domain: give a [domain] table",
            ));
        }
        let known = &plan.config.materials;
        let count = known.len();
        let indices: Vec<i64> = match (material, material_names) {
            (Some(m), _) => m.as_slice()?.to_vec(),
            (None, Some(names)) => names
                .iter()
                .map(|name| {
                    known
                        .iter()
                        .position(|m| &m.name == name)
                        .map(|i| i as i64)
                        .ok_or_else(|| {
                            let all: Vec<&str> = known.iter().map(|m| m.name.as_str()).collect();
                            PyValueError::new_err(format!(
                                "material {name:?} is not among the config's materials ({})",
                                all.join(", ")
                            ))
                        })
                })
                .collect::<PyResult<_>>()?,
            (None, None) => Vec::new(),
        };
        if !indices.is_empty() && indices.len() != x.len() {
            return Err(PyValueError::new_err(
                "material must have the disks' length",
            ));
        }
        let materials = indices
            .iter()
            .map(|&i| {
                u16::try_from(i)
                    .ok()
                    .filter(|&i| usize::from(i) < count)
                    .ok_or_else(|| {
                        PyValueError::new_err(format!(
                            "material {i}: the config has {count} materials"
                        ))
                    })
            })
            .collect::<PyResult<Vec<u16>>>()?;
        let disks = crate::convert::disks_of(x, y, r);
        let mut packed = Packed::of_disks(plan.config.scene.domain.clone(), disks);
        packed.materials = materials;
        let mut quiet = plan.clone();
        quiet.config.output.formats.clear();
        let (outcome, store) = py
            .detach(|| {
                let outcome = Outcome::of_packing(&quiet, packed, &Cancel::new())?;
                let mut store = MemoryStore::default();
                jobs::write(&quiet, &outcome, &quiet.config.output, &mut store)?;
                Ok((outcome, store))
            })
            .map_err(|e| job_error(py, e))?;
        plan.warnings.clear();
        Packing::new(
            py,
            plan,
            outcome,
            (text.to_owned(), None),
            &store,
            Vec::new(),
        )
    }

    fn __len__(&self, py: Python<'_>) -> usize {
        self.x.bind(py).len()
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let porosity = self
            .summary
            .bind(py)
            .get_item("porosity")
            .and_then(|p| p.extract::<f64>())
            .map_or_else(|_| "?".to_owned(), |p| format!("{p:.4}"));
        format!(
            "<gapack.Packing {}: {} disks, porosity {porosity}, seed {}{}>",
            self.plan.kind.name(),
            self.x.bind(py).len(),
            self.plan.seed(),
            if self.outcome.interrupted {
                ", interrupted"
            } else {
                ""
            }
        )
    }
}
