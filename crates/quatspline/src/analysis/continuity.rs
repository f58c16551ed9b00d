//! The continuity certificate: what is true at every joint of any spline (MATH.md §9).
//!
//! At joint k (time τ_k) with left limits L_m = q^(m)(τ_k⁻) from segment k−1 and right limits
//! R_m from segment k (m = 0 … 5, time derivatives — up to q''' from the four-term jets, up to
//! q⁽⁵⁾ from the six-term jets when `order` > 3; the left side negated when L₀·R₀ < 0, since
//! q and −q are the same rotation), it reports:
//! - the jumps |R_m − L_m|, absolute and relative to max(|L_m|, |R_m|, 1e-4·M_m) where M_m is
//!   the largest |q^(m)| met at any joint or segment midpoint (so a derivative that vanishes at a key does not
//!   turn rounding into a "jump", and the measure does not depend on the time unit);
//! - the parametric order C^k reached: the largest k with every relative jump m ≤ k at most
//!   `tol` (−1 when even the positions differ);
//! - the geometric (Beta) constraints with fitted parameters: G¹ R₁ = ξ L₁ with
//!   ξ = ⟨L₁, R₁⟩/|L₁|², and G² R₂ = ξ² L₂ + δ L₁ with δ = ⟨R₂ − ξ² L₂, L₁⟩/|L₁|²,
//!   and their residuals relative to |R₁| and |R₂|.

use crate::quat::Quat;
use crate::spline::Spline;

/// The certificate of one joint.
#[derive(Debug, Clone, PartialEq)]
pub struct JointReport {
    /// Joint index (1 … segments−1; `segments` is the seam of a closed curve).
    pub index: usize,
    pub time: f64,
    /// |R_m − L_m| for m = 0 … 5 (entries above max(3, order) are 0: not computed).
    pub jump_abs: [f64; 6],
    /// Jumps relative to the derivative's size (see the module doc).
    pub jump_rel: [f64; 6],
    /// The parametric order reached (−1 … `order`).
    pub order: i32,
    /// Fitted G¹ factor ξ and the relative residual |R₁ − ξ L₁| / |R₁|.
    pub g1_xi: f64,
    pub g1_residual: f64,
    /// Fitted G² factor δ and the relative residual |R₂ − ξ² L₂ − δ L₁| / |R₂|.
    pub g2_delta: f64,
    pub g2_residual: f64,
}

fn dist(a: Quat, b: Quat) -> f64 {
    (a - b).norm()
}

/// The derivatives q … q⁽⁵⁾ of segment `seg` at t: from the six-term jets when `deep` (and
/// the spline provides them), else q … q''' with zeros above.
fn derivs(s: &dyn Spline, seg: usize, t: f64, deep: bool) -> [Quat; 6] {
    if deep {
        if let Some(q) = s.segment_jet6(seg, t) {
            return q.derivatives();
        }
    }
    let d = s.segment_jet4(seg, t).derivatives();
    let z = Quat::new(0.0, 0.0, 0.0, 0.0);
    [d[0], d[1], d[2], d[3], z, z]
}

/// Certificates for every interior joint (and the seam of a closed curve), checking orders
/// 0 … `order` (≤ 5) against `tol`.
/// Orders 4 and 5 need a spline with six-term jets ([`Spline::segment_jet6`]); for one
/// without them the reached order stops at 3.
pub fn continuity(s: &dyn Spline, order: usize, tol: f64) -> Vec<JointReport> {
    let order = order.min(5);
    let deep = order > 3;
    let avail = if deep && s.segment_jet6(0, s.joints()[0]).is_some() { 5 } else { 3 };
    let j = s.joints();
    let last = j.len() - 1;
    // Interior joints, and for a closed curve the seam (index `last`: the end of the last
    // segment against the start of the first).
    let seam = if s.closed() { Some(last) } else { None };
    let sides: Vec<([Quat; 6], [Quat; 6])> = (1..last)
        .chain(seam)
        .map(|k| {
            let (lk, rk) = if k == last { (j[last], j[0]) } else { (j[k], j[k]) };
            let mut left = derivs(s, k - 1, lk, deep);
            let right = derivs(s, k % last, rk, deep);
            // q and −q are the same rotation: compare on the double cover's same sheet.
            if left[0].dot(right[0]) < 0.0 {
                left = left.map(|d| -d);
            }
            (left, right)
        })
        .collect();
    // The derivative sizes met along the curve: at every joint and every segment midpoint.
    let mut big = [0.0f64; 6];
    let mids = (0..j.len() - 1).map(|k| derivs(s, k, 0.5 * (j[k] + j[k + 1]), deep));
    for d in sides.iter().flat_map(|(l, r)| [*l, *r]).chain(mids) {
        for m in 0..6 {
            big[m] = big[m].max(d[m].norm());
        }
    }
    sides
        .iter()
        .enumerate()
        .map(|(i, (l, r))| {
            let jump_abs: [f64; 6] = std::array::from_fn(|m| dist(l[m], r[m]));
            let jump_rel: [f64; 6] = std::array::from_fn(|m| {
                let scale = l[m].norm().max(r[m].norm()).max(1e-4 * big[m]).max(f64::MIN_POSITIVE);
                jump_abs[m] / scale
            });
            let mut reached = -1;
            for m in 0..=order.min(avail) {
                if jump_rel[m] <= tol {
                    reached = m as i32;
                } else {
                    break;
                }
            }
            let ll = l[1].norm_squared();
            let xi = if ll > 0.0 { l[1].dot(r[1]) / ll } else { 1.0 };
            let g1 = dist(r[1], l[1].scale(xi)) / r[1].norm().max(f64::MIN_POSITIVE);
            let rest = r[2] - l[2].scale(xi * xi);
            let delta = if ll > 0.0 { rest.dot(l[1]) / ll } else { 0.0 };
            let g2 = dist(rest, l[1].scale(delta)) / r[2].norm().max(f64::MIN_POSITIVE);
            JointReport {
                index: i + 1,
                time: j[i + 1],
                jump_abs,
                jump_rel,
                order: reached,
                g1_xi: xi,
                g1_residual: g1,
                g2_delta: delta,
                g2_residual: g2,
            }
        })
        .collect()
}
