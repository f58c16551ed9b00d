//! Bindings of the spline family: constructors and one `Spline` class for all methods.

use crate::arrays::Count;
use crate::arrays::{guarded, keys_in, quats_of, rows_of, times_in, times_of, to_py, vec_of};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use quatspline::spline::{self as sp, Extrapolate, Frame, KeyEnds, TcbEnds};
use quatspline::{Error, Quat};
use rayon::prelude::*;
use std::sync::Arc;

/// Samples per parallel task; fewer than two tasks' worth run on the calling thread.
const CHUNK: usize = 4096;

/// Below this many samples a call runs on the calling thread with the GIL held.
const SMALL: usize = 256;

/// Any spline of the core, immutable after construction (safe to share between threads).
#[pyclass(name = "Spline", module = "quatspline._core", frozen)]
pub struct PySpline {
    inner: Arc<dyn sp::Spline>,
}

pub(crate) fn wrap(r: Result<impl sp::Spline + 'static, Error>) -> PyResult<PySpline> {
    r.map(|s| PySpline { inner: Arc::new(s) }).map_err(to_py)
}

impl PySpline {
    /// Wraps a core spline (for the other binding files).
    pub(crate) fn from_arc(inner: Arc<dyn sp::Spline>) -> Self {
        PySpline { inner }
    }

    /// The core spline (for the other binding files).
    pub(crate) fn arc(&self) -> Arc<dyn sp::Spline> {
        Arc::clone(&self.inner)
    }

    /// Fills an (M, width) array from t in parallel chunks with `f(t_chunk, first, out_chunk)`.
    fn batch<'py>(
        &self,
        py: Python<'py>,
        t: &Bound<'py, PyArray1<f64>>,
        width: usize,
        what: &str,
        f: impl Fn(&dyn sp::Spline, &[f64], usize, &mut [f64]) -> Result<(), Error> + Sync,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let m = t.len();
        if m < SMALL && t.is_contiguous() {
            // small calls: a copy of the times and a fresh output, no borrow tracking, no
            // `numpy.empty` lookup (each costs a fraction of a microsecond, more than the work)
            let mut tb = [0.0; SMALL];
            // SAFETY: contiguous, GIL held, copied at once (no reference outlives the copy).
            tb[..m].copy_from_slice(
                unsafe { t.as_slice() }.map_err(|e| PyRuntimeError::new_err(e.to_string()))?,
            );
            let out = PyArray2::<f64>::zeros(py, [m, width], false);
            // SAFETY: `out` was just created here; nothing else refers to it yet.
            let slice = unsafe { out.as_slice_mut() }.map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
            let s: &dyn sp::Spline = &*self.inner;
            crate::arrays::guarded_here(what, || f(s, &tb[..m], 0, slice))?;
            return Ok(out);
        }
        let t = t.readonly();
        // Every element is written before the array is returned; on error it is dropped.
        let out = crate::arrays::alloc2(py, m, width, what)?;
        self.batch_into(py, t, &out, width, what, f)?;
        Ok(out)
    }

    /// Like `batch`, into a caller-provided C-contiguous float64 (M, width) array.
    fn batch_into<'py>(
        &self,
        py: Python<'py>,
        t: PyReadonlyArray1<'py, f64>,
        out: &Bound<'py, PyArray2<f64>>,
        width: usize,
        what: &str,
        f: impl Fn(&dyn sp::Spline, &[f64], usize, &mut [f64]) -> Result<(), Error> + Sync,
    ) -> PyResult<()> {
        let tv = t.as_array();
        let owned;
        let ts: &[f64] = match tv.as_slice() {
            Some(s) => s,
            None => {
                owned = crate::arrays::try_vec(tv.len(), tv.iter().copied(), "t")?;
                &owned
            }
        };
        let m = ts.len();
        let dims = out.dims();
        if dims[0] != m || dims[1] != width {
            return Err(PyValueError::new_err(format!(
                "out: expected shape ({m}, {width}), got ({}, {})",
                dims[0], dims[1]
            )));
        }
        {
            let mut rw = out
                .try_readwrite()
                .map_err(|e| PyValueError::new_err(format!("out: not writeable ({e})")))?;
            let slice = rw.as_slice_mut().map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
            let s: &dyn sp::Spline = &*self.inner;
            if m < SMALL {
                // small calls: on this thread, GIL held (handing work to the pool or releasing
                // the GIL costs microseconds, more than the evaluation)
                return crate::arrays::guarded_here(what, || f(s, ts, 0, slice));
            }
            guarded(py, what, || {
                if m < 2 * CHUNK {
                    return f(s, ts, 0, slice);
                }
                let r = slice
                    .par_chunks_mut(CHUNK * width)
                    .zip(ts.par_chunks(CHUNK))
                    .enumerate()
                    .try_for_each(|(c, (o, tc))| f(s, tc, c * CHUNK, o));
                if r.is_err() {
                    // Report the first failing sample, whichever thread failed first.
                    let mut scratch = vec![0.0; width];
                    for (i, ti) in ts.iter().enumerate() {
                        f(s, std::slice::from_ref(ti), i, &mut scratch)?;
                    }
                }
                r
            })?;
        }
        Ok(())
    }
}

#[pymethods]
impl PySpline {
    /// Registry name of the method.
    #[getter]
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    /// (start, end) time.
    #[getter]
    fn domain(&self) -> (f64, f64) {
        self.inner.domain()
    }

    /// Joint times (segment boundaries, including both ends).
    #[getter]
    fn joints(&self) -> Vec<f64> {
        self.inner.joints().to_vec()
    }

    #[getter]
    fn interpolates(&self) -> bool {
        self.inner.interpolates()
    }

    /// Whether the curve is a closed loop (the certificate then includes the seam).
    #[getter]
    fn closed(&self) -> bool {
        self.inner.closed()
    }

    /// Guaranteed parametric continuity order at interior joints (255: a single C^∞ curve).
    #[getter]
    fn continuity(&self) -> u8 {
        self.inner.continuity()
    }

    /// (M, 4·(order+1)): q, q', …, q^(order) at each t.
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        t: &Bound<'py, PyArray1<f64>>,
        order: Count,
        extrapolate: &str,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let order = order.0;
        if order > 3 {
            return Err(PyValueError::new_err(format!("order: expected 0, 1, 2 or 3, got {order}")));
        }
        let ex: Extrapolate = extrapolate.parse().map_err(to_py)?;
        self.batch(py, t, 4 * (order + 1), "Spline.evaluate", move |s, tc, first, o| {
            sp::evaluate_into(s, tc, first, order, ex, o)
        })
    }

    /// Which kernel evaluates this spline now: "avx512", "avx2", "scalar" (batch kernels) or
    /// "jets"
    /// (the per-sample path: no batch kernel for this method, or reference mode).
    #[getter]
    fn kernel(&self) -> &'static str {
        match (self.inner.batch(), quatspline::simd::isa()) {
            (Some(_), Some(isa)) => isa.name(),
            _ => "jets",
        }
    }

    /// One sample's orientation (4,): the small-call fast path (no array in, no thread pool,
    /// no GIL release — for one sample those cost more than the evaluation).
    fn evaluate1<'py>(
        &self,
        py: Python<'py>,
        t: f64,
        extrapolate: &str,
    ) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
        let ex: Extrapolate = extrapolate.parse().map_err(to_py)?;
        let mut row = [0.0; 4];
        let s: &dyn sp::Spline = &*self.inner;
        crate::arrays::guarded_here("Spline.evaluate1", || sp::evaluate_into(s, &[t], 0, 0, ex, &mut row))?;
        Ok(numpy::PyArray1::from_slice(py, &row))
    }

    /// Like `evaluate`, into `out` (C-contiguous float64 of shape (M, 4·(order+1))).
    fn evaluate_out<'py>(
        &self,
        py: Python<'py>,
        t: PyReadonlyArray1<'py, f64>,
        order: Count,
        extrapolate: &str,
        out: &Bound<'py, PyArray2<f64>>,
    ) -> PyResult<()> {
        let order = order.0;
        if order > 3 {
            return Err(PyValueError::new_err(format!("order: expected 0, 1, 2 or 3, got {order}")));
        }
        let ex: Extrapolate = extrapolate.parse().map_err(to_py)?;
        self.batch_into(py, t, out, 4 * (order + 1), "Spline.evaluate", move |s, tc, first, o| {
            sp::evaluate_into(s, tc, first, order, ex, o)
        })
    }

    /// The straightforward scalar path (for tests): per sample, binary search and one segment
    /// evaluation, one thread, no cursor. (M, 4·(order+1)).
    fn evaluate_scalar<'py>(
        &self,
        py: Python<'py>,
        t: PyReadonlyArray1<'py, f64>,
        order: Count,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let order = order.0;
        let s = Arc::clone(&self.inner);
        let ta = t.as_array();
        let tv = crate::arrays::try_vec(ta.len(), ta.iter().copied(), "t")?;
        crate::arrays::fill_serial::<16>(py, "Spline.evaluate_scalar", tv.len(), move |i| {
            let ti = tv[i];
            let seg = s.locate(ti);
            let d = sp::derivatives_on(&*s, seg, ti, order);
            let mut row = [0.0; 16];
            for m in 0..=order.min(3) {
                row[4 * m..4 * m + 4].copy_from_slice(&d[m].to_wxyz());
            }
            Ok(row)
        })
    }

    /// (M, 3): angular velocity (order 1), acceleration (2) or jerk (3), world or body frame.
    fn angular<'py>(
        &self,
        py: Python<'py>,
        t: &Bound<'py, PyArray1<f64>>,
        order: Count,
        body: bool,
        extrapolate: &str,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let order = order.0;
        if !(1..=3).contains(&order) {
            return Err(PyValueError::new_err(format!("order: expected 1, 2 or 3, got {order}")));
        }
        let ex: Extrapolate = extrapolate.parse().map_err(to_py)?;
        let frame = if body { Frame::Body } else { Frame::World };
        self.batch(py, t, 3, "Spline.angular", move |s, tc, first, o| {
            sp::angular_into(s, tc, first, order, frame, ex, o)
        })
    }

    /// Continuity certificate: one tuple per interior joint
    /// (index, time, jump_abs[max(4, order+1)], jump_rel[…], order, g1_xi, g1_residual, g2_delta,
    /// g2_residual).
    #[allow(clippy::type_complexity)]
    fn continuity_report(
        &self,
        py: Python<'_>,
        order: Count,
        tol: f64,
    ) -> PyResult<Vec<(usize, f64, Vec<f64>, Vec<f64>, i32, f64, f64, f64, f64)>> {
        let order = order.0;
        let width = (order + 1).clamp(4, 6);
        let s = Arc::clone(&self.inner);
        let r = guarded(py, "continuity", move || Ok(quatspline::analysis::continuity(&*s, order, tol)))?;
        Ok(r.into_iter()
            .map(|j| {
                (
                    j.index,
                    j.time,
                    j.jump_abs[..width].to_vec(),
                    j.jump_rel[..width].to_vec(),
                    j.order,
                    j.g1_xi,
                    j.g1_residual,
                    j.g2_delta,
                    j.g2_residual,
                )
            })
            .collect())
    }

    /// Beta spline only: per interior joint (joint, g1[4], g2[4], theorem2[4], gamma, |s''|).
    #[allow(clippy::type_complexity)]
    fn beta_residuals(&self) -> Option<Vec<(usize, [f64; 4], [f64; 4], [f64; 4], f64, f64)>> {
        self.inner.beta_residuals().map(|v| {
            v.into_iter()
                .map(|b| {
                    (
                        b.joint,
                        b.g1.to_wxyz(),
                        b.g2.to_wxyz(),
                        b.theorem2.to_wxyz(),
                        b.gamma,
                        b.second_derivative,
                    )
                })
                .collect()
        })
    }

    /// Bézier control points per segment (l, 4, 4) where the method has them, else None.
    fn control_points(&self) -> Option<Vec<[[f64; 4]; 4]>> {
        self.inner.control_points().map(|v| v.into_iter().map(|c| c.map(Quat::to_wxyz)).collect())
    }

    /// (4, 4): q, q', q'', q''' of segment `seg` at time t (one-sided limits at joints).
    fn segment_derivatives<'py>(
        &self,
        py: Python<'py>,
        seg: Count,
        t: f64,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let seg = seg.0;
        if seg >= self.inner.segments() {
            return Err(PyValueError::new_err(format!(
                "seg: expected < {}, got {seg}",
                self.inner.segments()
            )));
        }
        let s = Arc::clone(&self.inner);
        let d = guarded(py, "Spline.segment_derivatives", move || Ok(s.segment_jet4(seg, t).derivatives()))?;
        let rows: Vec<Vec<f64>> = d.iter().map(|q| q.to_wxyz().to_vec()).collect();
        PyArray2::from_vec2(py, &rows).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    }
}

#[pyfunction]
#[pyo3(signature = (quats, times, canonicalize))]
fn piecewise_slerp(
    quats: PyReadonlyArray2<'_, f64>,
    times: Option<PyReadonlyArray1<'_, f64>>,
    canonicalize: bool,
) -> PyResult<PySpline> {
    let q = keys_in(&quats, "quats")?;
    wrap(sp::PiecewiseSlerp::new(&q, times_in(&times).as_deref(), canonicalize))
}

#[pyfunction]
fn spherical_bezier(
    control_points: PyReadonlyArray2<'_, f64>,
    domain: (f64, f64),
    canonicalize: bool,
) -> PyResult<PySpline> {
    let q = quats_of(&control_points, "control_points")?;
    wrap(sp::SphericalBezier::new(&q, domain, canonicalize))
}

#[pyfunction]
fn cumulative_bezier(
    control_points: PyReadonlyArray2<'_, f64>,
    domain: (f64, f64),
    canonicalize: bool,
) -> PyResult<PySpline> {
    let q = quats_of(&control_points, "control_points")?;
    wrap(sp::CumulativeBezier::new(&q, domain, canonicalize))
}

#[pyfunction]
#[pyo3(signature = (quats, times))]
fn nlerp_spline(
    quats: PyReadonlyArray2<'_, f64>,
    times: Option<PyReadonlyArray1<'_, f64>>,
) -> PyResult<PySpline> {
    let q = quats_of(&quats, "quats")?;
    wrap(sp::PiecewiseNlerp::new(&q, times_of(&times).as_deref()))
}

#[pyfunction]
#[pyo3(signature = (quats, times, seq))]
fn lin_euler_spline(
    quats: PyReadonlyArray2<'_, f64>,
    times: Option<PyReadonlyArray1<'_, f64>>,
    seq: &str,
) -> PyResult<PySpline> {
    let q = quats_of(&quats, "quats")?;
    wrap(sp::PiecewiseLinEuler::new(&q, times_of(&times).as_deref(), seq))
}

#[pyfunction]
#[pyo3(signature = (quats, times))]
fn lin_mat_spline(
    quats: PyReadonlyArray2<'_, f64>,
    times: Option<PyReadonlyArray1<'_, f64>>,
) -> PyResult<PySpline> {
    let q = quats_of(&quats, "quats")?;
    wrap(sp::PiecewiseLinMat::new(&q, times_of(&times).as_deref()))
}

/// Position, velocity, acceleration (M, 9) of the linear or natural cubic position spline
/// through `points` at `times`, at times `t` (inside the key range; the caller checks).
#[pyfunction]
fn position_eval<'py>(
    py: Python<'py>,
    times: PyReadonlyArray1<'py, f64>,
    points: PyReadonlyArray2<'py, f64>,
    cubic: bool,
    t: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let tk = vec_of(&times);
    let pts = rows_of::<3>(&points, "positions")?;
    let kind = if cubic {
        quatspline::translation::TranslationKind::Cubic
    } else {
        quatspline::translation::TranslationKind::Linear
    };
    let spline = quatspline::translation::PositionSpline::new(&tk, &pts, kind).map_err(to_py)?;
    let ta = t.as_array();
    let tv = crate::arrays::try_vec(ta.len(), ta.iter().copied(), "t")?;
    crate::arrays::fill(py, "position_eval", tv.len(), |i| {
        let ti = tv[i];
        let seg = tk.partition_point(|&x| x <= ti).saturating_sub(1).min(tk.len() - 2);
        let [p, v, a] = spline.eval(seg, ti);
        Ok([p[0], p[1], p[2], v[0], v[1], v[2], a[0], a[1], a[2]])
    })
}

/// Per segment (S, 3, 8): power-basis coefficients of the C³ spline's cumulative weights.
#[pyfunction]
#[pyo3(signature = (times, alpha, beta, variant))]
fn c3_weights(
    times: PyReadonlyArray1<'_, f64>,
    alpha: PyReadonlyArray1<'_, f64>,
    beta: PyReadonlyArray1<'_, f64>,
    variant: &str,
) -> PyResult<Vec<[[f64; 8]; 3]>> {
    let t = vec_of(&times);
    let variant: sp::C3Variant = variant.parse().map_err(to_py)?;
    let keys = vec![Quat::IDENTITY; t.len()];
    let s =
        sp::C3Spline::new(&keys, Some(&t), &vec_of(&alpha), &vec_of(&beta), variant, false).map_err(to_py)?;
    Ok(s.cumulative_weights())
}

#[pyfunction]
#[pyo3(signature = (quats, times, canonicalize, ends="open", holds=false))]
fn squad(
    quats: PyReadonlyArray2<'_, f64>,
    times: Option<PyReadonlyArray1<'_, f64>>,
    canonicalize: bool,
    ends: &str,
    holds: bool,
) -> PyResult<PySpline> {
    let q = keys_in(&quats, "quats")?;
    let ends = KeyEnds::for_method(ends, "squad").map_err(to_py)?;
    wrap(sp::Squad::with_keyframes(&q, times_in(&times).as_deref(), ends, holds, canonicalize))
}

#[pyfunction]
#[pyo3(signature = (quats, times, ends, canonicalize, alpha=None, holds=false))]
fn catmull_rom(
    quats: PyReadonlyArray2<'_, f64>,
    times: Option<PyReadonlyArray1<'_, f64>>,
    ends: &str,
    canonicalize: bool,
    alpha: Option<f64>,
    holds: bool,
) -> PyResult<PySpline> {
    let q = keys_in(&quats, "quats")?;
    let ends = TcbEnds::for_method(ends, "catmull_rom").map_err(to_py)?;
    wrap(sp::CatmullRom::with_keyframes(&q, times_in(&times).as_deref(), alpha, ends, holds, canonicalize))
}

#[pyfunction]
#[pyo3(signature = (control_quats, dt, t0, order, canonicalize, closed=false))]
fn cumulative_bspline(
    control_quats: PyReadonlyArray2<'_, f64>,
    dt: f64,
    t0: f64,
    order: Count,
    canonicalize: bool,
    closed: bool,
) -> PyResult<PySpline> {
    let order = order.0;
    let q = keys_in(&control_quats, "control_quats")?;
    wrap(sp::CumulativeBSpline::with_closed(&q, dt, t0, order, closed, canonicalize))
}

#[pyfunction]
#[pyo3(signature = (quats, times, ends, start_rate, end_rate, canonicalize, holds=false))]
fn natural_spline(
    quats: PyReadonlyArray2<'_, f64>,
    times: Option<PyReadonlyArray1<'_, f64>>,
    ends: &str,
    start_rate: Option<[f64; 3]>,
    end_rate: Option<[f64; 3]>,
    canonicalize: bool,
    holds: bool,
) -> PyResult<PySpline> {
    let q = keys_in(&quats, "quats")?;
    let ends =
        sp::NaturalEnds::for_method(ends, "the natural spline", start_rate, end_rate).map_err(to_py)?;
    wrap(sp::NaturalSpline::with_keyframes(&q, times_in(&times).as_deref(), ends, holds, canonicalize))
}

#[pyfunction]
#[pyo3(signature = (vertices, beta1, beta2, times, canonicalize))]
fn beta_spline(
    vertices: PyReadonlyArray2<'_, f64>,
    beta1: PyReadonlyArray1<'_, f64>,
    beta2: PyReadonlyArray1<'_, f64>,
    times: Option<PyReadonlyArray1<'_, f64>>,
    canonicalize: bool,
) -> PyResult<PySpline> {
    let q = keys_in(&vertices, "vertices")?;
    wrap(sp::BetaSpline::new(&q, &vec_of(&beta1), &vec_of(&beta2), times_in(&times).as_deref(), canonicalize))
}

#[pyfunction]
#[pyo3(signature = (quats, times, alpha, beta, variant, canonicalize, ends="open", holds=false))]
#[allow(clippy::too_many_arguments)]
fn c3_spline(
    quats: PyReadonlyArray2<'_, f64>,
    times: Option<PyReadonlyArray1<'_, f64>>,
    alpha: PyReadonlyArray1<'_, f64>,
    beta: PyReadonlyArray1<'_, f64>,
    variant: &str,
    canonicalize: bool,
    ends: &str,
    holds: bool,
) -> PyResult<PySpline> {
    let q = keys_in(&quats, "quats")?;
    let variant: sp::C3Variant = variant.parse().map_err(to_py)?;
    let ends = KeyEnds::for_method(ends, "c3").map_err(to_py)?;
    wrap(sp::C3Spline::with_keyframes(
        &q,
        times_in(&times).as_deref(),
        &vec_of(&alpha),
        &vec_of(&beta),
        variant,
        ends,
        holds,
        canonicalize,
    ))
}

/// Sets the number of threads for batch evaluation.
///
/// Large batches (more than one chunk of 4,096 samples) are spread over a thread pool with
/// the GIL released; small ones stay on the calling thread. Results do not depend on the
/// number of threads.
///
/// Parameters
/// ----------
/// n : int
///     Number of threads; 0 restores the default (one per core).
///
/// Raises
/// ------
/// OverflowError
///     If ``n`` is negative.
///
/// See Also
/// --------
/// get_num_threads
///
/// Examples
/// --------
/// >>> import quatspline as qs
/// >>> qs.set_num_threads(1)
/// >>> qs.get_num_threads()
/// 1
/// >>> qs.set_num_threads(0)  # back to one per core
#[pyfunction]
fn set_num_threads(n: Count) -> PyResult<()> {
    let n = n.0;
    crate::arrays::set_num_threads(n)
}

/// The number of threads batch evaluation uses.
///
/// Returns
/// -------
/// int
///     The size of the pool set by :func:`set_num_threads`, or the number of cores.
///
/// Examples
/// --------
/// >>> import quatspline as qs
/// >>> qs.get_num_threads() >= 1
/// True
#[pyfunction]
fn get_num_threads() -> usize {
    crate::arrays::num_threads()
}

/// Raises a deliberate panic inside the guarded path (tests that no panic reaches Python).
#[pyfunction]
fn _panic_for_test(py: Python<'_>) -> PyResult<()> {
    crate::arrays::guarded(py, "_panic_for_test", || -> Result<(), Error> { panic!("deliberate test panic") })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(set_num_threads, m)?)?;
    m.add_function(wrap_pyfunction!(get_num_threads, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_for_test, m)?)?;
    m.add_class::<PySpline>()?;
    m.add_function(wrap_pyfunction!(piecewise_slerp, m)?)?;
    m.add_function(wrap_pyfunction!(spherical_bezier, m)?)?;
    m.add_function(wrap_pyfunction!(cumulative_bezier, m)?)?;
    m.add_function(wrap_pyfunction!(squad, m)?)?;
    m.add_function(wrap_pyfunction!(catmull_rom, m)?)?;
    m.add_function(wrap_pyfunction!(cumulative_bspline, m)?)?;
    m.add_function(wrap_pyfunction!(natural_spline, m)?)?;
    m.add_function(wrap_pyfunction!(beta_spline, m)?)?;
    m.add_function(wrap_pyfunction!(nlerp_spline, m)?)?;
    m.add_function(wrap_pyfunction!(lin_euler_spline, m)?)?;
    m.add_function(wrap_pyfunction!(lin_mat_spline, m)?)?;
    m.add_function(wrap_pyfunction!(position_eval, m)?)?;
    m.add_function(wrap_pyfunction!(c3_weights, m)?)?;
    m.add_function(wrap_pyfunction!(c3_spline, m)?)?;
    Ok(())
}
