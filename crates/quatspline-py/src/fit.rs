//! Bindings of the fitting solvers (`quatspline::fit`): argument conversion, GIL release,
//! error mapping, progress callbacks. Nothing else.

use crate::arrays::{guarded, quats_of, rows_of, times_of, to_py, vec_of};
use numpy::{IntoPyArray, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use quatspline::fit::{self, position, FitOptions, Knots, Penalty, Robust, Smoothing};
use quatspline::spline::NaturalEnds;

fn knots_of(spacing: Option<f64>, array: Option<PyReadonlyArray1<'_, f64>>) -> Knots {
    match (spacing, array) {
        (_, Some(a)) => Knots::Array(vec_of(&a)),
        (Some(h), None) => Knots::Spacing(h),
        (None, None) => Knots::Default,
    }
}

fn smoothing_of(s: Option<f64>) -> Smoothing {
    match s {
        None => Smoothing::Auto,
        Some(v) => Smoothing::Fixed(v),
    }
}

/// Calls the Python progress callable (if any) with (stage, iteration, step); an exception
/// raised by it (e.g. KeyboardInterrupt) cancels the fit.
fn reporter(cb: Option<Py<PyAny>>) -> impl FnMut(&str, usize, f64) -> bool + Send {
    move |stage, it, step| match &cb {
        None => true,
        Some(f) => Python::attach(|py| f.call1(py, (stage, it, step)).is_ok() && py.check_signals().is_ok()),
    }
}

/// The samples of a fit, converted once for every entry point that takes them (the fits and
/// the posteriors): times, values (`quats` (N, 4) as quaternions or `positions` (N, 3) as
/// rows, shape-checked by [`rows_of`] with the argument's name), the sample weights and the
/// fit's final IRLS weights. Lengths and values are checked by the core (one message each).
struct Samples<V> {
    t: Vec<f64>,
    v: Vec<V>,
    w: Option<Vec<f64>>,
    rw: Option<Vec<f64>>,
}

impl<V> Samples<V> {
    fn new(
        times: &PyReadonlyArray1<'_, f64>,
        values: PyResult<Vec<V>>,
        weights: Option<&PyReadonlyArray1<'_, f64>>,
        robust_weights: Option<&PyReadonlyArray1<'_, f64>>,
    ) -> PyResult<Self> {
        Ok(Samples { t: vec_of(times), v: values?, w: weights.map(vec_of), rw: robust_weights.map(vec_of) })
    }
}

impl Samples<quatspline::quat::Quat> {
    /// Orientation samples: `quats` (N, 4), w x y z.
    fn quats(
        times: &PyReadonlyArray1<'_, f64>,
        quats: &PyReadonlyArray2<'_, f64>,
        weights: Option<&PyReadonlyArray1<'_, f64>>,
        robust_weights: Option<&PyReadonlyArray1<'_, f64>>,
    ) -> PyResult<Self> {
        Samples::new(times, quats_of(quats, "quats"), weights, robust_weights)
    }
}

impl Samples<[f64; 3]> {
    /// Position samples: `positions` (N, 3).
    fn positions(
        times: &PyReadonlyArray1<'_, f64>,
        positions: &PyReadonlyArray2<'_, f64>,
        weights: Option<&PyReadonlyArray1<'_, f64>>,
        robust_weights: Option<&PyReadonlyArray1<'_, f64>>,
    ) -> PyResult<Self> {
        Samples::new(times, rows_of::<3>(positions, "positions"), weights, robust_weights)
    }
}

/// Orientation fit; returns a dict of the result fields.
#[pyfunction]
#[pyo3(signature = (times, quats, weights, penalty, order, smoothing, knots_spacing, knots_array,
                    robust, robust_scale, max_iter, tol, progress=None, adaptivity="gcv"))]
#[allow(clippy::too_many_arguments)]
fn fit_rotations<'py>(
    py: Python<'py>,
    times: PyReadonlyArray1<'py, f64>,
    quats: PyReadonlyArray2<'py, f64>,
    weights: Option<PyReadonlyArray1<'py, f64>>,
    penalty: &str,
    order: Option<usize>,
    smoothing: Option<f64>,
    knots_spacing: Option<f64>,
    knots_array: Option<PyReadonlyArray1<'py, f64>>,
    robust: Option<&str>,
    robust_scale: Option<f64>,
    max_iter: usize,
    tol: f64,
    progress: Option<Py<PyAny>>,
    adaptivity: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let mode = adaptivity.parse::<fit::Adaptivity>().map_err(to_py)?;
    let Samples { t, v: q, w, .. } = Samples::quats(&times, &quats, weights.as_ref(), None)?;
    let opts = FitOptions {
        penalty: penalty.parse::<Penalty>().map_err(to_py)?,
        order,
        smoothing: smoothing_of(smoothing),
        knots: knots_of(knots_spacing, knots_array),
        robust: robust.map_or(Ok(Robust::None), str::parse).map_err(to_py)?,
        robust_scale,
        max_iter,
        tol,
    };
    let mut rep = reporter(progress);
    let r = guarded(py, "fit", move || fit::fit_adaptive(&t, &q, w.as_deref(), &opts, mode, &mut rep))?;
    let d = PyDict::new(py);
    put_fit_result(py, &d, r)?;
    Ok(d)
}

/// The fields of a fit result common to every orientation fit, into `d`.
fn put_fit_result(py: Python<'_>, d: &Bound<'_, PyDict>, r: fit::FitResult) -> PyResult<()> {
    let ctrl: Vec<f64> = r.ctrl.iter().flat_map(|q| q.to_wxyz()).collect();
    d.set_item("ctrl", ctrl.into_pyarray(py).reshape([r.ctrl.len(), 4])?)?;
    d.set_item("dt", r.dt)?;
    d.set_item("t0", r.t0)?;
    d.set_item("order", r.order)?;
    let full = r.breaks.as_ref().map(|b| fit::layout::full_knots(b, r.order).into_pyarray(py));
    d.set_item("knots_full", full)?;
    d.set_item("breaks", r.breaks.as_ref().map(|b| b.clone().into_pyarray(py)))?;
    d.set_item("residuals", r.residuals.into_pyarray(py))?;
    d.set_item("robust_weights", r.robust_weights.into_pyarray(py))?;
    d.set_item("robust_scale", r.robust_scale)?;
    d.set_item("smoothing", r.lambda)?;
    d.set_item("smoothing_requested", r.lambda_requested)?;
    d.set_item("effective_dof", r.edf)?;
    d.set_item("score", r.score)?;
    d.set_item("iterations", r.iterations)?;
    d.set_item("final_step", r.final_step)?;
    d.set_item("converged", r.converged)?;
    d.set_item("penalty_weights", r.penalty_weights.map(|v| v.into_pyarray(py)))?;
    Ok(())
}

/// Gyro-aided orientation fit (`quatspline::fit::fit_gyro`); returns the dict of
/// `fit_rotations` plus the sensor parameters, their covariance and the gyro residuals.
#[pyfunction]
#[pyo3(signature = (times, quats, weights, gyro_times, gyro, penalty, order, smoothing, knots_spacing,
                    knots_array, max_iter, tol, sigma_gyro, sigma_orientation, estimate,
                    bias, time_offset, rotation, knots_per_sample=None, bandwidth=None, progress=None))]
#[allow(clippy::too_many_arguments)]
fn fit_rotations_gyro<'py>(
    py: Python<'py>,
    times: PyReadonlyArray1<'py, f64>,
    quats: PyReadonlyArray2<'py, f64>,
    weights: Option<PyReadonlyArray1<'py, f64>>,
    gyro_times: PyReadonlyArray1<'py, f64>,
    gyro: PyReadonlyArray2<'py, f64>,
    penalty: &str,
    order: Option<usize>,
    smoothing: Option<f64>,
    knots_spacing: Option<f64>,
    knots_array: Option<PyReadonlyArray1<'py, f64>>,
    max_iter: usize,
    tol: f64,
    sigma_gyro: f64,
    sigma_orientation: f64,
    estimate: Vec<String>,
    bias: [f64; 3],
    time_offset: f64,
    rotation: [f64; 4],
    knots_per_sample: Option<f64>,
    bandwidth: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let Samples { t, v: q, w, .. } = Samples::quats(&times, &quats, weights.as_ref(), None)?;
    let gt = vec_of(&gyro_times);
    let gw = rows_of::<3>(&gyro, "gyro")?;
    let opts = FitOptions {
        penalty: penalty.parse::<Penalty>().map_err(to_py)?,
        order,
        smoothing: smoothing_of(smoothing),
        knots: knots_of(knots_spacing, knots_array),
        robust: Robust::None,
        robust_scale: None,
        max_iter,
        tol,
    };
    let est = fit::Estimate::parse(estimate.iter().map(String::as_str)).map_err(to_py)?;
    let gopts = fit::GyroOptions {
        sigma_gyro,
        sigma_orientation,
        estimate: est,
        start: fit::Sensor {
            bias,
            time_offset,
            rotation: quatspline::quat::Quat::from_wxyz(rotation).normalize(),
            scale: [0.0; 3],
        },
        knots_per_sample: knots_per_sample.unwrap_or(fit::GyroOptions::default().knots_per_sample),
        bandwidth: bandwidth.unwrap_or(fit::GyroOptions::default().bandwidth),
    };
    let mut rep = reporter(progress);
    let r =
        guarded(py, "fit", move || fit::fit_gyro(&t, &q, w.as_deref(), &gt, &gw, &opts, &gopts, &mut rep))?;
    let d = PyDict::new(py);
    put_fit_result(py, &d, r.fit)?;
    let names = r.estimate.names();
    let np = names.len();
    d.set_item("gyro_parameters", names)?;
    d.set_item("gyro_covariance", r.covariance.into_pyarray(py).reshape([np, np])?)?;
    d.set_item("gyro_bias", r.sensor.bias.to_vec().into_pyarray(py))?;
    d.set_item("time_offset", r.sensor.time_offset)?;
    d.set_item("sensor_rotation", r.sensor.rotation.to_wxyz().to_vec().into_pyarray(py))?;
    d.set_item("gyro_scale", r.sensor.scale.to_vec().into_pyarray(py))?;
    let n = r.gyro_residuals.len();
    let res: Vec<f64> = r.gyro_residuals.into_iter().flatten().collect();
    d.set_item("gyro_residuals", res.into_pyarray(py).reshape([n, 3])?)?;
    d.set_item("gyro_weight", r.gyro_weight)?;
    Ok(d)
}

/// Minimum-jerk interpolation (B-spline form); returns the same dict as `fit_rotations`.
#[pyfunction]
#[pyo3(signature = (times, quats, penalty, resolution, progress=None))]
fn min_energy<'py>(
    py: Python<'py>,
    times: PyReadonlyArray1<'py, f64>,
    quats: PyReadonlyArray2<'py, f64>,
    penalty: &str,
    resolution: crate::arrays::Count,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let resolution = resolution.0;
    let t = vec_of(&times);
    let q = quats_of(&quats, "quats")?;
    let pen = penalty.parse::<Penalty>().map_err(to_py)?;
    let mut rep = reporter(progress);
    let r = guarded(py, "MinimumEnergySpline", move || {
        fit::min_energy::min_energy_bspline(&t, &q, pen, resolution, &mut rep)
    })?;
    let d = PyDict::new(py);
    let ctrl: Vec<f64> = r.ctrl.iter().flat_map(|q| q.to_wxyz()).collect();
    d.set_item("ctrl", ctrl.into_pyarray(py).reshape([r.ctrl.len(), 4])?)?;
    d.set_item("dt", r.dt)?;
    d.set_item("t0", r.t0)?;
    d.set_item("order", r.order)?;
    d.set_item("residuals", r.residuals.into_pyarray(py))?;
    d.set_item("iterations", r.iterations)?;
    d.set_item("final_step", r.final_step)?;
    Ok(d)
}

/// Minimum-∫|ω̇|² interpolation: the natural spline times Exp(δ) (`fit/min_energy.rs`);
/// returns (spline, {energy, energy_natural, iterations, converged, gradient_norm}).
#[pyfunction]
#[pyo3(signature = (quats, times, ends, start_rate, end_rate, resolution, progress=None))]
#[allow(clippy::too_many_arguments)]
fn min_energy_spline<'py>(
    py: Python<'py>,
    quats: PyReadonlyArray2<'py, f64>,
    times: Option<PyReadonlyArray1<'py, f64>>,
    ends: &str,
    start_rate: Option<[f64; 3]>,
    end_rate: Option<[f64; 3]>,
    resolution: crate::arrays::Count,
    progress: Option<Py<PyAny>>,
) -> PyResult<(crate::spline::PySpline, Bound<'py, PyDict>)> {
    let resolution = resolution.0;
    let q = quats_of(&quats, "quats")?;
    let t = times_of(&times);
    let ends =
        NaturalEnds::for_method(ends, "the minimum-energy spline", start_rate, end_rate).map_err(to_py)?;
    let mut rep = reporter(progress);
    let s = guarded(py, "MinimumEnergySpline", move || {
        fit::min_energy::MinEnergySpline::new(&q, t.as_deref(), ends, resolution, &mut rep)
    })?;
    let d = PyDict::new(py);
    d.set_item("energy", s.energy)?;
    d.set_item("energy_natural", s.energy_natural)?;
    d.set_item("iterations", s.iterations)?;
    d.set_item("converged", s.converged)?;
    d.set_item("gradient_norm", s.gradient_norm)?;
    d.set_item("jacobian_passes", s.jacobian_passes)?;
    Ok((crate::spline::wrap(Ok(s))?, d))
}

/// The exact minimum-∫|ω̇|² interpolant, the Riemannian cubic spline
/// (`fit/riemannian_cubic.rs`); returns (spline, {energy, energy_natural, iterations, residual}).
#[pyfunction]
#[pyo3(signature = (quats, times, ends, start_rate, end_rate, progress=None))]
fn riemannian_cubic_spline<'py>(
    py: Python<'py>,
    quats: PyReadonlyArray2<'py, f64>,
    times: Option<PyReadonlyArray1<'py, f64>>,
    ends: &str,
    start_rate: Option<[f64; 3]>,
    end_rate: Option<[f64; 3]>,
    progress: Option<Py<PyAny>>,
) -> PyResult<(crate::spline::PySpline, Bound<'py, PyDict>)> {
    let q = quats_of(&quats, "quats")?;
    let t = times_of(&times);
    let ends =
        NaturalEnds::for_method(ends, "the minimum-energy spline", start_rate, end_rate).map_err(to_py)?;
    let mut rep = reporter(progress);
    let s = guarded(py, "MinimumEnergySpline", move || {
        fit::riemannian_cubic::RiemannianCubic::new(&q, t.as_deref(), ends, &mut rep)
    })?;
    let d = PyDict::new(py);
    d.set_item("energy", s.energy)?;
    d.set_item("energy_natural", s.energy_natural)?;
    d.set_item("iterations", s.iterations)?;
    d.set_item("residual", s.residual)?;
    Ok((crate::spline::wrap(Ok(s))?, d))
}

/// Position fit; returns a dict (ctrl (n, 3), dt, t0, order, residuals, robust_weights,
/// smoothing, effective_dof, score, iterations).
#[pyfunction]
#[pyo3(signature = (times, positions, weights, penalty, order, smoothing, knots_spacing,
                    knots_array, robust, robust_scale))]
#[allow(clippy::too_many_arguments)]
fn fit_positions<'py>(
    py: Python<'py>,
    times: PyReadonlyArray1<'py, f64>,
    positions: PyReadonlyArray2<'py, f64>,
    weights: Option<PyReadonlyArray1<'py, f64>>,
    penalty: &str,
    order: Option<usize>,
    smoothing: Option<f64>,
    knots_spacing: Option<f64>,
    knots_array: Option<PyReadonlyArray1<'py, f64>>,
    robust: Option<&str>,
    robust_scale: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let Samples { t, v: x, w, .. } = Samples::positions(&times, &positions, weights.as_ref(), None)?;
    let pen = penalty.parse::<Penalty>().map_err(to_py)?;
    let rob = robust.map_or(Ok(Robust::None), str::parse).map_err(to_py)?;
    let knots = knots_of(knots_spacing, knots_array);
    let sm = smoothing_of(smoothing);
    let r = guarded(py, "fit (positions)", move || {
        position::fit_positions(&t, &x, w.as_deref(), pen, order, sm, &knots, rob, robust_scale)
    })?;
    let d = PyDict::new(py);
    let ctrl: Vec<f64> = r.ctrl.iter().flat_map(|p| p.iter().copied()).collect();
    d.set_item("ctrl", ctrl.into_pyarray(py).reshape([r.ctrl.len(), 3])?)?;
    d.set_item("dt", r.dt)?;
    d.set_item("t0", r.t0)?;
    d.set_item("order", r.order)?;
    d.set_item("breaks", r.breaks.map(|b| b.into_pyarray(py)))?;
    d.set_item("residuals", r.residuals.into_pyarray(py))?;
    d.set_item("robust_weights", r.robust_weights.into_pyarray(py))?;
    d.set_item("smoothing", r.lambda)?;
    d.set_item("smoothing_requested", r.lambda_requested)?;
    d.set_item("effective_dof", r.edf)?;
    d.set_item("score", r.score)?;
    d.set_item("iterations", r.iterations)?;
    Ok(d)
}

/// (M, 12): p, p', p'', p''' of a position B-spline at t (uniform, or on `breaks`).
#[pyfunction]
#[pyo3(signature = (ctrl, dt, t0, order, t, breaks=None))]
fn position_bspline_eval<'py>(
    py: Python<'py>,
    ctrl: PyReadonlyArray2<'py, f64>,
    dt: f64,
    t0: f64,
    order: usize,
    t: PyReadonlyArray1<'py, f64>,
    breaks: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
    let breaks = breaks.map(|b| vec_of(&b));
    let c = rows_of::<3>(&ctrl, "ctrl")?;
    if !(2..=fit::model::MAXK).contains(&order) || c.len() < order {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "order: expected 2 … {} with at least order control points, got order {order} and {} points",
            fit::model::MAXK,
            c.len()
        )));
    }
    let tv = vec_of(&t);
    let m = tv.len();
    let out = guarded(py, "position_bspline_eval", move || {
        let mut out = vec![0.0; 12 * m];
        position::evaluate(&c, dt, t0, order, breaks.as_deref(), &tv, &mut out)?;
        Ok(out)
    })?;
    out.into_pyarray(py).reshape([m, 12])
}

// ---- posterior covariance ------------------------------------------------------------------

/// The posterior of an orientation fit (`quatspline::fit::Posterior`): the band of H⁻¹ and σ̂²,
/// built once, evaluated at any times.
#[pyclass(name = "FitPosterior", module = "quatspline._core", frozen)]
pub struct PyFitPosterior {
    inner: std::sync::Arc<fit::Posterior>,
}

#[pymethods]
impl PyFitPosterior {
    /// (M, 3, 3): the covariance of `quantity` ("orientation" or "angular_velocity") in
    /// `frame` ("body" or "world") at each t (inside the domain).
    fn covariance<'py>(
        &self,
        py: Python<'py>,
        t: PyReadonlyArray1<'py, f64>,
        quantity: &str,
        frame: &str,
    ) -> PyResult<Bound<'py, numpy::PyArray3<f64>>> {
        let what: fit::Quantity = quantity.parse().map_err(to_py)?;
        let fr: quatspline::Frame = frame.parse().map_err(to_py)?;
        let tv = vec_of(&t);
        let m = tv.len();
        let post = self.inner.clone();
        let out = guarded(py, "covariance", move || post.covariances(&tv, what, fr))?;
        out.into_pyarray(py).reshape([m, 3, 3])
    }
    #[getter]
    fn sigma2(&self) -> f64 {
        self.inner.sigma2
    }
    #[getter]
    fn effective_dof(&self) -> f64 {
        self.inner.edf
    }
    #[getter]
    fn observations(&self) -> f64 {
        self.inner.nobs
    }
}

/// The posterior of an orientation fit to `quats` at `times` (the fit's own data, weights and
/// final IRLS weights; its controls, layout, penalty and λ).
#[pyfunction]
#[pyo3(signature = (times, quats, weights, robust_weights, ctrl, dt, t0, order, breaks, penalty, smoothing, penalty_weights=None))]
#[allow(clippy::too_many_arguments)]
fn fit_posterior<'py>(
    py: Python<'py>,
    times: PyReadonlyArray1<'py, f64>,
    quats: PyReadonlyArray2<'py, f64>,
    weights: Option<PyReadonlyArray1<'py, f64>>,
    robust_weights: Option<PyReadonlyArray1<'py, f64>>,
    ctrl: PyReadonlyArray2<'py, f64>,
    dt: f64,
    t0: f64,
    order: crate::arrays::Count,
    breaks: Option<PyReadonlyArray1<'py, f64>>,
    penalty: &str,
    smoothing: f64,
    penalty_weights: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<PyFitPosterior> {
    let Samples { t, v: q, w, rw } =
        Samples::quats(&times, &quats, weights.as_ref(), robust_weights.as_ref())?;
    let c = quats_of(&ctrl, "ctrl")?;
    let br = breaks.as_ref().map(vec_of);
    let pw = penalty_weights.as_ref().map(vec_of);
    let pen = penalty.parse::<Penalty>().map_err(to_py)?;
    let order = order.0;
    let post = guarded(py, "covariance", move || {
        let lay = fit::fitted_layout(c.len(), dt, t0, order, br.as_deref())?;
        fit::Posterior::new(&t, &q, w.as_deref(), rw.as_deref(), c, lay, pen, smoothing, pw.as_deref())
    })?;
    Ok(PyFitPosterior { inner: std::sync::Arc::new(post) })
}

/// The posterior of a position fit (`quatspline::fit::position::PositionPosterior`).
#[pyclass(name = "PositionPosterior", module = "quatspline._core", frozen)]
pub struct PyPositionPosterior {
    inner: std::sync::Arc<position::PositionPosterior>,
}

#[pymethods]
impl PyPositionPosterior {
    /// (M,): the variance of each coordinate of p(t) (derivative 0) or p'(t) (1) at each t.
    fn variances<'py>(
        &self,
        py: Python<'py>,
        t: PyReadonlyArray1<'py, f64>,
        derivative: crate::arrays::Count,
    ) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
        let tv = vec_of(&t);
        let post = self.inner.clone();
        let d = derivative.0;
        let out = guarded(py, "position_covariance", move || post.variances(&tv, d))?;
        Ok(out.into_pyarray(py))
    }
    #[getter]
    fn sigma2(&self) -> f64 {
        self.inner.sigma2
    }
    #[getter]
    fn effective_dof(&self) -> f64 {
        self.inner.edf
    }
}

/// The posterior of a position fit (the fit's data, weights, IRLS weights, controls, layout,
/// penalty and λ).
#[pyfunction]
#[pyo3(signature = (times, positions, weights, robust_weights, ctrl, dt, t0, order, breaks, penalty, smoothing))]
#[allow(clippy::too_many_arguments)]
fn position_posterior<'py>(
    py: Python<'py>,
    times: PyReadonlyArray1<'py, f64>,
    positions: PyReadonlyArray2<'py, f64>,
    weights: Option<PyReadonlyArray1<'py, f64>>,
    robust_weights: Option<PyReadonlyArray1<'py, f64>>,
    ctrl: PyReadonlyArray2<'py, f64>,
    dt: f64,
    t0: f64,
    order: crate::arrays::Count,
    breaks: Option<PyReadonlyArray1<'py, f64>>,
    penalty: &str,
    smoothing: f64,
) -> PyResult<PyPositionPosterior> {
    let Samples { t, v: x, w, rw } =
        Samples::positions(&times, &positions, weights.as_ref(), robust_weights.as_ref())?;
    let c = rows_of::<3>(&ctrl, "ctrl")?;
    let br = breaks.as_ref().map(vec_of);
    let pen = penalty.parse::<Penalty>().map_err(to_py)?;
    let order = order.0;
    let post = guarded(py, "position_covariance", move || {
        let lay = fit::fitted_layout(c.len(), dt, t0, order, br.as_deref())?;
        position::PositionPosterior::new(&t, &x, w.as_deref(), rw.as_deref(), &c, lay, pen, smoothing)
    })?;
    Ok(PyPositionPosterior { inner: std::sync::Arc::new(post) })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyFitPosterior>()?;
    m.add_class::<PyPositionPosterior>()?;
    m.add_function(wrap_pyfunction!(fit_posterior, m)?)?;
    m.add_function(wrap_pyfunction!(position_posterior, m)?)?;
    m.add_function(wrap_pyfunction!(fit_rotations, m)?)?;
    m.add_function(wrap_pyfunction!(fit_rotations_gyro, m)?)?;
    m.add_function(wrap_pyfunction!(fit_positions, m)?)?;
    m.add_function(wrap_pyfunction!(min_energy, m)?)?;
    m.add_function(wrap_pyfunction!(min_energy_spline, m)?)?;
    m.add_function(wrap_pyfunction!(riemannian_cubic_spline, m)?)?;
    m.add_function(wrap_pyfunction!(position_bspline_eval, m)?)?;
    Ok(())
}
