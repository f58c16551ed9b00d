//! The Python binding: convert arrays, call the core, map errors. Nothing else lives here.
//!
//! Every function takes 2-D float64 arrays whose rows are quaternions (4), dual quaternions
//! (8), vectors (3), matrices (9) or scalars (1) — the Python layer does dtype coercion and
//! broadcasting, then passes flat views (any strides). Shapes are checked here with messages
//! that name the argument; the loop runs with the GIL released; a panic inside it becomes a
//! `RuntimeError`, never a crash.

mod algebra;
mod arrays;
mod fit;
mod keyframe;
mod simd;
mod spline;
mod toolkit;
mod validate;

use pyo3::prelude::*;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    algebra::register(m)?;
    spline::register(m)?;
    fit::register(m)?;
    keyframe::register(m)?;
    toolkit::register(m)?;
    simd::register(m)?;
    validate::register(m)?;
    Ok(())
}
