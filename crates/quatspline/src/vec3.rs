//! The few 3-vector operations the core needs, on plain `[f64; 3]`.

/// A 3-vector.
pub type Vec3 = [f64; 3];

#[inline]
pub fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

#[inline]
pub fn norm(a: Vec3) -> f64 {
    dot(a, a).sqrt()
}

#[inline]
pub fn scale(a: Vec3, s: f64) -> Vec3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

#[inline]
pub fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[inline]
pub fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// |a| without underflow or overflow: scales by the largest component when a·a leaves the
/// range where squaring is exact enough (tiny vectors such as 1e-160 would otherwise lose
/// their direction's length, or round to zero).
#[inline]
pub fn norm_robust(a: Vec3) -> f64 {
    let n2 = dot(a, a);
    if n2 > 1e-280 && n2 < 1e280 {
        return n2.sqrt();
    }
    let m = a[0].abs().max(a[1].abs()).max(a[2].abs());
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    let b = [a[0] / m, a[1] / m, a[2] / m];
    m * dot(b, b).sqrt()
}
