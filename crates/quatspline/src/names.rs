//! Every named choice of the API parses here, once: `impl FromStr` for each enum a caller
//! names by a string (frames, end conditions, variants, rate models, formulations,
//! extrapolation rules, fit penalties and losses, Euler sequences, engine modes), so a
//! front end (the Python binding, a CLI) writes `name.parse()` and never matches strings.
//!
//! A name that is none of the choices is [`Error::UnknownName`]: its message names the
//! parameter and lists the choices (`frame: expected 'world' or 'body', got 'up'`), or, for
//! end conditions, names the method (`ends: squad does not support 'loop'; supported: open,
//! rest, closed`).

use std::str::FromStr;

use crate::convert::EulerSeq;
use crate::error::{Error, Result};
use crate::fit::{Penalty, Robust};
use crate::frame::Frame;
use crate::integrate::RateModel;
use crate::se3::PoseFormulation;
use crate::simd::{self, Isa, Mode};
use crate::spline::{C3Variant, Extrapolate, KeyEnds, NaturalEnds, TcbEnds};

fn unknown(arg: &'static str, got: &str, choices: &'static [&'static str]) -> Error {
    Error::UnknownName { arg, got: got.to_string(), choices, method: None }
}

fn unsupported(arg: &'static str, got: &str, choices: &'static [&'static str], method: &str) -> Error {
    Error::UnknownName { arg, got: got.to_string(), choices, method: Some(method.to_string()) }
}

impl FromStr for Frame {
    type Err = Error;
    /// "world" or "body".
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "world" => Ok(Frame::World),
            "body" => Ok(Frame::Body),
            _ => Err(unknown("frame", s, &["world", "body"])),
        }
    }
}

impl FromStr for Extrapolate {
    type Err = Error;
    /// "raise", "clamp", "linear" or "periodic".
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "raise" => Ok(Extrapolate::Raise),
            "clamp" => Ok(Extrapolate::Clamp),
            "linear" => Ok(Extrapolate::Linear),
            "periodic" => Ok(Extrapolate::Periodic),
            _ => Err(unknown("extrapolate", s, &["raise", "clamp", "linear", "periodic"])),
        }
    }
}

const KEY_ENDS: &[&str] = &["open", "rest", "closed"];

impl KeyEnds {
    /// `name` as the `ends` of `method` (named in the error).
    pub fn for_method(name: &str, method: &str) -> Result<Self> {
        match name {
            "open" => Ok(KeyEnds::Open),
            "rest" => Ok(KeyEnds::Rest),
            "closed" => Ok(KeyEnds::Closed),
            _ => Err(unsupported("ends", name, KEY_ENDS, method)),
        }
    }
}

impl FromStr for KeyEnds {
    type Err = Error;
    /// "open", "rest" or "closed".
    fn from_str(s: &str) -> Result<Self> {
        KeyEnds::for_method(s, "").map_err(|_| unknown("ends", s, KEY_ENDS))
    }
}

const TCB_ENDS: &[&str] = &["reflect", "duplicate", "rest", "closed"];

impl TcbEnds {
    /// `name` as the `ends` of `method` (Catmull–Rom, Kochanek–Bartels; named in the error):
    /// "reflect" (alias "open"), "duplicate", "rest" or "closed".
    pub fn for_method(name: &str, method: &str) -> Result<Self> {
        match name {
            "reflect" | "open" => Ok(TcbEnds::Reflect),
            "duplicate" => Ok(TcbEnds::Duplicate),
            "rest" => Ok(TcbEnds::Rest),
            "closed" => Ok(TcbEnds::Closed),
            _ => Err(unsupported("ends", name, TCB_ENDS, method)),
        }
    }
}

impl FromStr for TcbEnds {
    type Err = Error;
    /// "reflect" (alias "open"), "duplicate", "rest" or "closed".
    fn from_str(s: &str) -> Result<Self> {
        TcbEnds::for_method(s, "").map_err(|_| unknown("ends", s, TCB_ENDS))
    }
}

const NATURAL_ENDS: &[&str] = &["natural", "clamped", "rest", "closed"];

impl NaturalEnds {
    /// `name` as the `ends` of `method` (named in the error), with the clamped ends' rates
    /// `start` and `end` (None: the rate the natural condition gives there).
    pub fn for_method(
        name: &str,
        method: &str,
        start: Option<[f64; 3]>,
        end: Option<[f64; 3]>,
    ) -> Result<Self> {
        match name {
            "natural" => Ok(NaturalEnds::Natural),
            "clamped" => Ok(NaturalEnds::Clamped { start, end }),
            "rest" => Ok(NaturalEnds::Rest),
            "closed" => Ok(NaturalEnds::Closed),
            _ => Err(unsupported("ends", name, NATURAL_ENDS, method)),
        }
    }
}

impl FromStr for NaturalEnds {
    type Err = Error;
    /// "natural", "clamped" (no rates given), "rest" or "closed".
    fn from_str(s: &str) -> Result<Self> {
        NaturalEnds::for_method(s, "", None, None).map_err(|_| unknown("ends", s, NATURAL_ENDS))
    }
}

impl FromStr for C3Variant {
    type Err = Error;
    /// "knot" or "patent".
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "knot" => Ok(C3Variant::Knot),
            "patent" => Ok(C3Variant::Patent),
            _ => Err(unknown("variant", s, &["knot", "patent"])),
        }
    }
}

impl FromStr for RateModel {
    type Err = Error;
    /// "zoh", "linear" or "cubic" (the `method` of rate integration).
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "zoh" => Ok(RateModel::Zoh),
            "linear" => Ok(RateModel::Linear),
            "cubic" => Ok(RateModel::Cubic),
            _ => Err(unknown("method", s, &["zoh", "linear", "cubic"])),
        }
    }
}

impl FromStr for PoseFormulation {
    type Err = Error;
    /// "se3" or "split".
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "se3" => Ok(PoseFormulation::Se3),
            "split" => Ok(PoseFormulation::Split),
            _ => Err(unknown("formulation", s, &["se3", "split"])),
        }
    }
}

impl FromStr for Penalty {
    type Err = Error;
    /// "acceleration" or "jerk" ([`Penalty::parse`]).
    fn from_str(s: &str) -> Result<Self> {
        Penalty::parse(s)
    }
}

impl FromStr for Robust {
    type Err = Error;
    /// "huber" or "cauchy" ([`Robust::parse`]; no loss is `Robust::None`, not a name).
    fn from_str(s: &str) -> Result<Self> {
        Robust::parse(Some(s))
    }
}

impl FromStr for EulerSeq {
    type Err = Error;
    /// One of the 24 sequences of [`crate::convert::EULER_SEQUENCES`] ([`EulerSeq::parse`]).
    fn from_str(s: &str) -> Result<Self> {
        EulerSeq::parse(s)
    }
}

impl FromStr for Mode {
    type Err = Error;
    /// "auto" (aliases "on", "1", ""), "avx512", "avx2", "scalar" ("off", "0") or "reference"
    /// ("ref"), any case ([`simd::parse_mode`]).
    fn from_str(s: &str) -> Result<Self> {
        simd::parse_mode(s)
            .ok_or_else(|| unknown("mode", s, &["auto", "avx512", "avx2", "scalar", "reference"]))
    }
}

impl FromStr for Isa {
    type Err = Error;
    /// "avx512", "avx2" or "scalar" (whether this CPU has it is the caller's question:
    /// [`Isa::available`]).
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "avx512" => Ok(Isa::Avx512),
            "avx2" => Ok(Isa::Avx2),
            "scalar" => Ok(Isa::Scalar),
            _ => Err(unknown("isa", s, &["avx512", "avx2", "scalar"])),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_parses_and_unknown_names_list_the_choices() {
        assert_eq!("body".parse::<Frame>().unwrap(), Frame::Body);
        assert_eq!("world".parse::<Frame>().unwrap(), Frame::World);
        assert_eq!("open".parse::<TcbEnds>().unwrap(), TcbEnds::Reflect);
        assert_eq!("periodic".parse::<Extrapolate>().unwrap(), Extrapolate::Periodic);
        assert_eq!("OFF".parse::<Mode>().unwrap(), Mode::Scalar);
        assert!(matches!(
            NaturalEnds::for_method("clamped", "m", Some([1.0, 0.0, 0.0]), None).unwrap(),
            NaturalEnds::Clamped { start: Some(_), end: None }
        ));
        let m = |e: Error| e.to_string();
        assert_eq!(m("up".parse::<Frame>().unwrap_err()), "frame: expected 'world' or 'body', got 'up'");
        assert_eq!(
            m("fast".parse::<Mode>().unwrap_err()),
            "mode: expected 'auto', 'avx512', 'avx2', 'scalar' or 'reference', got 'fast'"
        );
        assert_eq!(
            m(KeyEnds::for_method("loop", "squad").unwrap_err()),
            "ends: squad does not support 'loop'; supported: open, rest, closed"
        );
        assert_eq!(m("x".parse::<C3Variant>().unwrap_err()), "variant: expected 'knot' or 'patent', got 'x'");
        // quoted as Python quotes: one line whatever the name holds
        assert_eq!(
            m("it's\n".parse::<Frame>().unwrap_err()),
            "frame: expected 'world' or 'body', got \"it's\\n\""
        );
    }
}
