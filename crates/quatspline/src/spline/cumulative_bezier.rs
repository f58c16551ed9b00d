//! Cumulative spherical Bézier curve (Kim, Kim & Shin 1995; seeds 002, 003; MATH.md §4).
//!
//! q(u) = q₀ Π_{j=1..n} (q_{j−1}* q_j)^{B̃_{j,n}(u)}, B̃_{j,n} = Σ_{i≥j} B_{i,n} (Bernstein).
//! Cubic: B̃₁ = 1−(1−u)³, B̃₂ = 3u²−2u³, B̃₃ = u³. Passes through q₀ and qₙ with the same end
//! tangents as the de Casteljau curve, but it is a different curve in between. One curve on
//! u ∈ [0, 1]: C^∞. Every factor has a constant logarithm, so it is cheap to evaluate.
//!
//! Basis without overflow for any degree: C(n, i) overflows f64 at n = 1030 and uᶦ underflows,
//! so the binomial-times-powers form returned NaN everywhere from 1,024 control points on.
//! Each row B_{·,m}(u) is computed from its largest term, exp(ln C(m, k) + k ln u + (m−k)
//! ln(1−u)) at the mode k = ⌊(m+1)u⌋ (ln C from a table of ln k!), then outwards by the term
//! ratios B_{i+1}/B_i = (m−i)/(i+1) · u/(1−u), which only shrink: no term can overflow and
//! the small ones underflow harmlessly to 0. The derivatives in u come from the Bernstein
//! identities B̃_j' = n B_{j−1,n−1}, B̃_j'' = n(n−1)(B_{j−2,n−2} − B_{j−1,n−2}),
//! B̃_j''' = n(n−1)(n−2)(B_{j−3,n−3} − 2B_{j−2,n−3} + B_{j−1,n−3}) and are composed with
//! u(t). Cost per sample O(n); the degree is capped at [`MAX_CONTROL_POINTS`] − 1 so that
//! cost stays bounded (documented in the README).

use super::{prepare_keys, segment_jets, Spline};
use crate::error::{Error, Result};
use crate::jet::{Axis, JQuat};
use crate::quat::Quat;
use crate::simd::cumulative::{Basis, CumulativeTable, SegmentForm};

/// The most control points a cumulative Bézier curve takes (degree 4,095): O(n) work per
/// sample, about 0.1 ms at this size. For more keys, a spline with local support
/// (`CumulativeBSpline`, registry name "bspline") costs O(1) per sample.
pub const MAX_CONTROL_POINTS: usize = 4096;

/// One cumulative Bézier curve of degree up to 4,095 on u ∈ [0, 1].
#[derive(Debug, Clone)]
pub struct CumulativeBezier {
    ctrl: Vec<Quat>,
    logs: Vec<Axis>,
    /// ln k! for k = 0 … n.
    ln_fact: Vec<f64>,
    joints: [f64; 2],
    /// Flat per-segment data of the batch kernels (`crate::simd::cumulative`).
    batch: Option<crate::simd::cumulative::CumulativeTable>,
}

impl CumulativeBezier {
    /// Control points q₀ … qₙ (2 ≤ n + 1 ≤ [`MAX_CONTROL_POINTS`]).
    /// `domain` (t₀, t₁) maps u = (t − t₀)/(t₁ − t₀); (0, 1) is the plain curve.
    pub fn new(ctrl: &[Quat], domain: (f64, f64), canonicalize: bool) -> Result<Self> {
        let joints = super::check_domain(domain)?;
        if ctrl.len() > MAX_CONTROL_POINTS {
            return Err(Error::invalid(
                "control_points",
                format!(
                    "{} control points: a cumulative Bézier curve takes at most {MAX_CONTROL_POINTS} \
                     (its cost per sample grows with the degree); for more keys use the cumulative \
                     B-spline (CumulativeBSpline, method 'bspline'), which costs the same at any size",
                    ctrl.len()
                ),
            ));
        }
        let ctrl = prepare_keys(ctrl, "control_points", 2, canonicalize)?;
        let logs = super::chain_logs(&ctrl);
        let n = ctrl.len() - 1;
        let mut ln_fact = vec![0.0; n + 1];
        for k in 2..=n {
            ln_fact[k] = ln_fact[k - 1] + (k as f64).ln();
        }
        // factor j's weight B̃_j = Σ_{l≥j} B_{l,n}: Bernstein coefficients 1 from l = j on
        // (only for degrees the kernels take: building the forms costs O(n²) memory)
        let small = n <= crate::simd::cumulative::MAX_FACTORS;
        let batch = small
            .then(|| {
                CumulativeTable::new(&joints, Basis::Bernstein, |_| SegmentForm {
                    base: ctrl[0],
                    factors: (1..=n)
                        .map(|j| (logs[j - 1], (0..=n).map(|l| if l >= j { 1.0 } else { 0.0 }).collect()))
                        .collect(),
                })
            })
            .flatten();
        Ok(CumulativeBezier { ctrl, logs, ln_fact, joints, batch })
    }

    /// B_{i,m}(u) for i = 0 … m into `out[0..=m]`, overflow-free (see the module comment).
    fn bernstein_row(&self, m: usize, u: f64, out: &mut [f64]) {
        let out = &mut out[..=m];
        out.fill(0.0);
        if u <= 0.0 {
            out[0] = 1.0;
            return;
        }
        if u >= 1.0 {
            out[m] = 1.0;
            return;
        }
        let k = (((m + 1) as f64 * u).floor() as usize).min(m);
        let f = &self.ln_fact;
        let ln_c = f[m] - f[k] - f[m - k];
        out[k] = (ln_c + k as f64 * u.ln() + (m - k) as f64 * (-u).ln_1p()).exp();
        let r = u / (1.0 - u);
        for i in k..m {
            out[i + 1] = out[i] * ((m - i) as f64 / (i + 1) as f64) * r;
            if out[i + 1] == 0.0 {
                break;
            }
        }
        for i in (1..=k).rev() {
            out[i - 1] = out[i] * (i as f64 / (m - i + 1) as f64) / r;
            if out[i - 1] == 0.0 {
                break;
            }
        }
    }

    /// B̃_j(u) and its first N − 1 derivatives in u, for j = 1 … n: `d[j][r]`.
    fn cumulative_basis<const N: usize>(&self, u: f64) -> Vec<[f64; N]> {
        let n = self.ctrl.len() - 1;
        let u = u.clamp(0.0, 1.0);
        let mut d = vec![[0.0; N]; n + 1];
        let mut row = vec![0.0; n + 1];
        // Value: suffix sums of B_{i,n}.
        self.bernstein_row(n, u, &mut row);
        let mut tail = 0.0;
        for j in (1..=n).rev() {
            tail += row[j];
            d[j][0] = tail.min(1.0);
        }
        // b(i) = B_{i,m} with zero outside 0 … m.
        let get =
            |row: &[f64], m: usize, i: isize| if i < 0 || i as usize > m { 0.0 } else { row[i as usize] };
        let nf = n as f64;
        for r in 1..N.min(4) {
            if r > n {
                break; // a degree-n polynomial: higher derivatives vanish
            }
            let m = n - r;
            self.bernstein_row(m, u, &mut row);
            let scale: f64 = (0..r).map(|k| nf - k as f64).product();
            for (j, dj) in d.iter_mut().enumerate().skip(1) {
                let j = j as isize;
                let v = match r {
                    1 => get(&row, m, j - 1),
                    2 => get(&row, m, j - 2) - get(&row, m, j - 1),
                    _ => get(&row, m, j - 3) - 2.0 * get(&row, m, j - 2) + get(&row, m, j - 1),
                };
                dj[r] = scale * v;
            }
        }
        d
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, _seg: usize, t: f64) -> JQuat<N> {
        let n = self.ctrl.len() - 1;
        let u = super::local::<N>(t, self.joints[0], self.joints[1]);
        let basis = self.cumulative_basis::<N>(u.value());
        let mut q = JQuat::constant(self.ctrl[0]);
        for j in 1..=n {
            q = q * JQuat::exp_axis(&self.logs[j - 1], u.compose(basis[j]));
        }
        q
    }
}

impl Spline for CumulativeBezier {
    segment_jets!();
    fn name(&self) -> &'static str {
        "cumulative_bezier"
    }
    fn joints(&self) -> &[f64] {
        &self.joints
    }
    fn interpolates(&self) -> bool {
        false
    }
    fn continuity(&self) -> u8 {
        u8::MAX
    }
    fn batch(&self) -> Option<&dyn crate::simd::BatchKernel> {
        self.batch.as_ref().map(|b| b as &dyn crate::simd::BatchKernel)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression (issue 2.1 item 5): from 1,024 control points the basis was NaN (C(n, i)
    /// overflowed). The overflow-free rows must equal the exact Bernstein values, which we
    /// get here in log space term by term (an independent formula), at several thousand.
    #[test]
    fn bernstein_rows_match_log_space_reference_at_thousands_of_points() {
        for &n in &[3usize, 40, 1023, 1024, 1100, 3000, 4095] {
            let ctrl = vec![Quat::IDENTITY; n + 1];
            let c = CumulativeBezier::new(&ctrl, (0.0, 1.0), false).unwrap();
            let mut row = vec![0.0; n + 1];
            for &u in &[1e-9, 0.001, 0.3, 0.5, 0.77, 0.999, 1.0 - 1e-12] {
                c.bernstein_row(n, u, &mut row);
                let sum: f64 = row.iter().sum();
                assert!((sum - 1.0).abs() < 1e-12 * (n as f64).sqrt().max(1.0), "n {n} u {u}: sum {sum}");
                for i in (0..=n).step_by((n / 17).max(1)) {
                    let lc = c.ln_fact[n] - c.ln_fact[i] - c.ln_fact[n - i];
                    let want = (lc + i as f64 * u.ln() + (n - i) as f64 * (1.0 - u).ln()).exp();
                    let tol = 1e-12 * want + 1e-300;
                    assert!(
                        (row[i] - want).abs() <= tol.max(want * 2e-13 * n as f64),
                        "n {n} u {u} i {i}: {} vs {want}",
                        row[i]
                    );
                }
            }
        }
    }

    #[test]
    fn too_many_control_points_name_the_limit_and_the_alternative() {
        let ctrl = vec![Quat::IDENTITY; MAX_CONTROL_POINTS + 1];
        let e = CumulativeBezier::new(&ctrl, (0.0, 1.0), false).unwrap_err().to_string();
        assert!(e.contains("at most 4096") && e.contains("bspline"), "{e}");
    }
}
