//! The seeds' naive baselines, kept for comparison (seed 002; MATH.md §2).
//!
//! LinEuler: interpolate Euler angles linearly, each angle difference taken in (−π, π].
//! Not constant speed, axis wanders, and it breaks near gimbal lock.
//! LinMat: interpolate rotation matrices entrywise, then project back to SO(3) by polar
//! decomposition (SVD). Not constant speed; ill-defined for 180° apart (rank-deficient mean).

use crate::convert::{self, EulerSeq};
use crate::quat::Quat;
use std::f64::consts::PI;

/// Linear interpolation of the Euler angles of `q0` and `q1` in sequence `seq`.
pub fn lin_euler(seq: EulerSeq, q0: Quat, q1: Quat, t: f64) -> Quat {
    let (a, _) = convert::to_euler(seq, q0);
    let (b, _) = convert::to_euler(seq, q1);
    let ang: [f64; 3] = std::array::from_fn(|k| {
        let mut d = b[k] - a[k];
        if d > PI {
            d -= 2.0 * PI;
        } else if d <= -PI {
            d += 2.0 * PI;
        }
        a[k] + t * d
    });
    convert::from_euler(seq, ang).canonical_to(q0)
}

/// Entrywise interpolation of the rotation matrices of `q0` and `q1`, projected back to a
/// rotation by SVD.
pub fn lin_mat(q0: Quat, q1: Quat, t: f64) -> Quat {
    let a = convert::to_matrix(q0);
    let b = convert::to_matrix(q1);
    let m: convert::Mat3 =
        std::array::from_fn(|i| std::array::from_fn(|j| (1.0 - t) * a[i][j] + t * b[i][j]));
    let r = convert::project_to_rotation(&m);
    match convert::try_from_matrix(&r) {
        Ok(q) => q.canonical_to(q0),
        Err(_) => q0,
    }
}
