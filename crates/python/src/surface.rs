//! `hullskin.Surface`: a NURBS surface with its length unit, evaluated over NumPy arrays
//! (points, derivatives, normals, curvature, closest points), and its hydrostatics, meshes,
//! files and JSON, each from the library function the command line calls.

use hull::Units;
use numpy::PyArrayDyn;
use nurbs::{KnotVector, NurbsSurface, SurfaceDerivatives, Vec3};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

use crate::arrays;
use crate::errors::{bad_arg, to_py};
use crate::options;

/// A NURBS surface (a starboard half hull as fitted: x forward, y half-breadth, z up), in
/// `units`. Parameters outside the domain are clamped to it, as the library does.
#[pyclass(module = "hullskin", name = "Surface", frozen)]
#[derive(Clone)]
pub struct PySurface {
    pub surface: NurbsSurface,
    pub units: Units,
    /// Where it came from (`<offsets>, fitted by <method>`, a file, `python`): the title of its
    /// hydrostatic table and exports, as on the command line.
    pub source: String,
    /// The perpendiculars of the offsets it was fitted to, where they were known.
    pub perpendiculars: Option<hull::Perpendiculars>,
}

/// Evaluate `f` at every pair, in parallel (the order of the result is the pairs').
fn each<T: Send>(pairs: &[(f64, f64)], f: impl Fn(f64, f64) -> T + Sync) -> Vec<T> {
    pairs.par_iter().with_min_len(4096).map(|&(u, v)| f(u, v)).collect()
}

fn knots(name: &str, degree: i64, obj: &Bound<'_, PyAny>) -> PyResult<KnotVector> {
    let degree = usize::try_from(degree).map_err(|_| bad_arg(format!("degree: {degree} is negative")))?;
    let (shape, k) = arrays::finite_floats(obj, name)?;
    if shape.len() != 1 {
        return Err(bad_arg(format!("{name}: shape {shape:?}, expected a 1-D knot vector")));
    }
    KnotVector::try_new(degree, k).map_err(|e| bad_arg(format!("{name}: {e}")))
}

impl PySurface {
    fn derivs(&self, py: Python<'_>, pairs: &[(f64, f64)]) -> Vec<SurfaceDerivatives> {
        py.detach(|| each(pairs, |u, v| self.surface.derivatives(u, v)))
    }
}

#[pymethods]
impl PySurface {
    /// A surface from its knot vectors, control points of shape (nu, nv, 3) and weights of
    /// shape (nu, nv) (all 1 without them); the degrees are `(p, q)`.
    #[new]
    #[pyo3(signature = (degree, knots_u, knots_v, control_points, weights = None, units = "m", source = "python"))]
    fn py_new(
        degree: (i64, i64),
        knots_u: &Bound<'_, PyAny>,
        knots_v: &Bound<'_, PyAny>,
        control_points: &Bound<'_, PyAny>,
        weights: Option<&Bound<'_, PyAny>>,
        units: &str,
        source: &str,
    ) -> PyResult<Self> {
        let ku = knots("knots_u", degree.0, knots_u)?;
        let kv = knots("knots_v", degree.1, knots_v)?;
        let (nu, nv) = (ku.num_basis(), kv.num_basis());
        let (shape, c) = arrays::finite_floats(control_points, "control_points")?;
        if shape != [nu, nv, 3] {
            return Err(bad_arg(format!(
                "control_points: shape {shape:?}, expected ({nu}, {nv}, 3) for these degrees and knot vectors"
            )));
        }
        let pts: Vec<Vec3> = c.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect();
        let w = match weights {
            Some(w) => {
                let (shape, w) = arrays::finite_floats(w, "weights")?;
                if shape != [nu, nv] {
                    return Err(bad_arg(format!("weights: shape {shape:?}, expected ({nu}, {nv})")));
                }
                Some(w)
            }
            None => None,
        };
        let surface = NurbsSurface::try_new(ku, kv, &pts, w.as_deref()).map_err(|e| bad_arg(e.to_string()))?;
        hull::check_finite(&surface).map_err(to_py)?;
        Ok(PySurface { surface, units: options::units(units)?, source: source.to_string(), perpendiculars: None })
    }

    /// Degrees `(p, q)` along u (the sections) and v (across them).
    #[getter]
    fn degree(&self) -> (usize, usize) {
        (self.surface.degree_u(), self.surface.degree_v())
    }

    /// Knot vector along u.
    #[getter]
    fn knots_u<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let k = self.surface.knots_u().as_slice().to_vec();
        arrays::array(py, &[k.len()], k)
    }

    /// Knot vector along v.
    #[getter]
    fn knots_v<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let k = self.surface.knots_v().as_slice().to_vec();
        arrays::array(py, &[k.len()], k)
    }

    /// Control points, shape (nu, nv, 3).
    #[getter]
    fn control_points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        arrays::vec3s(py, &[self.surface.n_u(), self.surface.n_v()], &self.surface.control_points())
    }

    /// Weights, shape (nu, nv).
    #[getter]
    fn weights<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        arrays::array(py, &[self.surface.n_u(), self.surface.n_v()], self.surface.weights())
    }

    /// The length unit: m, mm, ft or in.
    #[getter]
    fn units(&self) -> &'static str {
        self.units.symbol()
    }

    /// Where the surface came from.
    #[getter]
    fn source(&self) -> String {
        self.source.clone()
    }

    /// `((u0, u1), (v0, v1))`: the parameter domain.
    #[getter]
    fn domain(&self) -> ((f64, f64), (f64, f64)) {
        (self.surface.domain_u(), self.surface.domain_v())
    }

    /// The points S(u, v): `u` and `v` arrays of one shape (or one a scalar), result of that
    /// shape + (3,). Released from the GIL and evaluated in parallel by the kernel's
    /// evaluator of scattered points (equal to `derivatives()["point"]` to a few ulps).
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let evaluator = nurbs::PointEvaluator::new(&self.surface);
        arrays::map_pairs(py, u, v, |u, v| {
            let p = evaluator.point(u, v);
            [p.x, p.y, p.z]
        })
    }

    /// The point and the partial derivatives up to second order: a dict of arrays of shape
    /// + (3,), keys `point`, `su`, `sv`, `suu`, `suv`, `svv`.
    fn derivatives<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (shape, pairs) = arrays::parameters(u, v)?;
        let d = self.derivs(py, &pairs);
        let out = PyDict::new(py);
        let parts: [(&str, fn(&SurfaceDerivatives) -> Vec3); 6] = [
            ("point", |d| d.point),
            ("su", |d| d.su),
            ("sv", |d| d.sv),
            ("suu", |d| d.suu),
            ("suv", |d| d.suv),
            ("svv", |d| d.svv),
        ];
        for (key, part) in parts {
            let pts: Vec<Vec3> = d.iter().map(part).collect();
            out.set_item(key, arrays::vec3s(py, &shape, &pts)?)?;
        }
        Ok(out)
    }

    /// Unit normals S_u x S_v / |S_u x S_v| (at a collapsed edge the limit from inside), shape
    /// + (3,); NaN where there is none.
    fn normal<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        arrays::map_pairs(py, u, v, |u, v| self.surface.normal(u, v).map_or([f64::NAN; 3], |n| [n.x, n.y, n.z]))
    }

    /// Gaussian curvature K and mean curvature H (from the fundamental forms), and the
    /// principal curvatures k1 >= k2 (H ± sqrt(H² - K)): a dict of arrays of the parameters'
    /// shape; NaN at degenerate points.
    fn curvature<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (shape, pairs) = arrays::parameters(u, v)?;
        let c = py.detach(|| each(&pairs, |u, v| self.surface.curvature(u, v)));
        let (k, h): (Vec<f64>, Vec<f64>) =
            c.iter().map(|c| c.map_or((f64::NAN, f64::NAN), |c| (c.gaussian, c.mean))).unzip();
        let root = |k: f64, h: f64| (h * h - k).max(0.0).sqrt();
        let k1 = k.iter().zip(&h).map(|(&k, &h)| h + root(k, h)).collect();
        let k2 = k.iter().zip(&h).map(|(&k, &h)| h - root(k, h)).collect();
        let out = PyDict::new(py);
        out.set_item("gaussian", arrays::array(py, &shape, k)?)?;
        out.set_item("mean", arrays::array(py, &shape, h)?)?;
        out.set_item("k1", arrays::array(py, &shape, k1)?)?;
        out.set_item("k2", arrays::array(py, &shape, k2)?)?;
        Ok(out)
    }

    /// The closest point of the surface to each of `points` (shape (n, 3)), by the library's
    /// projector (the one that measures fit errors): a dict with `u`, `v`, `points` (n, 3),
    /// `distance` and `converged` (n,).
    fn closest_points<'py>(&self, py: Python<'py>, points: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
        let qs = arrays::points(points, "points")?;
        let r = py.detach(|| {
            let projector = nurbs::SurfaceProjector::new(&self.surface, nurbs::ProjectionOptions::default());
            qs.par_chunks(256).flat_map_iter(|c| projector.project_many(c)).collect::<Vec<_>>()
        });
        let n = [r.len()];
        let out = PyDict::new(py);
        out.set_item("u", arrays::array(py, &n, r.iter().map(|p| p.u).collect())?)?;
        out.set_item("v", arrays::array(py, &n, r.iter().map(|p| p.v).collect())?)?;
        out.set_item("points", arrays::vec3s(py, &n, &r.iter().map(|p| p.point).collect::<Vec<_>>())?)?;
        out.set_item("distance", arrays::array(py, &n, r.iter().map(|p| p.distance).collect())?)?;
        out.set_item("converged", arrays::array(py, &n, r.iter().map(|p| p.converged).collect())?)?;
        Ok(out)
    }

    /// The hydrostatic table at `draft` (or the drafts from `draft` to `to` by `step`), as
    /// `hullskin hydrostatics --format json` prints it (a dict parsed from the same JSON):
    /// `source`, `units`, `density`, `perpendiculars` where known, and `rows`. `density` in
    /// t/m³; `lpp` (with `ap`, default 0) places the perpendiculars, else the offsets' own.
    #[pyo3(signature = (draft, to = None, step = None, density = hull::SEA_WATER_DENSITY, lpp = None, ap = None))]
    fn hydrostatics<'py>(
        &self,
        py: Python<'py>,
        draft: f64,
        to: Option<f64>,
        step: Option<f64>,
        density: f64,
        lpp: Option<f64>,
        ap: Option<f64>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let json = crate::hydrostatics::table_json(self, draft, to, step, density, lpp, ap)?;
        py.import("json")?.call_method1("loads", (json,))
    }

    /// A triangle mesh within `tolerance` of the surface (default 1e-4 of the control net's
    /// diagonal, as `hullskin export` uses); `mirror` adds the port half. Returns
    /// `(vertices (n, 3), faces (m, 3) of vertex indices)`, faces counter-clockwise from outside.
    #[pyo3(signature = (tolerance = None, mirror = false))]
    fn tessellate<'py>(
        &self,
        py: Python<'py>,
        tolerance: Option<f64>,
        mirror: bool,
    ) -> PyResult<(Bound<'py, PyArrayDyn<f64>>, Bound<'py, PyArrayDyn<i64>>)> {
        let mesh = crate::export::mesh(py, self, tolerance, mirror)?;
        let faces: Vec<i64> = mesh.triangles.iter().flat_map(|t| t.map(i64::from)).collect();
        Ok((
            arrays::vec3s(py, &[mesh.vertices.len()], &mesh.vertices)?,
            arrays::array(py, &[mesh.triangles.len(), 3], faces)?,
        ))
    }

    /// Write IGES 5.3 (one rational B-spline surface, entity 128), as `hullskin export
    /// --format iges`; `mirror` joins the port half; `timestamp` (Unix seconds) dates the header
    /// (default SOURCE_DATE_EPOCH, else now).
    #[pyo3(signature = (path, mirror = false, timestamp = None))]
    fn write_iges(
        &self,
        py: Python<'_>,
        path: std::path::PathBuf,
        mirror: bool,
        timestamp: Option<i64>,
    ) -> PyResult<()> {
        crate::export::write(py, self, &path, crate::export::Format::Iges, mirror, None, timestamp)
    }

    /// Write STEP AP214 (one B-spline face), as `hullskin export --format step`.
    #[pyo3(signature = (path, mirror = false, timestamp = None))]
    fn write_step(
        &self,
        py: Python<'_>,
        path: std::path::PathBuf,
        mirror: bool,
        timestamp: Option<i64>,
    ) -> PyResult<()> {
        crate::export::write(py, self, &path, crate::export::Format::Step, mirror, None, timestamp)
    }

    /// Write a binary (or `ascii`) STL triangulated to `tolerance`, as `hullskin export
    /// --format stl`.
    #[pyo3(signature = (path, tolerance = None, mirror = false, ascii = false))]
    fn write_stl(
        &self,
        py: Python<'_>,
        path: std::path::PathBuf,
        tolerance: Option<f64>,
        mirror: bool,
        ascii: bool,
    ) -> PyResult<()> {
        let format = if ascii { crate::export::Format::StlAscii } else { crate::export::Format::Stl };
        crate::export::write(py, self, &path, format, mirror, tolerance, None)
    }

    /// The surface as the `surface.json` that `hullskin fit` writes: the Euclidean control
    /// points and weights with their shortest round-trip digits (read back, a rational
    /// surface's products w·P are rounded once more; pickling keeps them exactly).
    fn to_json(&self) -> PyResult<String> {
        let mut out = Vec::new();
        hull::write_surface_json(&mut out, &self.surface, self.units)
            .map_err(|e| bad_arg(format!("cannot write the surface JSON: {e}")))?;
        String::from_utf8(out).map_err(|e| bad_arg(e.to_string()))
    }

    /// A surface from the text of a `surface.json` (`to_json`, or `hullskin fit`'s file).
    #[staticmethod]
    #[pyo3(signature = (text, source = "surface.json"))]
    fn from_json(text: &str, source: &str) -> PyResult<Self> {
        let (surface, units) = hull::read_surface_json(text.trim_start_matches('\u{FEFF}'))
            .map_err(|e| crate::errors::HullskinError::new_err(format!("{source}: {e}")))?;
        hull::check_finite(&surface).map_err(to_py)?;
        Ok(PySurface { surface, units: options::units(&units)?, source: source.to_string(), perpendiculars: None })
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.cast::<PySurface>().is_ok_and(|o| {
            let o = o.get();
            o.surface == self.surface && o.units == self.units
        })
    }

    fn __repr__(&self) -> String {
        format!(
            "<hullskin.Surface degree {:?}, {}x{} control points, {}, {}>",
            self.degree(),
            self.surface.n_u(),
            self.surface.n_v(),
            if self.surface.is_rational() { "rational" } else { "non-rational" },
            self.units.symbol()
        )
    }

    /// Pickled exactly: degrees, knots, homogeneous control points, units, source and
    /// perpendiculars.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let py = slf.py();
        let me = slf.get();
        let f = py.import("hullskin._hullskin")?.getattr("_surface_from_state")?;
        let s = &me.surface;
        let state = (
            (s.degree_u(), s.degree_v()),
            s.knots_u().as_slice().to_vec(),
            s.knots_v().as_slice().to_vec(),
            s.homogeneous().to_vec(),
            me.units.symbol(),
            me.source.clone(),
            me.perpendiculars.map(|p| (p.aft, p.fore)),
        );
        Ok((f, state.into_pyobject(py)?.into_any()))
    }
}

/// Rebuild a pickled surface.
#[pyfunction]
pub fn _surface_from_state(
    degree: (usize, usize),
    knots_u: Vec<f64>,
    knots_v: Vec<f64>,
    homogeneous: Vec<[f64; 4]>,
    units: &str,
    source: String,
    perpendiculars: Option<(f64, f64)>,
) -> PyResult<PySurface> {
    let bad = |e: nurbs::NurbsError| bad_arg(format!("pickled surface: {e}"));
    let ku = KnotVector::try_new(degree.0, knots_u).map_err(bad)?;
    let kv = KnotVector::try_new(degree.1, knots_v).map_err(bad)?;
    let surface = NurbsSurface::try_from_homogeneous(ku, kv, homogeneous).map_err(bad)?;
    let perpendiculars = perpendiculars.map(crate::offsets::perpendiculars_of).transpose()?;
    Ok(PySurface { surface, units: options::units(units)?, source, perpendiculars })
}
