//! Conversions between unit quaternions and rotation matrices, rotation vectors, axis–angle
//! pairs and Euler angles (all 12 sequences, scipy's convention).
//!
//! Euler convention (as `scipy.spatial.transform.Rotation`): an uppercase sequence such as
//! "XYZ" is intrinsic (rotate about the body's axes, q = q_X(a) q_Y(b) q_Z(c)), a lowercase one
//! such as "xyz" is extrinsic (about the fixed axes, q = q_z(c) q_y(b) q_x(a)). `as_euler` uses
//! the quaternion-direct method of Bernardes & Viollet (2022), as scipy does, including its
//! gimbal-lock rule (third angle set to zero when the middle angle is within 1e-7 of 0 or π).

use crate::error::{Error, Result};
use crate::quat::Quat;
use crate::special::{atan2_over, sinc};
use crate::vec3::{self, Vec3};
use std::f64::consts::PI;

/// A 3×3 matrix, row major.
pub type Mat3 = [[f64; 3]; 3];

/// The 12 valid Euler sequences, for error messages.
pub const EULER_SEQUENCES: [&str; 24] = [
    "xyz", "xzy", "yxz", "yzx", "zxy", "zyx", "xyx", "xzx", "yxy", "yzy", "zxz", "zyz", "XYZ", "XZY", "YXZ",
    "YZX", "ZXY", "ZYX", "XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ",
];

/// The rotation matrix of a unit quaternion (columns are the body axes in world coordinates).
pub fn to_matrix(q: Quat) -> Mat3 {
    let (w, x, y, z) = (q.w, q.x, q.y, q.z);
    let (xx, yy, zz) = (x * x, y * y, z * z);
    let (xy, xz, yz) = (x * y, x * z, y * z);
    let (wx, wy, wz) = (w * x, w * y, w * z);
    [
        [1.0 - 2.0 * (yy + zz), 2.0 * (xy - wz), 2.0 * (xz + wy)],
        [2.0 * (xy + wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz - wx)],
        [2.0 * (xz - wy), 2.0 * (yz + wx), 1.0 - 2.0 * (xx + yy)],
    ]
}

fn det3(m: &Mat3) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// The nearest rotation to any 3×3 matrix in the Frobenius norm (the orthogonal polar factor,
/// with the sign of the smallest singular direction fixed so that det = +1), by SVD.
pub fn project_to_rotation(m: &Mat3) -> Mat3 {
    let a = nalgebra::Matrix3::from_fn(|i, j| m[i][j]);
    let svd = a.svd(true, true);
    let (Some(u), Some(vt)) = (svd.u, svd.v_t) else {
        return [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    };
    // nalgebra sorts singular values in decreasing order; flip the last one if needed.
    let mut u = u;
    if (u * vt).determinant() < 0.0 {
        let mut c = u.column_mut(2);
        c *= -1.0;
    }
    let r = u * vt;
    [[r[(0, 0)], r[(0, 1)], r[(0, 2)]], [r[(1, 0)], r[(1, 1)], r[(1, 2)]], [r[(2, 0)], r[(2, 1)], r[(2, 2)]]]
}

/// The unit quaternion (w ≥ 0 not enforced) of a rotation matrix, robust for every angle:
/// Shepperd's method picks the largest of trace, m00, m11, m22 to divide by. A matrix that is
/// not orthogonal to 1e-12 is first projected to the nearest rotation (as scipy does); a
/// matrix with det ≤ 0 is an error.
pub fn try_from_matrix(m: &Mat3) -> Result<Quat> {
    if m.iter().flatten().any(|v| !v.is_finite()) {
        return Err(Error::NonFinite { arg: "matrix", index: 0 });
    }
    if det3(m).partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(Error::invalid("matrix", "non-positive determinant: not a rotation"));
    }
    let mut orthogonal = true;
    for i in 0..3 {
        for j in 0..3 {
            let g: f64 = (0..3).map(|k| m[i][k] * m[j][k]).sum();
            let e = if i == j { 1.0 } else { 0.0 };
            if (g - e).abs() > 1e-12 {
                orthogonal = false;
            }
        }
    }
    let m = if orthogonal { *m } else { project_to_rotation(m) };
    let tr = m[0][0] + m[1][1] + m[2][2];
    let q = if tr >= m[0][0] && tr >= m[1][1] && tr >= m[2][2] {
        Quat::new(1.0 + tr, m[2][1] - m[1][2], m[0][2] - m[2][0], m[1][0] - m[0][1])
    } else if m[0][0] >= m[1][1] && m[0][0] >= m[2][2] {
        Quat::new(m[2][1] - m[1][2], 1.0 - tr + 2.0 * m[0][0], m[1][0] + m[0][1], m[2][0] + m[0][2])
    } else if m[1][1] >= m[2][2] {
        Quat::new(m[0][2] - m[2][0], m[1][0] + m[0][1], 1.0 - tr + 2.0 * m[1][1], m[2][1] + m[1][2])
    } else {
        Quat::new(m[1][0] - m[0][1], m[2][0] + m[0][2], m[2][1] + m[1][2], 1.0 - tr + 2.0 * m[2][2])
    };
    q.try_normalize()
}

/// The rotation vector (axis × angle, angle in [0, π]) of a unit quaternion. Uses the w ≥ 0
/// representative and θ/sin θ via [`atan2_over`], so it is exact near the identity.
pub fn to_rotvec(q: Quat) -> Vec3 {
    let q = if q.w < 0.0 { -q } else { q };
    let v = q.vec();
    let s = vec3::norm(v);
    if s == 0.0 {
        return [0.0; 3];
    }
    vec3::scale(v, 2.0 * atan2_over(s, q.w))
}

/// The unit quaternion of a rotation vector r: (cos(|r|/2), sinc(|r|/2) r/2).
///
/// |r| is computed with scaling ([`vec3::norm_robust`]), so every finite r gives a finite unit
/// quaternion (|r|² overflowed above |r| ≈ 1.3e154 and gave NaN); above |r| = 1 the vector part
/// is sin(|r|/2) · r/|r|, the unit axis times the sine, so no ratio under- or overflows.
pub fn from_rotvec(r: Vec3) -> Quat {
    let n = vec3::norm_robust(r);
    let half = 0.5 * n;
    if n <= 1.0 {
        let s = 0.5 * sinc(half);
        return Quat::new(half.cos(), s * r[0], s * r[1], s * r[2]);
    }
    let (sh, ch) = half.sin_cos();
    Quat::new(ch, sh * (r[0] / n), sh * (r[1] / n), sh * (r[2] / n))
}

/// The unit quaternion of a rotation by `angle` radians about `axis` (normalised here).
pub fn try_from_axis_angle(axis: Vec3, angle: f64) -> Result<Quat> {
    let n = vec3::norm(axis);
    if !n.is_finite() || !angle.is_finite() {
        return Err(Error::NonFinite { arg: "axis", index: 0 });
    }
    if n < f64::MIN_POSITIVE {
        return Err(Error::invalid("axis", "zero axis"));
    }
    Ok(from_rotvec(vec3::scale(axis, angle / n)))
}

/// Axis (unit) and angle in [0, π] of a unit quaternion; the identity gets axis x.
pub fn to_axis_angle(q: Quat) -> (Vec3, f64) {
    let r = to_rotvec(q);
    let a = vec3::norm(r);
    if a == 0.0 {
        ([1.0, 0.0, 0.0], 0.0)
    } else {
        (vec3::scale(r, 1.0 / a), a)
    }
}

/// A parsed Euler sequence: axis indices (0 = x, 1 = y, 2 = z) and whether it is extrinsic.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EulerSeq {
    pub axes: [usize; 3],
    pub extrinsic: bool,
}

impl EulerSeq {
    /// Parses one of the 24 strings of [`EULER_SEQUENCES`].
    pub fn parse(seq: &str) -> Result<Self> {
        if !EULER_SEQUENCES.contains(&seq) {
            return Err(Error::invalid(
                "seq",
                format!("unknown Euler sequence {seq:?}; valid: {}", EULER_SEQUENCES.join(", ")),
            ));
        }
        let extrinsic = seq.chars().all(|c| c.is_ascii_lowercase());
        let mut axes = [0; 3];
        for (k, c) in seq.to_ascii_lowercase().chars().enumerate() {
            axes[k] = (c as u8 - b'x') as usize;
        }
        Ok(EulerSeq { axes, extrinsic })
    }
}

fn elementary(axis: usize, angle: f64) -> Quat {
    let (s, c) = (0.5 * angle).sin_cos();
    let mut v = [0.0; 3];
    v[axis] = s;
    Quat::new(c, v[0], v[1], v[2])
}

/// The quaternion of Euler angles (radians) in sequence `seq`.
pub fn from_euler(seq: EulerSeq, angles: Vec3) -> Quat {
    let q: [Quat; 3] = std::array::from_fn(|k| elementary(seq.axes[k], angles[k]));
    if seq.extrinsic {
        q[2] * q[1] * q[0]
    } else {
        q[0] * q[1] * q[2]
    }
}

/// Euler angles (radians) of a unit quaternion in sequence `seq`, as scipy computes them:
/// first and third in [−π, π], the middle one in [0, π] (proper) or [−π/2, π/2] (Tait–Bryan).
/// Returns the angles and whether gimbal lock was met (third angle then set to zero).
pub fn to_euler(seq: EulerSeq, q: Quat) -> (Vec3, bool) {
    let [mut i, j, mut k] = seq.axes;
    if !seq.extrinsic {
        std::mem::swap(&mut i, &mut k);
    }
    let symmetric = i == k;
    if symmetric {
        k = 3 - i - j;
    }
    let sign = (((i as i64 - j as i64) * (j as i64 - k as i64) * (k as i64 - i as i64)) / 2) as f64;
    let comp = |a: usize| -> f64 { [q.x, q.y, q.z][a] };
    let (a, b, c, d) = if symmetric {
        (q.w, comp(i), comp(j), comp(k) * sign)
    } else {
        (q.w - comp(j), comp(i) + comp(k) * sign, comp(j) + q.w, comp(k) * sign - comp(i))
    };
    let half_sum = b.atan2(a);
    let half_diff = d.atan2(c);
    let mut ang = [0.0, 2.0 * c.hypot(d).atan2(a.hypot(b)), 0.0];
    let eps = 1e-7;
    let case1 = ang[1].abs() <= eps;
    let case2 = (ang[1] - PI).abs() <= eps;
    let case0 = !(case1 || case2);
    ang[0] = if case1 { 2.0 * half_sum } else { 2.0 * half_diff * if seq.extrinsic { -1.0 } else { 1.0 } };
    let (first, third) = if seq.extrinsic { (0, 2) } else { (2, 0) };
    if case0 {
        ang[first] = half_sum - half_diff;
    }
    let mut a3 = if case0 { half_sum + half_diff } else { ang[third] };
    if !symmetric {
        a3 *= sign;
        ang[1] -= PI / 2.0;
    }
    ang[third] = a3;
    // scipy's wrap (its Cython `_get_angles`): one shift by 2π, only strictly outside
    // [−π, π], so an angle of exactly ±π keeps its sign (a middle angle of π stays +π).
    for v in ang.iter_mut() {
        if *v < -PI {
            *v += 2.0 * PI;
        } else if *v > PI {
            *v -= 2.0 * PI;
        }
    }
    (ang, !case0)
}

/// Parses a rotation sequence of 1, 2 or 3 axes as scipy's `from_euler` accepts: all
/// uppercase (intrinsic) or all lowercase (extrinsic), no axis repeated consecutively
/// ("X", "zx", "xyz", "ZYZ", …). Returns the axes and whether the sequence is extrinsic.
pub fn parse_rotation_sequence(seq: &str) -> Result<(Vec<usize>, bool)> {
    let bad = || {
        Error::invalid(
            "seq",
            format!(
                "unknown rotation sequence {seq:?}: expected 1 to 3 axes, all of x, y, z (extrinsic) \
                 or all of X, Y, Z (intrinsic), no axis twice in a row, e.g. \"x\", \"zx\", \"xyz\", \"ZYZ\""
            ),
        )
    };
    let n = seq.chars().count();
    if !(1..=3).contains(&n) {
        return Err(bad());
    }
    let extrinsic = seq.chars().all(|c| matches!(c, 'x' | 'y' | 'z'));
    let intrinsic = seq.chars().all(|c| matches!(c, 'X' | 'Y' | 'Z'));
    if !(extrinsic || intrinsic) {
        return Err(bad());
    }
    let axes: Vec<usize> = seq.to_ascii_lowercase().bytes().map(|c| (c - b'x') as usize).collect();
    if axes.windows(2).any(|w| w[0] == w[1]) {
        return Err(bad());
    }
    Ok((axes, extrinsic))
}

/// The quaternion of 1 to 3 elementary rotations (radians) about `axes`: intrinsic
/// q = q₀ q₁ q₂, extrinsic q = q₂ q₁ q₀ (scipy's `from_euler` with 1, 2 or 3 axes).
pub fn from_rotation_sequence(axes: &[usize], extrinsic: bool, angles: &[f64]) -> Quat {
    let mut q = Quat::IDENTITY;
    for (&a, &g) in axes.iter().zip(angles) {
        let e = elementary(a, g);
        q = if extrinsic { e * q } else { q * e };
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn matrix_round_trip(w in 0.05..1.0f64, x in -1.0..1.0f64, y in -1.0..1.0f64, z in -1.0..1.0f64) {
            let q = Quat::new(w, x, y, z).normalize();
            let back = try_from_matrix(&to_matrix(q)).unwrap().canonical_to(q);
            prop_assert!((back - q).to_wxyz().iter().all(|c| c.abs() < 1e-14));
        }

        #[test]
        fn euler_round_trip_all_sequences(w in 0.05..1.0f64, x in -1.0..1.0f64, y in -1.0..1.0f64, z in -1.0..1.0f64) {
            let q = Quat::new(w, x, y, z).normalize();
            for s in EULER_SEQUENCES {
                let seq = EulerSeq::parse(s).unwrap();
                let (a, _) = to_euler(seq, q);
                let back = from_euler(seq, a).canonical_to(q);
                prop_assert!((back - q).to_wxyz().iter().all(|c| c.abs() < 1e-12), "{s}");
            }
        }
    }

    /// Regression (issue 2.1 item 15): |r|² overflowed above |r| ≈ 1.3e154 and gave NaN.
    #[test]
    fn huge_rotation_vectors_give_finite_unit_quaternions() {
        for m in [1e154, 1.3e154, 1e200, 1e300, f64::MAX / 2.0] {
            for r in [[m, 0.0, 0.0], [m, -m, m], [0.0, 1e-300, m]] {
                let q = from_rotvec(r);
                assert!(q.is_finite() && (q.norm() - 1.0).abs() < 1e-15, "{r:?}: {q:?}");
                // The angle is |r| taken modulo 2π: cos(|r|/2) exactly as libm gives it.
                let n = vec3::norm_robust(r);
                assert_eq!(q.w, (0.5 * n).cos());
            }
        }
        // Continuous across the branch at |r| = 1.
        let a = from_rotvec([1.0, 0.0, 0.0]);
        let b = from_rotvec([1.0 + 2e-16, 0.0, 0.0]);
        assert!((a - b).norm() < 1e-15);
    }

    #[test]
    fn half_turn_matrices_convert() {
        for axis in 0..3 {
            let mut v = [0.0; 3];
            v[axis] = 1.0;
            let q = Quat::new(0.0, v[0], v[1], v[2]);
            let back = try_from_matrix(&to_matrix(q)).unwrap();
            assert!((back.dot(q).abs() - 1.0).abs() < 1e-15);
        }
    }

    /// Regression (issue 2.1 item 3): a middle angle of exactly 180° came out as −π where scipy
    /// gives +π (rem_euclid mapped π to −π).
    #[test]
    fn as_euler_keeps_plus_pi_like_scipy() {
        for s in ["zxz", "ZXZ", "xyx", "YZY"] {
            let seq = EulerSeq::parse(s).unwrap();
            let q = from_euler(seq, [0.3, PI, 0.0]);
            let (a, lock) = to_euler(seq, q);
            assert!(lock && a[1] == PI, "{s}: {a:?}");
        }
    }

    /// Regression (issue 2.1 item 7): one- and two-axis sequences, as scipy accepts them.
    #[test]
    fn one_and_two_axis_sequences_are_accepted() {
        let (axes, ext) = parse_rotation_sequence("X").unwrap();
        assert_eq!((axes.as_slice(), ext), (&[0usize][..], false));
        let (axes, ext) = parse_rotation_sequence("zx").unwrap();
        let q = from_rotation_sequence(&axes, ext, &[0.4, 0.7]);
        let want = elementary(0, 0.7) * elementary(2, 0.4);
        assert!((q - want).norm() < 1e-16);
        for bad in ["", "xx", "xY", "xyzx", "w"] {
            assert!(parse_rotation_sequence(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn unknown_sequence_lists_the_valid_ones() {
        let e = EulerSeq::parse("xxy").unwrap_err().to_string();
        assert!(e.contains("xyz") && e.contains("ZYZ"));
    }
}
