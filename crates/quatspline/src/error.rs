//! The one error type of the core. Every fallible function returns [`Result`]; the Python
//! binding maps each variant to a `ValueError` (or `RuntimeError` for [`Error::Internal`]) in
//! one place. Messages are one line and name the argument and the index that is wrong.

use std::fmt;

/// What went wrong, and where.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// A NaN or infinity in argument `arg` at flat element `index`.
    NonFinite { arg: &'static str, index: usize },
    /// A quaternion whose components are all zero or denormal: it has no direction.
    ZeroNorm { arg: &'static str, index: usize },
    /// An argument whose value is outside what the method accepts.
    Invalid { arg: &'static str, message: String },
    /// A time outside the spline's domain with `extrapolate = "raise"`.
    OutOfDomain { index: usize, t: f64, start: f64, end: f64 },
    /// An invariant of the library itself was broken (a bug): reported, never a panic.
    Internal(String),
    /// An iterative solver stopped before reaching its tolerance.
    NotConverged { what: &'static str, iterations: usize, step: f64, tol: f64 },
}

impl Error {
    /// Shorthand for [`Error::Invalid`].
    pub fn invalid(arg: &'static str, message: impl Into<String>) -> Self {
        Error::Invalid { arg, message: message.into() }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::NonFinite { arg, index } => {
                write!(f, "{arg}: non-finite value (NaN or inf) at element {index}")
            }
            Error::ZeroNorm { arg, index } => {
                write!(f, "{arg}: quaternion {index} has zero (or denormal) norm")
            }
            Error::Invalid { arg, message } => write!(f, "{arg}: {message}"),
            Error::OutOfDomain { index, t, start, end } => write!(
                f,
                "t: t[{index}] = {t} is outside the spline's domain [{start}, {end}] \
                 (use extrapolate=\"clamp\", \"linear\" or \"periodic\" to evaluate outside)"
            ),
            Error::Internal(m) => write!(f, "internal error (please report): {m}"),
            Error::NotConverged { what, iterations, step, tol } => write!(
                f,
                "{what}: did not converge in {iterations} iterations (last step {step:.3e}, \
                 tolerance {tol:.1e})"
            ),
        }
    }
}

impl std::error::Error for Error {}

/// The core's result type.
pub type Result<T> = std::result::Result<T, Error>;
