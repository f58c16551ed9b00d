//! Two-keyframe interpolation (MATH.md §2–3): each method in its own file.

mod baseline;
mod dlb;
mod lerp;
mod sclerp;
mod slerp;

pub use baseline::{lin_euler, lin_mat};
pub use dlb::try_dlb;
pub use lerp::{lerp, try_nlerp};
pub use sclerp::sclerp;
pub use slerp::slerp;
