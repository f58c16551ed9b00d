//! Argument checks shared with the Python layer, so that it reports exactly the core's
//! messages (one definition of what a valid time vector is).

use crate::arrays::to_py;
use numpy::PyReadonlyArray1;
use pyo3::prelude::*;

/// Checks key times as every spline constructor does: `n` finite, strictly increasing values,
/// spacing and magnitude within the supported range. Raises the core's `ValueError`.
#[pyfunction]
fn check_times(times: PyReadonlyArray1<'_, f64>, n: usize) -> PyResult<()> {
    let a = times.as_array();
    let t = crate::arrays::try_vec(a.len(), a.iter().copied(), "times")?;
    quatspline::spline::prepare_times(Some(&t), n).map(|_| ()).map_err(to_py)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(check_times, m)?)?;
    Ok(())
}
