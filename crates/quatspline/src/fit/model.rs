//! The fitted curve and its closed-form Jacobians: a cumulative B-spline on SO(3) (MATH.md §6;
//! uniform or on breakpoints, `layout.rs`: only the basis tables B̃_j(u) and the segment widths
//! differ), q(t) = R_i Π_{j=1}^{k−1} Exp(B̃_j(u) d_{i+j}), d_m = Log(R_{m−1}⁻¹ R_m),
//! perturbed on the right, R_m ← R_m Exp(δ_m) (rotation vectors).
//!
//! Jacobian (Sommer, Usenko, Schubert, Demmel & Cremers, "Efficient Derivative Computation for
//! Cumulative B-Splines on Lie Groups", CVPR 2020, §4; written here for the right
//! perturbation of the control points): the curve moves as q(t) ← q(t) Exp(ξ(t)) with
//!   ξ(t) = Σ_m X_m(t) δ_m,
//!   X_i   = Ad(S_0⁻¹) − M_1 J_l⁻¹(d_{i+1}),
//!   X_{i+j} = M_j J_r⁻¹(d_{i+j}) − M_{j+1} J_l⁻¹(d_{i+j+1})   (M_k = 0),
//! where S_j = A_{j+1} ⋯ A_{k−1} (S_{k−1} = 1), A_j = Exp(B̃_j d_{i+j}), and
//! M_j = Ad(S_j⁻¹) · B̃_j J_r(B̃_j d_{i+j}). This follows from Log(Exp(−δ) X Exp(δ′)) ≈
//! Log X − J_l⁻¹ δ + J_r⁻¹ δ′ and Exp(b(d + ε)) ≈ Exp(bd) Exp(b J_r(bd) ε). With a = |d| and
//! n = d/a, b J_r(bd) = b I − ((1 − cos ba)/a)[n]× + (b − sin(ba)/a)[n]×²
//! ([`crate::special::scaled_jr_coefficients`], series below a = 0.02), so every factor is a function of the scalar B̃_j(u): written once over
//! [`Jet<N>`], the same code gives ξ and its time derivatives ξ̇, ξ̈, ξ⃛ exactly.
//!
//! Body angular velocity under the perturbation: ω ← ω + ξ̇ + ω × ξ (first order), hence
//! δω̇ = d/dt(ξ̇ + ω × ξ) and δω̈ = d²/dt²(ξ̇ + ω × ξ): the penalty's Jacobians are the jets of
//! ξ̇ + ω × ξ. The data residual r = Log(q(t)⁻¹ y) moves by −J_l⁻¹(r) ξ.

use super::layout::Layout;
use super::so3::{self, M3};
use crate::jet::{Axis, JQuat, Jet};
use crate::quat::Quat;
use crate::spline::CumulativeBSpline;
use crate::vec3::{self, Vec3};
use rayon::prelude::*;

/// The largest order the fitting solver uses.
pub const MAXK: usize = 8;

/// A vector of jets.
pub type V<const N: usize> = [Jet<N>; 3];

/// Per-control-point, per-direction columns X_m(t) e_c as jets (index [m − i][c]).
pub type Cols<const N: usize> = [[V<N>; 3]; MAXK];

/// A uniform cumulative B-spline on SO(3) being fitted.
#[derive(Debug, Clone)]
pub struct Model {
    pub order: usize,
    pub dt: f64,
    pub t0: f64,
    pub ctrl: Vec<Quat>,
    pub layout: Layout,
    d: Vec<Vec3>,
    axes: Vec<Axis>,
    jri: Vec<M3>,
}

#[inline(always)]
fn cross_jc<const N: usize>(a: &V<N>, b: &V<N>) -> V<N> {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// A 3×3 matrix of jets (row-major).
pub type JM3<const N: usize> = [[Jet<N>; 3]; 3];

/// The Jacobian factors of one segment (see [`Model::value_and_factors`]).
pub type Factors<const N: usize> = [JM3<N>; MAXK];

/// R(S)ᵀ for a unit jet quaternion S: the matrix of v ↦ S* v S.
#[inline(always)]
fn rot_t<const N: usize>(q: &JQuat<N>) -> JM3<N> {
    let (w, x, y, z) = (q.w, q.x, q.y, q.z);
    let one = Jet::constant(1.0);
    let (xx, yy, zz) = (x * x, y * y, z * z);
    let (xy, xz, yz) = (x * y, x * z, y * z);
    let (wx, wy, wz) = (w * x, w * y, w * z);
    // R = [[1−2(y²+z²), 2(xy−wz), 2(xz+wy)], [2(xy+wz), 1−2(x²+z²), 2(yz−wx)],
    //      [2(xz−wy), 2(yz+wx), 1−2(x²+y²)]]; return Rᵀ.
    [
        [one - (yy + zz) * 2.0, (xy + wz) * 2.0, (xz - wy) * 2.0],
        [(xy - wz) * 2.0, one - (xx + zz) * 2.0, (yz + wx) * 2.0],
        [(xz + wy) * 2.0, (yz - wx) * 2.0, one - (xx + yy) * 2.0],
    ]
}

#[inline(always)]
fn jm_mul<const N: usize>(a: &JM3<N>, b: &JM3<N>) -> JM3<N> {
    std::array::from_fn(|r| {
        std::array::from_fn(|c| a[r][0] * b[0][c] + a[r][1] * b[1][c] + a[r][2] * b[2][c])
    })
}

/// x += s · a · m for a constant matrix m.
#[inline(always)]
fn jm_acc<const N: usize>(x: &mut JM3<N>, a: &JM3<N>, m: &M3, s: f64) {
    for r in 0..3 {
        for c in 0..3 {
            x[r][c] = x[r][c] + (a[r][0] * (s * m[0][c]) + a[r][1] * (s * m[1][c]) + a[r][2] * (s * m[2][c]));
        }
    }
}

#[inline(always)]
fn transpose(m: &M3) -> M3 {
    std::array::from_fn(|r| std::array::from_fn(|c| m[c][r]))
}

/// The jet of the time derivative (the last coefficient is unknown and set to 0).
#[inline(always)]
pub fn shift<const N: usize>(j: Jet<N>) -> Jet<N> {
    Jet(std::array::from_fn(|k| if k + 1 < N { (k + 1) as f64 * j.0[k + 1] } else { 0.0 }))
}

impl Model {
    pub fn new(ctrl: Vec<Quat>, dt: f64, t0: f64, order: usize) -> Self {
        let layout = Layout::uniform(t0, dt, ctrl.len() + 1 - order, order);
        Self::with_layout(ctrl, layout)
    }

    /// A model on any knot layout (uniform or breakpoints).
    pub fn with_layout(ctrl: Vec<Quat>, layout: Layout) -> Self {
        let mut m = Model {
            order: layout.order,
            dt: layout.dt,
            t0: layout.t0,
            ctrl,
            layout,
            d: vec![],
            axes: vec![],
            jri: vec![],
        };
        m.refresh();
        m
    }

    /// Recomputes the chain logarithms and their inverse Jacobians after the controls moved
    /// (element-wise, in parallel, in the tables' existing storage; the result does not depend
    /// on the thread count).
    pub fn refresh(&mut self) {
        let n = self.ctrl.len();
        self.d.resize(n, [0.0; 3]);
        self.axes.resize(n, Axis::default());
        self.jri.resize(n, [[0.0; 3]; 3]);
        let ctrl = &self.ctrl;
        self.d
            .par_iter_mut()
            .zip(self.axes.par_iter_mut())
            .zip(self.jri.par_iter_mut())
            .with_min_len(4096)
            .enumerate()
            .for_each(|(m, ((d, axis), jri))| {
                if m == 0 {
                    *d = [0.0; 3];
                    *axis = Axis::default();
                    *jri = [[0.0; 3]; 3];
                } else {
                    let v = so3::log(ctrl[m - 1].conj() * ctrl[m]);
                    *d = v;
                    *axis = Axis::from_log(vec3::scale(v, 0.5));
                    *jri = so3::jr_inv(v);
                }
            });
    }

    /// Applies R_m ← R_m Exp(δ_m) (δ has 3 entries per control point).
    pub fn retract(&mut self, delta: &[f64]) {
        *self = self.retracted(delta, None);
    }

    /// A copy with R_m ← R_m Exp(δ_m), built in the storage of `reuse` (a model of the same
    /// size, or None to allocate) without copying the derived tables first.
    pub fn retracted(&self, delta: &[f64], reuse: Option<Model>) -> Model {
        let mut out = reuse.unwrap_or_else(|| Model {
            order: self.order,
            dt: self.dt,
            t0: self.t0,
            ctrl: vec![],
            layout: self.layout.clone(),
            d: vec![],
            axes: vec![],
            jri: vec![],
        });
        out.order = self.order;
        out.dt = self.dt;
        out.t0 = self.t0;
        out.layout = self.layout.clone();
        out.ctrl.resize(self.ctrl.len(), Quat::IDENTITY);
        out.ctrl.par_iter_mut().with_min_len(4096).enumerate().for_each(|(m, o)| {
            *o = (self.ctrl[m] * so3::exp([delta[3 * m], delta[3 * m + 1], delta[3 * m + 2]])).normalize()
        });
        out.refresh();
        out
    }

    pub fn segments(&self) -> usize {
        self.ctrl.len() + 1 - self.order
    }

    /// (segment, local parameter u) of time t (clamped to the domain).
    #[inline]
    pub fn locate(&self, t: f64) -> (usize, f64) {
        self.layout.locate(t)
    }

    /// The width of segment i (Δt for uniform knots).
    #[inline(always)]
    pub fn width(&self, i: usize) -> f64 {
        self.layout.width(i)
    }

    /// The curve on segment i at local parameter u (a jet: u and du/dt = 1/Δt).
    #[inline]
    pub fn value<const N: usize>(&self, i: usize, u: Jet<N>) -> JQuat<N> {
        let mut q = JQuat::constant(self.ctrl[i]);
        for j in 1..self.order {
            let b = Jet::poly(self.layout.row(i, j), u);
            q = q * JQuat::exp_axis(&self.axes[i + j], b);
        }
        q
    }

    /// The curve on segment i with the columns X_m(t) e_c, m = i … i+k−1, c = 0 … 2.
    #[inline]
    pub fn value_and_columns<const N: usize>(&self, i: usize, u: Jet<N>, cols: &mut Cols<N>) -> JQuat<N> {
        let zero = Jet::<N>::constant(0.0);
        let mut mats: Factors<N> = [[[zero; 3]; 3]; MAXK];
        let q = self.value_and_factors::<N>(i, u, &mut mats);
        let k = self.order;
        for mm in 0..k {
            let mut x: JM3<N> = if mm == 0 { mats[0] } else { [[zero; 3]; 3] };
            if mm >= 1 {
                jm_acc(&mut x, &mats[mm], &self.jri[i + mm], 1.0);
            }
            if mm + 1 < k {
                jm_acc(&mut x, &mats[mm + 1], &transpose(&self.jri[i + mm + 1]), -1.0);
            }
            for c in 0..3 {
                cols[mm][c] = [x[0][c], x[1][c], x[2][c]];
            }
        }
        q
    }

    /// J_r⁻¹(d_m) and J_l⁻¹(d_m) of the chain logarithm d_m = Log(R_{m−1}⁻¹ R_m) (m ≥ 1).
    /// J_l⁻¹(d) = J_r⁻¹(−d) = J_r⁻¹(d)ᵀ, to the bit (`so3::jr_inv` is I + ½[d]× + c[d]×² with
    /// [d]× antisymmetric and [d]×² symmetric entry for entry), so only J_r⁻¹ is stored.
    #[inline(always)]
    pub fn chain_jacobians(&self, m: usize) -> (&M3, M3) {
        (&self.jri[m], transpose(&self.jri[m]))
    }

    /// The curve on segment i and the factors of its Jacobian as jets: `mats[0]` = Ad(S_0⁻¹)
    /// and `mats[j]` = M_j (j = 1 … k − 1), from which the columns are
    /// X_i = mats[0] − mats[1] J_l⁻¹(d_{i+1}) and X_{i+j} = mats[j] J_r⁻¹(d_{i+j}) −
    /// mats[j+1] J_l⁻¹(d_{i+j+1}) (constant right factors: any linear map of the jets, such
    /// as the penalty's δω^(m), can be applied to the factors first).
    #[inline]
    pub fn value_and_factors<const N: usize>(&self, i: usize, u: Jet<N>, mats: &mut Factors<N>) -> JQuat<N> {
        // Monomorphised per order (arrays of exactly k entries, loops unrolled).
        match self.order {
            4 => self.factors_k::<N, 4>(i, u, mats),
            5 => self.factors_k::<N, 5>(i, u, mats),
            6 => self.factors_k::<N, 6>(i, u, mats),
            7 => self.factors_k::<N, 7>(i, u, mats),
            8 => self.factors_k::<N, 8>(i, u, mats),
            _ => self.factors_k::<N, MAXK>(i, u, mats),
        }
    }

    fn factors_k<const N: usize, const KK: usize>(
        &self,
        i: usize,
        u: Jet<N>,
        mats: &mut Factors<N>,
    ) -> JQuat<N> {
        let k = self.order.min(KK);
        let one = JQuat::constant(Quat::IDENTITY);
        let zero = Jet::<N>::constant(0.0);
        let mut b = [zero; KK];
        let mut s = [one; KK];
        let mut a = [one; KK];
        let (tab, ko) = (self.layout.table(i), self.order);
        for j in 1..k {
            b[j] = Jet::poly(&tab[j * ko..(j + 1) * ko], u);
            a[j] = JQuat::exp_axis(&self.axes[i + j], b[j]);
        }
        // S_{k−1} = 1, S_{k−2} = A_{k−1}, S_{j−1} = A_j S_j.
        if k >= 2 {
            s[k - 2] = a[k - 1];
        }
        for j in (1..k.saturating_sub(1)).rev() {
            s[j - 1] = a[j] * s[j];
        }
        let q = JQuat::constant(self.ctrl[i]) * s[0];
        // M_j = R(S_j)ᵀ (b I − f1 K + f2 K²), K = [n]×, K² = n nᵀ − I (R(S_{k−1}) = I).
        for j in 1..k {
            let dj = self.d[i + j];
            let aa = vec3::norm(dj);
            let n = if aa > 0.0 { vec3::scale(dj, 1.0 / aa) } else { [0.0; 3] };
            let bj = b[j];
            let (f1, f2) = crate::special::scaled_jr_coefficients(bj, aa);
            let kx = super::so3::skew(n);
            let bm: JM3<N> = std::array::from_fn(|r| {
                std::array::from_fn(|c| {
                    let k2 = n[r] * n[c] - if r == c { 1.0 } else { 0.0 };
                    let diag = if r == c { bj } else { zero };
                    diag - f1 * kx[r][c] + f2 * k2
                })
            });
            mats[j] = if j + 1 == k { bm } else { jm_mul(&rot_t(&s[j]), &bm) };
        }
        mats[0] = rot_t(&s[0]);
        q
    }

    /// Body angular velocity ω = 2 vec(q* q̇) as a jet (accurate to coefficient N − 2).
    #[inline]
    pub fn omega<const N: usize>(q: &JQuat<N>) -> V<N> {
        let qd = JQuat { w: shift(q.w), x: shift(q.x), y: shift(q.y), z: shift(q.z) };
        let o = q.conj() * qd;
        [o.x * 2.0, o.y * 2.0, o.z * 2.0]
    }

    /// δω = ξ̇ + ω × ξ for one column ξ.
    #[inline]
    pub fn delta_omega<const N: usize>(omega: &V<N>, xi: &V<N>) -> V<N> {
        let c = cross_jc(omega, xi);
        std::array::from_fn(|r| shift(xi[r]) + c[r])
    }

    /// The fitted curve as a library spline.
    pub fn to_spline(&self) -> crate::Result<CumulativeBSpline> {
        CumulativeBSpline::new(&self.ctrl, self.dt, self.t0, self.order, true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> Model {
        let ctrl: Vec<Quat> = (0..7)
            .map(|m| {
                let x = m as f64;
                so3::exp([0.3 * (0.7 * x).sin(), 0.2 * x, -0.1 * x * x * 0.3 + 0.05])
            })
            .collect();
        Model::new(ctrl, 0.4, 1.0, 4)
    }

    /// The stored J_r⁻¹ transposed is J_l⁻¹ to the bit, on both sides of the series switch.
    #[test]
    fn jl_inv_is_the_transpose_of_jr_inv() {
        for v in [[0.3, -0.2, 0.9], [1e-9, 2e-9, -1e-9], [1e-3, 0.0, 2e-3], [2.0, 1.0, -0.5], [0.0; 3]] {
            for s in [1.0, 0.01, 3.0] {
                let d = vec3::scale(v, s);
                let (l, r) = (so3::jl_inv(d), so3::jr_inv(d));
                assert_eq!(l, transpose(&r), "{d:?}");
            }
        }
    }

    /// ξ columns against finite differences of Log(q(δ=0)⁻¹ q(δ)) for every control and
    /// component, and their time derivatives against finite differences in t.
    #[test]
    fn columns_match_finite_differences() {
        for order in [4usize, 5, 6] {
            let mut m0 = model();
            m0 = Model::new(
                (0..(order + 3)).map(|j| m0.ctrl[j % 7] * so3::exp([0.01 * j as f64, 0.0, 0.02])).collect(),
                0.4,
                1.0,
                order,
            );
            let i = 2usize;
            for &u in &[0.0, 0.37, 0.99] {
                let mut cols = [[[Jet::<4>::constant(0.0); 3]; 3]; MAXK];
                let q = m0.value_and_columns::<4>(i, Jet::variable(u, 1.0 / m0.dt), &mut cols);
                let q0 = q.value();
                for mm in 0..order {
                    for c in 0..3 {
                        let h = 1e-6;
                        let eval = |s: f64, dtime: f64| {
                            let mut m = m0.clone();
                            let mut del = vec![0.0; 3 * m.ctrl.len()];
                            del[3 * (i + mm) + c] = s;
                            m.retract(&del);
                            m.value::<1>(i, Jet::variable(u + dtime / m.dt, 1.0)).value()
                        };
                        let fd = |dtime: f64| -> Vec3 {
                            let base = m0.value::<1>(i, Jet::variable(u + dtime / m0.dt, 1.0)).value();
                            let p = so3::log(base.conj() * eval(h, dtime));
                            let n = so3::log(base.conj() * eval(-h, dtime));
                            std::array::from_fn(|r| (p[r] - n[r]) / (2.0 * h))
                        };
                        let x0 = fd(0.0);
                        for r in 0..3 {
                            let a = cols[mm][c][r].value();
                            assert!(
                                (a - x0[r]).abs() < 1e-7,
                                "order {order} u {u} m {mm} c {c} r {r}: {a} vs {}",
                                x0[r]
                            );
                        }
                        // d/dt of ξ at fixed δ: central difference in time of the columns.
                        let ht = 1e-4;
                        let xp = fd(ht);
                        let xm = fd(-ht);
                        for r in 0..3 {
                            let d = (xp[r] - xm[r]) / (2.0 * ht);
                            let a = cols[mm][c][r].derivative(1);
                            assert!(
                                (a - d).abs() < 1e-4 * (1.0 + d.abs()),
                                "ξ̇ order {order} m {mm} c {c}: {a} vs {d}"
                            );
                        }
                        let _ = q0;
                    }
                }
            }
        }
    }
}
