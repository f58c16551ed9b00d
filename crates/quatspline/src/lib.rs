//! # quatspline
//!
//! Keyframe orientations and poses in, smooth rigid-body motion out. The pure Rust core:
//! quaternion and dual-quaternion algebra ([`Quat`], [`DualQuat`]), conversions
//! ([`convert`]), two-keyframe interpolation ([`interp`]). Every formula is in
//! `shared/spec/MATH.md`; each method's doc comment states its formula, source and continuity.
//!
//! Fallible functions return [`Result`] with one [`Error`] type; nothing here panics on user
//! data (the few panicking conveniences say so under `# Panics`).

// Index loops mirror the formulas (q_{i,j}, M̃[j][m]) and read better than iterator chains here.
#![allow(clippy::needless_range_loop)]

pub mod analysis;
pub mod convert;
pub mod dual_quat;
mod error;
pub mod fit;
mod frame;
pub mod integrate;
pub mod interp;
pub mod jet;
pub mod kinematics;
mod names;
pub mod quadrature;
pub mod quat;
pub mod se3;
pub mod simd;
pub mod special;
pub mod spline;
#[doc(hidden)]
pub mod testing;
pub mod translation;
pub mod vec3;

pub use dual_quat::{DualQuat, Screw};
pub use error::{Error, Result, Short};
pub use frame::Frame;
pub use quat::Quat;
