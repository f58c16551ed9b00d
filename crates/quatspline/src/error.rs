//! The one error type of the core. Every fallible function returns [`Result`]; the Python
//! binding maps each variant to a `ValueError` (or `RuntimeError` for [`Error::Internal`]) in
//! one place. Messages are one line and name the argument and the index that is wrong.

use std::fmt;

/// A number as messages print it: as written between 1e-4 and 1e15 (Rust's shortest
/// round-trip digits), in scientific notation beyond (a weight of 1e308 is "1e308", not
/// 309 digits). Every `f64` interpolated into an error message goes through it.
pub struct Short(pub f64);

impl fmt::Display for Short {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0;
        if v == 0.0 || !v.is_finite() || (1e-4..1e15).contains(&v.abs()) {
            write!(f, "{v}")
        } else {
            write!(f, "{v:e}")
        }
    }
}

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
    /// A name (`got`) that is none of option `arg`'s `choices`; for an end condition, the
    /// `method` that does not support it (see `names.rs`).
    UnknownName { arg: &'static str, got: String, choices: &'static [&'static str], method: Option<String> },
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
                "t: t[{index}] = {} is outside the spline's domain [{}, {}] \
                 (use extrapolate=\"clamp\", \"linear\" or \"periodic\" to evaluate outside)",
                Short(*t),
                Short(*start),
                Short(*end)
            ),
            Error::Internal(m) => write!(f, "internal error (please report): {m}"),
            Error::NotConverged { what, iterations, step, tol } => write!(
                f,
                "{what}: did not converge in {iterations} iterations (last step {step:.3e}, \
                 tolerance {tol:.1e})"
            ),
            Error::UnknownName { arg, got, choices, method: Some(method) } => {
                write!(
                    f,
                    "{arg}: {method} does not support {}; supported: {}",
                    Quoted(got),
                    choices.join(", ")
                )
            }
            Error::UnknownName { arg, got, choices, method: None } => {
                write!(f, "{arg}: expected ")?;
                for (i, c) in choices.iter().enumerate() {
                    let sep = match i {
                        0 => "",
                        _ if i + 1 == choices.len() => " or ",
                        _ => ", ",
                    };
                    write!(f, "{sep}{}", Quoted(c))?;
                }
                write!(f, ", got {}", Quoted(got))
            }
        }
    }
}

/// A name as Python quotes it (the binding's callers read these messages): 'name', or
/// "name" when it holds a single quote and no double one; backslashes, the quote and control
/// characters escaped, so the message stays on one line.
struct Quoted<'a>(&'a str);

impl fmt::Display for Quoted<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = self.0;
        let q = if s.contains('\'') && !s.contains('"') { '"' } else { '\'' };
        write!(f, "{q}")?;
        for c in s.chars() {
            if c == '\\' || c == q {
                write!(f, "\\{c}")?;
            } else if c.is_control() {
                write!(f, "{}", c.escape_default())?;
            } else {
                write!(f, "{c}")?;
            }
        }
        write!(f, "{q}")
    }
}

impl std::error::Error for Error {}

/// The core's result type.
pub type Result<T> = std::result::Result<T, Error>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_prints_huge_and_tiny_numbers_in_scientific_notation() {
        let cases = [
            (1e308, "1e308"),
            (-1e308, "-1e308"),
            (f64::MAX, "1.7976931348623157e308"),
            (1e15, "1e15"),
            (1e-5, "1e-5"),
            (f64::MIN_POSITIVE, "2.2250738585072014e-308"),
            (5e-324, "5e-324"),
            (0.0, "0"),
            (0.5, "0.5"),
            (-2.25, "-2.25"),
            (1e-4, "0.0001"),
            (123456789012345.0, "123456789012345"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
            (f64::NAN, "NaN"),
        ];
        for (v, want) in cases {
            assert_eq!(Short(v).to_string(), want, "{v:e}");
        }
        // Round trip: the printed digits are the shortest that read back as the same number.
        for v in [1e308, 1.5e-300, 0.1, 3.0e14, 7.25e15] {
            assert_eq!(Short(v).to_string().parse::<f64>().unwrap(), v);
        }
    }

    #[test]
    fn out_of_domain_message_prints_huge_numbers_short() {
        let e = Error::OutOfDomain { index: 2, t: 1e308, start: -1e300, end: 1e-310 };
        let m = e.to_string();
        assert!(m.contains("t[2] = 1e308") && m.contains("[-1e300, 1e-310]"), "{m}");
        assert!(!m.contains("00000"), "{m}");
    }
}
