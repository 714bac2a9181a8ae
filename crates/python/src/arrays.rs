//! NumPy arrays in and out: arguments converted to `float64` and checked (shape, finite
//! values) with a `TypeError` or `ValueError` naming the argument; results built as arrays.

use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{IntoPyArray, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use nurbs::Vec3;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use rayon::prelude::*;

use crate::errors::bad_arg;

/// `obj` as a C-contiguous `float64` array: its shape and values. A `TypeError` when NumPy
/// cannot make numbers of it.
pub fn floats(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<usize>, Vec<f64>)> {
    let arr = float_array(obj, name)?;
    let ro = arr.readonly();
    Ok((ro.shape().to_vec(), slice(&ro, name)?.to_vec()))
}

/// [`floats`] with every value finite (a `ValueError` naming the first NaN or infinity).
pub fn finite_floats(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<usize>, Vec<f64>)> {
    let (shape, values) = floats(obj, name)?;
    if let Some(i) = values.iter().position(|x| !x.is_finite()) {
        return Err(bad_arg(format!(
            "{name}: value {} at flat index {i} is not finite (expected finite numbers)",
            values[i]
        )));
    }
    Ok((shape, values))
}

/// Points given as an array of shape `(n, 3)` (or one point, `(3,)`), finite.
pub fn points(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<Vec3>> {
    let (shape, values) = finite_floats(obj, name)?;
    match shape.as_slice() {
        [3] | [_, 3] => Ok(values.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect()),
        s => Err(bad_arg(format!("{name}: shape {s:?}, expected (n, 3) points"))),
    }
}

/// The parameters `u` and `v` of an evaluation: arrays of one shape, or one of them a scalar
/// (broadcast to the other's shape); finite. Returns the shape and the pairs.
pub fn parameters(u: &Bound<'_, PyAny>, v: &Bound<'_, PyAny>) -> PyResult<(Vec<usize>, Vec<(f64, f64)>)> {
    let (su, us) = finite_floats(u, "u")?;
    let (sv, vs) = finite_floats(v, "v")?;
    let pairs = if su == sv {
        us.into_iter().zip(vs).collect()
    } else if su.is_empty() {
        vs.into_iter().map(|v| (us[0], v)).collect()
    } else if sv.is_empty() {
        us.into_iter().map(|u| (u, vs[0])).collect()
    } else {
        return Err(bad_arg(format!("u has shape {su:?} and v {sv:?}: expected one shape, or one of them a scalar")));
    };
    Ok((if su.is_empty() { sv } else { su }, pairs))
}

/// Evaluate `f` at every pair of `u`, `v` (arrays of one shape, or one a scalar; finite),
/// without the GIL and in parallel, writing its `K` values per pair straight into a new
/// array of shape `shape + (K,)`: no copy of the parameters nor of the results.
pub fn map_pairs<'py, const K: usize>(
    py: Python<'py>,
    u: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
    f: impl Fn(f64, f64) -> [f64; K] + Sync,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let ua = float_array(u, "u")?;
    let va = float_array(v, "v")?;
    let (ur, vr) = (ua.readonly(), va.readonly());
    let (su, sv) = (ur.shape().to_vec(), vr.shape().to_vec());
    let (us, vs) = (slice(&ur, "u")?, slice(&vr, "v")?);
    let shape = if su == sv || sv.is_empty() {
        su
    } else if su.is_empty() {
        sv
    } else {
        return Err(bad_arg(format!("u has shape {su:?} and v {sv:?}: expected one shape, or one of them a scalar")));
    };
    for (name, xs) in [("u", us), ("v", vs)] {
        if let Some(i) = xs.iter().position(|x| !x.is_finite()) {
            return Err(bad_arg(format!(
                "{name}: value {} at flat index {i} is not finite (expected finite numbers)",
                xs[i]
            )));
        }
    }
    let n: usize = shape.iter().product();
    let mut out_shape = shape;
    out_shape.push(K);
    let out = PyArrayDyn::<f64>::zeros(py, IxDyn(&out_shape), false);
    {
        let mut rw = out.readwrite();
        let dst = rw.as_slice_mut().map_err(|e| bad_arg(format!("output array: {e}")))?;
        // A scalar is repeated over the other's blocks.
        fn block(xs: &[f64], c: usize, len: usize) -> std::borrow::Cow<'_, [f64]> {
            if xs.len() == 1 {
                std::borrow::Cow::Owned(vec![xs[0]; len])
            } else {
                std::borrow::Cow::Borrowed(&xs[c * CHUNK..c * CHUNK + len])
            }
        }
        py.detach(|| {
            dst.par_chunks_mut(K * CHUNK).enumerate().for_each(|(c, out)| {
                let len = out.len() / K;
                let (bu, bv) = (block(us, c, len), block(vs, c, len));
                for ((cell, &u), &v) in out.chunks_exact_mut(K).zip(bu.iter()).zip(bv.iter()) {
                    cell.copy_from_slice(&f(u, v));
                }
            });
        });
        debug_assert_eq!(dst.len(), n * K);
    }
    Ok(out)
}

/// Pairs per parallel task of [`map_pairs`].
const CHUNK: usize = 4096;

/// `obj` as a C-contiguous `float64` array (NumPy converts; a `TypeError` when it cannot).
fn float_array<'py>(obj: &Bound<'py, PyAny>, name: &str) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let np = obj.py().import("numpy")?;
    let arr = np.call_method1("asarray", (obj, "float64", "C")).map_err(|e| {
        PyTypeError::new_err(format!("{name}: expected numbers (a float, a sequence or a NumPy array), got {e}"))
    })?;
    arr.cast_into::<PyArrayDyn<f64>>()
        .map_err(|_| PyTypeError::new_err(format!("{name}: expected an array of float64")))
}

fn slice<'a>(a: &'a numpy::PyReadonlyArrayDyn<'_, f64>, name: &str) -> PyResult<&'a [f64]> {
    a.as_slice().map_err(|e| PyTypeError::new_err(format!("{name}: {e}")))
}

/// An array of `shape` from `values` (as many as the shape holds).
pub fn array<'py, T: numpy::Element>(
    py: Python<'py>,
    shape: &[usize],
    values: Vec<T>,
) -> PyResult<Bound<'py, PyArrayDyn<T>>> {
    let a = ArrayD::from_shape_vec(IxDyn(shape), values).map_err(|e| bad_arg(format!("internal shape error: {e}")))?;
    Ok(a.into_pyarray(py))
}

/// Points as an array of `shape + (3,)`.
pub fn vec3s<'py>(py: Python<'py>, shape: &[usize], pts: &[Vec3]) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let mut s = shape.to_vec();
    s.push(3);
    array(py, &s, pts.iter().flat_map(|p| [p.x, p.y, p.z]).collect())
}
