//! Inspecting splines: continuity certificates at joints.

mod continuity;

pub use continuity::{continuity, JointReport};
