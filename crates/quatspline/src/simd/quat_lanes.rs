//! Quaternions and 3-vectors of lanes, written once for every kernel: a quaternion is
//! `[w, x, y, z]` of [`Lanes`] (one sample per lane), a vector `[x, y, z]`. Each helper is one
//! fixed sequence of (fused) operations, so a kernel's bits do not depend on which kernel
//! calls it. (Functions, not closures: a closure would not inherit the caller's
//! `target_feature`, and its vector operations would be calls.)

use super::lanes::Lanes;

/// A quaternion of lanes, `[w, x, y, z]`.
pub(crate) type Q4<V> = [V; 4];
/// A 3-vector of lanes.
pub(crate) type V3<V> = [V; 3];

/// The Hamilton product a ⊗ b.
#[inline(always)]
pub(crate) fn qmul<V: Lanes>(a: Q4<V>, b: Q4<V>) -> Q4<V> {
    [
        a[3].fnma(b[3], a[2].fnma(b[2], a[1].fnma(b[1], a[0] * b[0]))),
        a[3].fnma(b[2], a[2].fma(b[3], a[1].fma(b[0], a[0] * b[1]))),
        a[3].fma(b[1], a[2].fma(b[0], a[1].fnma(b[3], a[0] * b[2]))),
        a[3].fma(b[0], a[2].fnma(b[1], a[1].fma(b[2], a[0] * b[3]))),
    ]
}

/// a ⊗ (0, v).
#[inline(always)]
pub(crate) fn qmul_pure<V: Lanes>(a: Q4<V>, v: V3<V>) -> Q4<V> {
    [
        a[3].fnma(v[2], a[2].fnma(v[1], -(a[1] * v[0]))),
        a[3].fnma(v[1], a[2].fma(v[2], a[0] * v[0])),
        a[3].fma(v[0], a[1].fnma(v[2], a[0] * v[1])),
        a[2].fnma(v[0], a[1].fma(v[1], a[0] * v[2])),
    ]
}

/// The conjugate a* = (w, −v).
#[inline(always)]
pub(crate) fn conj<V: Lanes>(a: Q4<V>) -> Q4<V> {
    [a[0], -a[1], -a[2], -a[3]]
}

/// a + b.
#[inline(always)]
pub(crate) fn add4<V: Lanes>(a: Q4<V>, b: Q4<V>) -> Q4<V> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]
}

/// a s.
#[inline(always)]
pub(crate) fn scale4<V: Lanes>(a: Q4<V>, s: V) -> Q4<V> {
    [a[0] * s, a[1] * s, a[2] * s, a[3] * s]
}

/// a·b by fused multiply-adds.
#[inline(always)]
pub(crate) fn dot4<V: Lanes>(a: Q4<V>, b: Q4<V>) -> V {
    a[3].fma(b[3], a[2].fma(b[2], a[1].fma(b[1], a[0] * b[0])))
}

/// q·q summed as `Quat::norm_squared` does (no FMA), so that [`normalize`] keeps the scalar
/// path's bits.
#[inline(always)]
pub(crate) fn norm2_plain<V: Lanes>(q: Q4<V>) -> V {
    q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]
}

/// `Quat::try_normalize` of a quaternion with squared norm `n2` ([`norm2_plain`]) in
/// [1e-290, 1e290]: q as given when |q·q − 1| ≤ 4ε, else (q/m)/|q/m| with m the largest
/// |component| — the same operations, so the same bits.
#[inline(always)]
pub(crate) fn normalize<V: Lanes>(q: Q4<V>, n2: V) -> Q4<V> {
    let one = V::splat(1.0);
    let dev = n2 - one;
    let tol = V::splat(4.0 * f64::EPSILON);
    // |dev| ≤ tol  ⇔  not (dev < −tol or tol < dev)
    if !(dev.any_lt(-tol) || tol.any_lt(dev)) {
        return q;
    }
    let zero = V::splat(0.0);
    let abs = |x: V| x.lt_select(zero, -x, x);
    let max = |a: V, b: V| a.lt_select(b, b, a);
    let m = max(max(max(abs(q[0]), abs(q[1])), abs(q[2])), abs(q[3]));
    let s = [q[0] / m, q[1] / m, q[2] / m, q[3] / m];
    let k = one / norm2_plain(s).sqrt();
    let keep = |c: usize| dev.lt_select(-tol, s[c] * k, tol.lt_select(dev, s[c] * k, q[c]));
    [keep(0), keep(1), keep(2), keep(3)]
}

/// c exp(x n) for a quaternion c, unit axis n and angle x.
#[inline(always)]
pub(crate) fn times_exp<V: Lanes>(c: Q4<V>, n: V3<V>, x: V) -> Q4<V> {
    let (s, co) = x.sin_cos();
    qmul(c, [co, s * n[0], s * n[1], s * n[2]])
}

/// slerp(a, b; w) = a exp(w log(a* b)), no hemisphere flip (as `JQuat::slerp`), for unit a
/// and b, written without quaternion products: with c = a·b and r = b − c a (= a ⊗ vec(a* b),
/// orthogonal to a, |r| = sin θ), θ = atan2(|r|, c) and the result is
/// a cos wθ + r sin wθ / |r|. Where |r| = 0 exactly: a, or for c < 0 the reference's
/// log(−1) = (π, 0, 0) choice, a ⊗ (cos wπ, sin wπ, 0, 0).
#[inline(always)]
pub(crate) fn slerp<V: Lanes>(a: Q4<V>, b: Q4<V>, w: V) -> Q4<V> {
    let c = dot4(a, b);
    let r = [c.fnma(a[0], b[0]), c.fnma(a[1], b[1]), c.fnma(a[2], b[2]), c.fnma(a[3], b[3])];
    let s = dot4(r, r).sqrt();
    let th = s.atan2(c);
    let (sn, cs) = (w * th).sin_cos();
    let zero = V::splat(0.0);
    let k = zero.lt_select(s, sn / s, zero);
    let o = [r[0].fma(k, a[0] * cs), r[1].fma(k, a[1] * cs), r[2].fma(k, a[2] * cs), r[3].fma(k, a[3] * cs)];
    if !s.any_lt(V::splat(f64::MIN_POSITIVE)) {
        return o;
    }
    // a ⊗ (cs, sn, 0, 0) = a cs + (a ⊗ i) sn, a ⊗ i = (−a_x, a_w, a_z, −a_y)
    let special = [
        a[1].fnma(sn, a[0] * cs),
        a[0].fma(sn, a[1] * cs),
        a[3].fma(sn, a[2] * cs),
        a[2].fnma(sn, a[3] * cs),
    ];
    let tiny = V::splat(f64::MIN_POSITIVE);
    [
        s.lt_select(tiny, special[0], o[0]),
        s.lt_select(tiny, special[1], o[1]),
        s.lt_select(tiny, special[2], o[2]),
        s.lt_select(tiny, special[3], o[3]),
    ]
}

/// vec(a* b) for quaternions a = (a₀, a), b = (b₀, b): a₀ b − b₀ a − a × b.
#[inline(always)]
pub(crate) fn vec_conj_mul<V: Lanes>(a0: V, a: V3<V>, b0: V, b: V3<V>) -> V3<V> {
    let c = cross(a, b);
    [a0.fma(b[0], -(b0 * a[0])) - c[0], a0.fma(b[1], -(b0 * a[1])) - c[1], a0.fma(b[2], -(b0 * a[2])) - c[2]]
}

/// a × b.
#[inline(always)]
pub(crate) fn cross<V: Lanes>(a: V3<V>, b: V3<V>) -> V3<V> {
    [a[2].fnma(b[1], a[1] * b[2]), a[0].fnma(b[2], a[2] * b[0]), a[1].fnma(b[0], a[0] * b[1])]
}

/// a·b by fused multiply-adds.
#[inline(always)]
pub(crate) fn dot3<V: Lanes>(a: V3<V>, b: V3<V>) -> V {
    a[2].fma(b[2], a[1].fma(b[1], a[0] * b[0]))
}

/// a + b.
#[inline(always)]
pub(crate) fn add3<V: Lanes>(a: V3<V>, b: V3<V>) -> V3<V> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// a s.
#[inline(always)]
pub(crate) fn scale3<V: Lanes>(a: V3<V>, s: V) -> V3<V> {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// a x + b y.
#[inline(always)]
pub(crate) fn lin3<V: Lanes>(a: V, x: V3<V>, b: V, y: V3<V>) -> V3<V> {
    [a.fma(x[0], b * y[0]), a.fma(x[1], b * y[1]), a.fma(x[2], b * y[2])]
}

/// The vector rotated by the unit quaternion q: x + 2w (v × x) + 2 v × (v × x).
#[inline(always)]
pub(crate) fn rotate<V: Lanes>(q: Q4<V>, x: V3<V>) -> V3<V> {
    let v = [q[1], q[2], q[3]];
    let c1 = cross(v, x);
    let c1 = add3(c1, c1);
    let c2 = cross(v, c1);
    [q[0].fma(c1[0], x[0]) + c2[0], q[0].fma(c1[1], x[1]) + c2[1], q[0].fma(c1[2], x[2]) + c2[2]]
}

/// v cos 2θ − sin 2θ (n × v) + (1 − cos 2θ)(n·v) n given s2 = sin 2θ, c2 = cos 2θ,
/// omc = 1 − cos 2θ: e* v e for e = (cos θ, sin θ n), and e v e* with s2 = −sin 2θ.
#[inline(always)]
pub(crate) fn rot_axis<V: Lanes>(n: V3<V>, s2: V, c2: V, omc: V, v: V3<V>) -> V3<V> {
    let cr = cross(n, v);
    let k = omc * dot3(n, v);
    [
        k.fma(n[0], s2.fnma(cr[0], c2 * v[0])),
        k.fma(n[1], s2.fnma(cr[1], c2 * v[1])),
        k.fma(n[2], s2.fnma(cr[2], c2 * v[2])),
    ]
}
