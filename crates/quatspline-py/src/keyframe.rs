//! Bindings of keyframe control: Hermite keys, Kochanek–Bartels, closed/rest ends.

use crate::arrays::{to_py, Rows};
use crate::spline::{quats_of, times_of, wrap, PySpline};
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use quatspline::spline::{self as sp, Frame, KeyEnds};

/// Parses `ends` among the names a method accepts (the error lists them).
pub(crate) fn key_ends(ends: &str, method: &str, supported: &[&str]) -> PyResult<KeyEnds> {
    let e = match ends {
        "open" => KeyEnds::Open,
        "rest" => KeyEnds::Rest,
        "closed" => KeyEnds::Closed,
        _ => KeyEnds::Open,
    };
    if !supported.contains(&ends) {
        return Err(PyValueError::new_err(format!(
            "ends: {method} does not support {ends:?}; supported: {}",
            supported.join(", ")
        )));
    }
    Ok(e)
}

fn vectors(a: &PyReadonlyArray2<'_, f64>, name: &'static str) -> PyResult<Vec<[f64; 3]>> {
    let rows = Rows::new(a, name, 3)?;
    Ok((0..rows.len()).map(|i| rows.row::<3>(i)).collect())
}

fn frame_of(frame: &str) -> PyResult<Frame> {
    match frame {
        "world" => Ok(Frame::World),
        "body" => Ok(Frame::Body),
        other => Err(PyValueError::new_err(format!("frame: expected \"world\" or \"body\", got {other:?}"))),
    }
}

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
    let w = vectors(&angular_velocity, "angular_velocity")?;
    let a = angular_acceleration.as_ref().map(|a| vectors(a, "angular_acceleration")).transpose()?;
    let frame = frame_of(frame)?;
    let ends = key_ends(ends, "hermite", &["open", "rest", "closed"])?;
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
    let q = quats_of(&quats, "quats")?;
    let ends = sp::tcb_ends(ends, "kochanek_bartels").map_err(to_py)?;
    let (t, c, b) = (vec_of(&tension), vec_of(&continuity), vec_of(&bias));
    let tcb = sp::Tcb { tension: &t, continuity: &c, bias: &b };
    wrap(sp::KochanekBartels::new(&q, times_of(&times).as_deref(), alpha, tcb, ends, holds, canonicalize))
}

fn vec_of(a: &PyReadonlyArray1<'_, f64>) -> Vec<f64> {
    a.as_array().iter().copied().collect()
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(hermite, m)?)?;
    m.add_function(wrap_pyfunction!(kochanek_bartels, m)?)?;
    Ok(())
}
