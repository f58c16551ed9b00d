//! Bindings of the evaluation engine's switches: the kernel mode and the vector sin/cos test
//! hook.

use crate::arrays::{to_py, vec_of};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use quatspline::simd::{self, Isa, Mode};

/// Sets the engine mode: "auto" (AVX-512, else AVX2, where the CPU has it), "avx512" / "avx2"
/// (at most that instruction set), "scalar" (portable kernels), "reference" (the per-sample
/// jet path).
#[pyfunction]
fn set_simd(mode: &str) -> PyResult<()> {
    simd::set_mode(mode.parse::<Mode>().map_err(to_py)?);
    Ok(())
}

/// (mode, kernel): the mode and the instruction set batch kernels run on now
/// ("avx512", "avx2", "scalar", or "reference" when no batch kernel runs).
#[pyfunction]
fn simd_status() -> (&'static str, &'static str) {
    (simd::mode().name(), simd::isa().map_or("reference", Isa::name))
}

type Pair<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

/// (sin x, cos x) by the engine's vector kernel for `isa` ("avx512", "avx2" or "scalar"):
/// test hook.
#[pyfunction]
fn _simd_sin_cos<'py>(py: Python<'py>, x: PyReadonlyArray1<'py, f64>, isa: &str) -> PyResult<Pair<'py>> {
    let isa: Isa = isa.parse().map_err(to_py)?;
    if isa == Isa::Avx2 && !simd::avx2_available() {
        return Err(PyValueError::new_err("isa: this CPU has no AVX2+FMA"));
    }
    if isa == Isa::Avx512 && !simd::avx512_available() {
        return Err(PyValueError::new_err("isa: this CPU has no AVX-512 F+DQ"));
    }
    let xv = vec_of(&x);
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
