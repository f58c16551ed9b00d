//! Non-uniform cumulative B-spline on SO(3), any order k, explicit knot vector
//! (Kim, Kim & Shin 1995 cumulative form; De Boor 1972 / Cox 1972 basis recursion; the uniform
//! case is Sommer et al., CVPR 2020 and basalt's `so3_spline`, see `cumulative_bspline.rs`).
//!
//! Control rotations q₀ … q_{n−1}, order k (degree k − 1), knots u₀ ≤ u₁ ≤ … ≤ u_{n+k−1}.
//! The domain is [u_{k−1}, u_n]; on a knot interval [u_m, u_{m+1}) (k−1 ≤ m ≤ n−1, u_m < u_{m+1})
//! q(t) = q_{m−k+1} Π_{j=m−k+2..m} exp(B̃ⱼ(t) ωⱼ), ωⱼ = log(q_{j−1}* qⱼ),
//! with the cumulative basis B̃ⱼ = Σ_{l=j..m} B_{l,k} and B_{l,k} the B-spline basis of the knots
//! from the Cox–De Boor recursion (NURBS Book A2.2: only the k non-zero functions, whose
//! denominators u_{m+r+1} − u_{m+1−d+r} are knot differences ≥ u_{m+1} − u_m > 0). The
//! recursion runs on jets in t, so q', q'', q''' are exact (the basis is a polynomial per
//! interval). With uniform knots it is the uniform spline to rounding (tested to 1e-14).
//!
//! Continuity: at a joint (distinct interior knot) of multiplicity μ the curve is C^(k−1−μ) in
//! time (the basis is, and the cumulative product of smooth factors preserves it); `continuity()`
//! is the minimum over interior joints (k − 2 for simple knots). Knots may repeat up to k times
//! (k at the ends clamps the curve to the end control rotations), at most k − 1 times inside
//! the domain. Approximating: it passes through control rotations only at clamped ends.

use super::{prepare_keys, segment_jets, Spline};
use crate::error::{Error, Result, Short};
use crate::jet::{Axis, JQuat, Jet};
use crate::quat::Quat;

/// The k basis functions B_{m−k+1..m, k}(t) that are non-zero on [u_m, u_{m+1}), as jets in t.
#[inline(always)]
pub fn basis_jets<const N: usize>(knots: &[f64], m: usize, k: usize, t: f64) -> [Jet<N>; 12] {
    let mut b = [Jet::<N>::constant(0.0); 12];
    let mut left = [Jet::<N>::constant(0.0); 12];
    let mut right = [Jet::<N>::constant(0.0); 12];
    // Local coordinate x = t − u_m: knot differences are exact-ish, no cancellation with t.
    let um = knots[m];
    let x = Jet::<N>::variable(t - um, 1.0);
    b[0] = Jet::constant(1.0);
    for d in 1..k {
        left[d] = x + (um - knots[m + 1 - d]);
        right[d] = -x + (knots[m + d] - um);
        let mut saved = Jet::constant(0.0);
        for r in 0..d {
            let inv = 1.0 / (knots[m + r + 1] - knots[m + 1 + r - d]);
            let temp = b[r] * inv;
            b[r] = saved + right[r + 1] * temp;
            saved = left[d - r] * temp;
        }
        b[d] = saved;
    }
    b
}

/// Checks a knot vector for `n` control points of order `k` and returns, per segment, the
/// knot index m of its interval, the joint times, and the minimum continuity at interior joints.
pub fn check_knots(knots: &[f64], n: usize, k: usize) -> Result<(Vec<usize>, Vec<f64>, u8)> {
    if knots.len() < 2 * k {
        return Err(Error::invalid(
            "knots",
            format!("order {k} needs at least 2·k = {} knots, got {}", 2 * k, knots.len()),
        ));
    }
    if knots.len() != n + k {
        return Err(Error::invalid(
            "knots",
            format!(
                "expected n + k = {} knots for {n} control rotations of order {k}, got {}",
                n + k,
                knots.len()
            ),
        ));
    }
    for (i, &u) in knots.iter().enumerate() {
        if !u.is_finite() {
            return Err(Error::NonFinite { arg: "knots", index: i });
        }
        if u.abs() > super::MAX_TIME {
            return Err(Error::invalid("knots", format!("knot {i} = {} is beyond |t| ≤ 1e30", Short(u))));
        }
        if i > 0 && u < knots[i - 1] {
            return Err(Error::invalid(
                "knots",
                format!("not non-decreasing at index {i} ({} after {})", Short(u), Short(knots[i - 1])),
            ));
        }
    }
    let mut i = 0;
    while i < knots.len() {
        let mut j = i;
        while j + 1 < knots.len() && knots[j + 1] == knots[i] {
            j += 1;
        }
        let mult = j - i + 1;
        let inside = knots[i] > knots[k - 1] && knots[i] < knots[n];
        if mult > k || (inside && mult > k - 1) {
            return Err(Error::invalid(
                "knots",
                format!(
                    "knot {} (index {i}) repeats {mult} times; at most {} {} the domain",
                    Short(knots[i]),
                    if inside { k - 1 } else { k },
                    if inside { "inside" } else { "at the ends of" }
                ),
            ));
        }
        i = j + 1;
    }
    if knots[n] <= knots[k - 1] {
        return Err(Error::invalid(
            "knots",
            format!(
                "the domain [u_{}, u_{n}] = [{}, {}] is empty",
                k - 1,
                Short(knots[k - 1]),
                Short(knots[n])
            ),
        ));
    }
    let mut seg = Vec::new();
    let mut joints = vec![knots[k - 1]];
    let mut cont = (k - 2) as u8;
    for m in k - 1..n {
        if knots[m + 1] > knots[m] {
            super::check_span("knots", knots[m], knots[m + 1], m + 1)?;
            if !seg.is_empty() {
                let mult = knots.iter().filter(|&&u| u == knots[m]).count();
                cont = cont.min((k - 1 - mult) as u8);
            }
            seg.push(m);
            joints.push(knots[m + 1]);
        }
    }
    Ok((seg, joints, cont))
}

/// Non-uniform cumulative B-spline of order k on SO(3).
#[derive(Debug, Clone)]
pub struct NonUniformBSpline {
    ctrl: Vec<Quat>,
    logs: Vec<Axis>,
    knots: Vec<f64>,
    order: usize,
    seg: Vec<usize>,
    joints: Vec<f64>,
    continuity: u8,
}

impl NonUniformBSpline {
    /// `ctrl`: n ≥ k control rotations; `knots`: n + k non-decreasing knots; 2 ≤ k ≤ 12.
    pub fn new(ctrl: &[Quat], knots: &[f64], order: usize, canonicalize: bool) -> Result<Self> {
        if !(2..=12).contains(&order) {
            return Err(Error::invalid("order", format!("expected 2 ≤ order ≤ 12, got {order}")));
        }
        let ctrl = prepare_keys(ctrl, "control_quats", order, canonicalize)?;
        let (seg, joints, continuity) = check_knots(knots, ctrl.len(), order)?;
        let mut logs = vec![Axis::default()];
        logs.extend(super::chain_logs(&ctrl));
        Ok(NonUniformBSpline { ctrl, logs, knots: knots.to_vec(), order, seg, joints, continuity })
    }

    /// The knot vector.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        let m = self.seg[i];
        let k = self.order;
        let b = basis_jets::<N>(&self.knots, m, k, t);
        // b[r] = B_{m−k+1+r}; B̃ for j = m−k+1+r (r ≥ 1) is the sum of b[r..k].
        let first = m + 1 - k;
        let mut q = JQuat::constant(self.ctrl[first]);
        let mut cum = [Jet::<N>::constant(0.0); 12];
        let mut acc = Jet::constant(0.0);
        for r in (1..k).rev() {
            acc = acc + b[r];
            cum[r] = acc;
        }
        for r in 1..k {
            q = q * JQuat::exp_axis(&self.logs[first + r], cum[r]);
        }
        q
    }
}

impl Spline for NonUniformBSpline {
    segment_jets!();
    fn name(&self) -> &'static str {
        "nonuniform_bspline"
    }
    fn joints(&self) -> &[f64] {
        &self.joints
    }
    fn interpolates(&self) -> bool {
        false
    }
    fn continuity(&self) -> u8 {
        self.continuity
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spline::CumulativeBSpline;

    fn ctrl(n: usize) -> Vec<Quat> {
        (0..n)
            .map(|i| {
                let a = i as f64;
                Quat::new(1.0, 0.3 * a.sin(), 0.2 * a, -0.1 * a * a).normalize()
            })
            .collect()
    }

    #[test]
    fn uniform_knots_equal_the_uniform_spline() {
        for k in 2..=6 {
            let q = ctrl(9);
            let (dt, t0) = (0.5, 1.0);
            let knots: Vec<f64> = (0..q.len() + k).map(|i| t0 + (i as f64 - (k - 1) as f64) * dt).collect();
            let a = NonUniformBSpline::new(&q, &knots, k, true).unwrap();
            let b = CumulativeBSpline::new(&q, dt, t0, k, true).unwrap();
            assert_eq!(a.joints().len(), b.joints().len());
            for s in 0..a.segments() {
                for f in [0.0, 0.3, 0.77, 1.0] {
                    let t = a.joints()[s] + f * dt;
                    let (x, y) = (a.segment_jet4(s, t).derivatives(), b.segment_jet4(s, t).derivatives());
                    for d in 0..4 {
                        let scale = 1.0f64.max(y[d].norm());
                        assert!((x[d] - y[d]).norm() <= 1e-14 * scale, "k={k} seg={s} d={d}");
                    }
                }
            }
        }
    }

    #[test]
    fn basis_is_a_partition_of_unity() {
        let knots = [0.0, 0.0, 0.0, 0.0, 0.3, 1.1, 1.2, 2.0, 2.0, 2.0, 2.0];
        for m in 3..7 {
            let t = 0.5 * (knots[m] + knots[m + 1]);
            let b = basis_jets::<4>(&knots, m, 4, t);
            let s = b[..4].iter().fold(Jet::<4>::constant(0.0), |a, &x| a + x);
            assert!((s.0[0] - 1.0).abs() < 1e-15 && s.0[1].abs() < 1e-13 && s.0[2].abs() < 1e-12);
        }
    }

    #[test]
    fn bad_knots() {
        let q = ctrl(5);
        assert!(NonUniformBSpline::new(&q, &[0.0; 3], 4, true).is_err());
        let mut k: Vec<f64> = (0..9).map(|i| i as f64).collect();
        assert!(NonUniformBSpline::new(&q, &k, 4, true).is_ok());
        k[5] = 3.5;
        assert!(NonUniformBSpline::new(&q, &k, 4, true).is_err());
        let k = [0.0, 1.0, 2.0, 3.0, 3.0, 3.0, 3.0, 7.0, 8.0];
        assert!(NonUniformBSpline::new(&q, &k, 4, true).is_err());
    }
}
