//! Bindings of keyframe control: Hermite keys, Kochanek–Bartels, closed/rest ends.

use crate::arrays::{keys_in, quats_of, rows_of, times_in, times_of, to_py, vec_of};
use crate::spline::{wrap, PySpline};
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use quatspline::spline::{self as sp, Frame, KeyEnds, TcbEnds};

#[pyfunction]
#[pyo3(signature = (quats, times, angular_velocity, angular_acceleration, frame, ends, canonicalize, holds=false))]
#[allow(clippy::too_many_arguments)]
fn hermite(
    quats: PyReadonlyArray2<'_, f64>,
    times: Option<PyReadonlyArray1<'_, f64>>,
    angular_velocity: PyReadonlyArray2<'_, f64>,
    angular_acceleration: Option<PyReadonlyArray2<'_, f64>>,
    frame: &str,
    ends: &str,
    canonicalize: bool,
    holds: bool,
) -> PyResult<PySpline> {
    let q = quats_of(&quats, "quats")?;
    let w = rows_of::<3>(&angular_velocity, "angular_velocity")?;
    let a = angular_acceleration.as_ref().map(|a| rows_of::<3>(a, "angular_acceleration")).transpose()?;
    let frame: Frame = frame.parse().map_err(to_py)?;
    let ends = KeyEnds::for_method(ends, "hermite").map_err(to_py)?;
    let t = times_of(&times);
    wrap(sp::Hermite::with_keyframes(&q, t.as_deref(), &w, a.as_deref(), frame, ends, holds, canonicalize))
}

#[pyfunction]
#[pyo3(signature = (quats, times, alpha, tension, continuity, bias, ends, holds, canonicalize))]
#[allow(clippy::too_many_arguments)]
fn kochanek_bartels(
    quats: PyReadonlyArray2<'_, f64>,
    times: Option<PyReadonlyArray1<'_, f64>>,
    alpha: Option<f64>,
    tension: PyReadonlyArray1<'_, f64>,
    continuity: PyReadonlyArray1<'_, f64>,
    bias: PyReadonlyArray1<'_, f64>,
    ends: &str,
    holds: bool,
    canonicalize: bool,
) -> PyResult<PySpline> {
    let q = keys_in(&quats, "quats")?;
    let ends = TcbEnds::for_method(ends, "kochanek_bartels").map_err(to_py)?;
    let (t, c, b) = (vec_of(&tension), vec_of(&continuity), vec_of(&bias));
    let tcb = sp::Tcb { tension: &t, continuity: &c, bias: &b };
    wrap(sp::KochanekBartels::new(&q, times_in(&times).as_deref(), alpha, tcb, ends, holds, canonicalize))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(hermite, m)?)?;
    m.add_function(wrap_pyfunction!(kochanek_bartels, m)?)?;
    Ok(())
}
