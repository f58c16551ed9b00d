//! Bindings of the trajectory toolkit (issue 2.4): integrating angular velocity, non-uniform
//! B-splines, reparameterised and retimed splines, SE(3) splines. Conversions, shape checks,
//! GIL release and error mapping only.

use crate::arrays::Count;
use crate::arrays::{flat_array, guarded, quats_of, rows_of, times_of, to_array, to_py, vec_of};
use numpy::{PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use quatspline::integrate::{self, RateModel};
use quatspline::spline::Frame;
use quatspline::Quat;

/// Orientations (N, 4) from rates (N, 3) at times (N,), starting at q0.
#[pyfunction]
fn integrate_rates<'py>(
    py: Python<'py>,
    times: PyReadonlyArray1<'py, f64>,
    angular_velocity: PyReadonlyArray2<'py, f64>,
    q0: [f64; 4],
    frame: &str,
    method: &str,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let frame: Frame = frame.parse().map_err(to_py)?;
    let model: RateModel = method.parse().map_err(to_py)?;
    let t = vec_of(&times);
    let r = rows_of::<3>(&angular_velocity, "angular_velocity")?;
    let q = Quat::from_wxyz(q0);
    let out = guarded(py, "integrate", move || integrate::integrate(&t, &r, q, frame, model))?;
    to_array(py, out.into_iter().map(Quat::to_wxyz).collect())
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(integrate_rates, m)?)?;
    register_splines(m)
}

// ---- splines ---------------------------------------------------------------------------

use crate::spline::{wrap, PySpline};
use quatspline::spline::{self as sp};
use std::sync::Arc;

/// Non-uniform cumulative B-spline of order k with an explicit knot vector (n + k knots).
#[pyfunction]
fn nonuniform_bspline(
    control_quats: PyReadonlyArray2<'_, f64>,
    knots: PyReadonlyArray1<'_, f64>,
    order: Count,
    canonicalize: bool,
) -> PyResult<PySpline> {
    let order = order.0;
    let q = quats_of(&control_quats, "control_quats")?;
    wrap(sp::NonUniformBSpline::new(&q, &vec_of(&knots), order, canonicalize))
}

/// The spline on its arc-length clock (constant angular speed, same domain); also returns
/// the path length.
#[pyfunction]
fn arc_length_spline(py: Python<'_>, spline: &PySpline) -> PyResult<(PySpline, f64)> {
    let inner = spline.arc();
    let r = guarded(py, "reparameterize", move || sp::Reparameterized::arc_length(inner))?;
    let length = r.length();
    Ok((PySpline::from_arc(Arc::new(r)), length))
}

/// The spline with time stretched by `factor` about the start of its domain.
#[pyfunction]
fn time_scaled_spline(spline: &PySpline, factor: f64) -> PyResult<PySpline> {
    wrap(sp::Reparameterized::scaled(spline.arc(), factor))
}

/// (max |ω| or |dω/dt| or |d²ω/dt²|, time where reached) over the domain.
#[pyfunction]
fn max_rate(py: Python<'_>, spline: &PySpline, order: Count) -> PyResult<(f64, f64)> {
    let order = order.0;
    let inner = spline.arc();
    guarded(py, "max_rate", move || sp::max_rate(&*inner, order))
}

pub fn register_splines(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(nonuniform_bspline, m)?)?;
    m.add_function(wrap_pyfunction!(arc_length_spline, m)?)?;
    m.add_function(wrap_pyfunction!(time_scaled_spline, m)?)?;
    m.add_function(wrap_pyfunction!(max_rate, m)?)?;
    register_se3(m)
}

// ---- SE(3) splines -----------------------------------------------------------------------

use quatspline::se3::{self, PoseCurve};

/// A pose spline of the core (screw spline, pose B-spline): rotation part, dual part,
/// positions with derivatives, twists.
#[pyclass(name = "PoseCurve", module = "quatspline._core", frozen)]
pub struct PyPoseCurve {
    inner: Arc<dyn PoseCurve>,
}

#[pymethods]
impl PyPoseCurve {
    /// The rotation part as a Spline (all rotation features, certificate).
    fn rotation(&self) -> PySpline {
        let s: Arc<dyn sp::Spline> = self.inner.clone();
        PySpline::from_arc(s)
    }

    /// The dual part d(t) as a quaternion Spline (for the continuity certificate).
    fn dual_part(&self) -> PySpline {
        PySpline::from_arc(Arc::new(se3::DualPart(self.inner.clone())))
    }

    /// (M, 3·(order+1)): p, p', …, p^(order) at each t (world coordinates).
    fn positions<'py>(
        &self,
        py: Python<'py>,
        t: PyReadonlyArray1<'py, f64>,
        order: Count,
        extrapolate: &str,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let order = order.0;
        let ex: sp::Extrapolate = extrapolate.parse().map_err(to_py)?;
        if order > 3 {
            return Err(PyValueError::new_err(format!("order: expected 0, 1, 2 or 3, got {order}")));
        }
        let tv = vec_of(&t);
        let s = self.inner.clone();
        let w = 3 * (order + 1);
        let out = guarded(py, "positions", move || {
            let mut out = vec![0.0; tv.len() * w];
            se3::positions_into(&*s, &tv, order, ex, &mut out)?;
            Ok(out)
        })?;
        let n = out.len() / w;
        flat_array(py, out, n, w)
    }

    /// (M, 6): the body or spatial twist (order 1) or its time derivatives (2, 3).
    fn twists<'py>(
        &self,
        py: Python<'py>,
        t: PyReadonlyArray1<'py, f64>,
        order: Count,
        body: bool,
        extrapolate: &str,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let order = order.0;
        let ex: sp::Extrapolate = extrapolate.parse().map_err(to_py)?;
        let tv = vec_of(&t);
        let s = self.inner.clone();
        let out = guarded(py, "twists", move || {
            let mut out = vec![0.0; tv.len() * 6];
            se3::twists_into(&*s, &tv, order, body, ex, &mut out)?;
            Ok(out)
        })?;
        let n = out.len() / 6;
        flat_array(py, out, n, 6)
    }
}

fn pose_inputs(
    quats: &PyReadonlyArray2<'_, f64>,
    positions: &PyReadonlyArray2<'_, f64>,
    qname: &'static str,
) -> PyResult<(Vec<Quat>, Vec<[f64; 3]>)> {
    Ok((quats_of(quats, qname)?, rows_of::<3>(positions, "positions")?))
}

#[pyfunction]
#[pyo3(signature = (quats, positions, times, smooth, alpha, beta))]
fn screw_spline(
    quats: PyReadonlyArray2<'_, f64>,
    positions: PyReadonlyArray2<'_, f64>,
    times: Option<PyReadonlyArray1<'_, f64>>,
    smooth: bool,
    alpha: PyReadonlyArray1<'_, f64>,
    beta: PyReadonlyArray1<'_, f64>,
) -> PyResult<PyPoseCurve> {
    let (q, p) = pose_inputs(&quats, &positions, "quats")?;
    let t = times_of(&times);
    let s = se3::ScrewSpline::new(&q, &p, t.as_deref(), smooth, &vec_of(&alpha), &vec_of(&beta))
        .map_err(to_py)?;
    Ok(PyPoseCurve { inner: Arc::new(s) })
}

#[pyfunction]
fn pose_bspline(
    control_quats: PyReadonlyArray2<'_, f64>,
    positions: PyReadonlyArray2<'_, f64>,
    knots: PyReadonlyArray1<'_, f64>,
    order: Count,
    formulation: &str,
) -> PyResult<PyPoseCurve> {
    let order = order.0;
    let f: se3::PoseFormulation = formulation.parse().map_err(to_py)?;
    let (q, p) = pose_inputs(&control_quats, &positions, "control_quats")?;
    let s = se3::PoseBSpline::new(&q, &p, &vec_of(&knots), order, f).map_err(to_py)?;
    Ok(PyPoseCurve { inner: Arc::new(s) })
}

pub fn register_se3(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyPoseCurve>()?;
    m.add_function(wrap_pyfunction!(screw_spline, m)?)?;
    m.add_function(wrap_pyfunction!(pose_bspline, m)?)?;
    Ok(())
}
