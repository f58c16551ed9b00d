//! Bindings of the evaluation engine's switches: the kernel mode and the vector sin/cos test
//! hook.

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use quatspline::simd::{self, Isa, Mode};

/// Sets the engine mode: "auto" (AVX2 where the CPU has it), "scalar" (portable kernels),
/// "reference" (the per-sample jet path).
#[pyfunction]
fn set_simd(mode: &str) -> PyResult<()> {
    let m = simd::parse_mode(mode).ok_or_else(|| {
        PyValueError::new_err(format!("mode: expected 'auto', 'scalar' or 'reference', got {mode:?}"))
    })?;
    simd::set_mode(m);
    Ok(())
}

/// (mode, kernel): the mode and the instruction set batch kernels run on now
/// ("avx2", "scalar", or "reference" when no batch kernel runs).
#[pyfunction]
fn simd_status() -> (&'static str, &'static str) {
    let m = match simd::mode() {
        Mode::Auto => "auto",
        Mode::Scalar => "scalar",
        Mode::Reference => "reference",
    };
    (m, simd::isa().map_or("reference", Isa::name))
}

type Pair<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

/// (sin x, cos x) by the engine's vector kernel for `isa` ("avx2" or "scalar"): test hook.
#[pyfunction]
fn _simd_sin_cos<'py>(py: Python<'py>, x: PyReadonlyArray1<'py, f64>, isa: &str) -> PyResult<Pair<'py>> {
    let isa = match isa {
        "avx2" if simd::avx2_available() => Isa::Avx2,
        "avx2" => return Err(PyValueError::new_err("isa: this CPU has no AVX2+FMA")),
        "scalar" => Isa::Scalar,
        _ => return Err(PyValueError::new_err(format!("isa: expected 'avx2' or 'scalar', got {isa:?}"))),
    };
    let xv: Vec<f64> = x.as_array().iter().copied().collect();
    let (mut s, mut c) = (vec![0.0; xv.len()], vec![0.0; xv.len()]);
    simd::sin_cos_slice(isa, &xv, &mut s, &mut c);
    Ok((PyArray1::from_vec(py, s), PyArray1::from_vec(py, c)))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(set_simd, m)?)?;
    m.add_function(wrap_pyfunction!(simd_status, m)?)?;
    m.add_function(wrap_pyfunction!(_simd_sin_cos, m)?)?;
    Ok(())
}
