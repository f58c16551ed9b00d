//! Knot layout of a fitted spline: uniform (t₀, Δt) or non-uniform breakpoints τ₀ < … < τ_S
//! spanning exactly the data's time range.
//!
//! Order k, S segments, S + k − 1 control points. The full knot vector extends the breakpoints
//! by k − 1 knots at each end with the first and last interval widths, u = (τ₀ − (k−1)h₀, …,
//! τ₀, …, τ_S, …, τ_S + (k−1)h_S), so the domain [u_{k−1}, u_{S+k−1}] is [τ₀, τ_S] and uniform
//! breakpoints give the uniform spline. On segment i, u = (t − τᵢ)/(τ_{i+1} − τᵢ) ∈ [0, 1] and the
//! cumulative basis B̃ⱼ(u) = Σ_{r≥j} B_{i+r,k}(t) (j = 0 … k − 1, B̃₀ = 1) is a polynomial of
//! degree k − 1 in u: its coefficients come from the Cox–De Boor recursion on jets
//! ([`crate::spline::basis_jets`], Taylor coefficients in t − τᵢ, scaled by hᵢ^d), one k×k
//! table per segment; uniform layouts share the cumulative blending matrix (MATH.md §6).

use std::sync::Arc;

/// Where the segments of a fitted spline lie and their cumulative bases.
#[derive(Debug, Clone)]
pub struct Layout {
    /// First knot τ₀ (= the first sample time).
    pub t0: f64,
    /// Uniform knot width; for breakpoints, the mean width (informational).
    pub dt: f64,
    pub segs: usize,
    pub order: usize,
    /// Breakpoints τ₀ … τ_S (non-uniform layouts only).
    pub breaks: Option<Arc<Vec<f64>>>,
    /// Row j of segment i's table (k coefficients of B̃ⱼ in powers of u) at
    /// `basis[i·stride + j·k ..]`; one table (stride 0) for uniform layouts.
    basis: Arc<Vec<f64>>,
    stride: usize,
}

impl Layout {
    pub fn uniform(t0: f64, dt: f64, segs: usize, order: usize) -> Self {
        let m = crate::spline::cumulative_blending_matrix(order);
        Layout { t0, dt, segs, order, breaks: None, basis: Arc::new(m.concat()), stride: 0 }
    }

    /// Breakpoints τ₀ < … < τ_S (S ≥ 1; checked by the caller).
    pub fn nonuniform(breaks: Vec<f64>, order: usize) -> Self {
        let k = order;
        let segs = breaks.len() - 1;
        let full = full_knots(&breaks, k);
        let mut basis = vec![0.0; segs * k * k];
        for i in 0..segs {
            let h = breaks[i + 1] - breaks[i];
            let b = crate::spline::basis_jets::<{ super::model::MAXK }>(&full, i + k - 1, k, breaks[i]);
            let tab = &mut basis[i * k * k..(i + 1) * k * k];
            for j in 0..k {
                // B̃ⱼ = Σ_{r ≥ j} b[r]; coefficient d of (t − τᵢ)^d times h^d is that of u^d.
                let mut hd = 1.0;
                for d in 0..k {
                    let c: f64 = (j..k).map(|r| b[r].0[d]).sum();
                    tab[j * k + d] = c * hd;
                    hd *= h;
                }
            }
        }
        let span = breaks[segs] - breaks[0];
        Layout {
            t0: breaks[0],
            dt: span / segs as f64,
            segs,
            order,
            breaks: Some(Arc::new(breaks)),
            basis: Arc::new(basis),
            stride: k * k,
        }
    }

    /// Row j (coefficients of B̃ⱼ in powers of u) of segment i.
    #[inline(always)]
    pub fn row(&self, i: usize, j: usize) -> &[f64] {
        let k = self.order;
        let o = i * self.stride + j * k;
        &self.basis[o..o + k]
    }

    /// Segment i's whole table (k rows of k coefficients).
    #[inline(always)]
    pub fn table(&self, i: usize) -> &[f64] {
        let o = i * self.stride;
        &self.basis[o..o + self.order * self.order]
    }

    /// Segment i's width.
    #[inline(always)]
    pub fn width(&self, i: usize) -> f64 {
        match &self.breaks {
            Some(b) => b[i + 1] - b[i],
            None => self.dt,
        }
    }

    /// (segment, local parameter u) of time t (clamped to the domain).
    #[inline]
    pub fn locate(&self, t: f64) -> (usize, f64) {
        let last = self.segs - 1;
        match &self.breaks {
            None => {
                let x = (t - self.t0) / self.dt;
                let i = (x.floor().max(0.0) as usize).min(last);
                (i, x - i as f64)
            }
            Some(b) => {
                let i = b.partition_point(|&v| v <= t).saturating_sub(1).min(last);
                (i, (t - b[i]) / (b[i + 1] - b[i]))
            }
        }
    }

    /// The Greville abscissae of the S + k − 1 control points: control m's is the mean of knots
    /// m + 1 … m + k − 1 of the full knot vector (uniform: t₀ + (m − (k − 2)/2)Δt).
    pub fn abscissae(&self) -> Vec<f64> {
        let k = self.order;
        let n = self.segs + k - 1;
        match self.full_knots() {
            None => (0..n).map(|m| self.t0 + (m as f64 - (k as f64 - 2.0) / 2.0) * self.dt).collect(),
            Some(u) => (0..n).map(|m| u[m + 1..m + k].iter().sum::<f64>() / (k - 1) as f64).collect(),
        }
    }

    /// The full knot vector (S + 2k − 1 knots) of a non-uniform layout.
    pub fn full_knots(&self) -> Option<Vec<f64>> {
        self.breaks.as_ref().map(|b| full_knots(b, self.order))
    }
}

/// Breakpoints extended by k − 1 knots at each end with the end intervals' widths.
pub fn full_knots(breaks: &[f64], k: usize) -> Vec<f64> {
    let s = breaks.len() - 1;
    let (h0, h1) = (breaks[1] - breaks[0], breaks[s] - breaks[s - 1]);
    let mut out = Vec::with_capacity(s + 2 * k - 1);
    for j in (1..k).rev() {
        out.push(breaks[0] - j as f64 * h0);
    }
    out.extend_from_slice(breaks);
    for j in 1..k {
        out.push(breaks[s] + j as f64 * h1);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jet::Jet;

    /// Uniform breakpoints give the uniform tables (to rounding); the non-uniform cumulative
    /// basis is 1 at j = 0, partitions unity, and is continuous across breakpoints with k − 2
    /// derivatives (values and derivatives of B̃ⱼ at u = 1 of segment i equal those at u = 0
    /// of segment i + 1 for the same control index).
    #[test]
    fn tables_match_uniform_and_join_smoothly() {
        for k in [4usize, 5, 6] {
            let b: Vec<f64> = (0..9).map(|i| 2.0 + 0.25 * i as f64).collect();
            let nu = Layout::nonuniform(b.clone(), k);
            let un = Layout::uniform(2.0, 0.25, 8, k);
            for i in 0..8 {
                for j in 0..k {
                    for (x, y) in nu.row(i, j).iter().zip(un.row(i, j)) {
                        assert!((x - y).abs() < 1e-12, "k {k} seg {i} row {j}: {x} vs {y}");
                    }
                }
            }
            let b = vec![0.0, 0.1, 0.5, 0.6, 1.7, 2.0, 2.05, 3.0];
            let nu = Layout::nonuniform(b.clone(), k);
            for i in 0..b.len() - 2 {
                let (h0, h1) = (nu.width(i), nu.width(i + 1));
                // Control m = i + j on segment i is control index j − 1 on segment i + 1.
                for j in 1..k {
                    for d in 0..k - 1 {
                        let end = Jet::<6>::poly(nu.row(i, j), Jet::variable(1.0, 1.0 / h0));
                        let start = Jet::<6>::poly(nu.row(i + 1, j - 1), Jet::variable(0.0, 1.0 / h1));
                        let (a, c) = (end.derivative(d), start.derivative(d));
                        assert!(
                            (a - c).abs() < 1e-9 * (1.0 + a.abs()),
                            "k {k} joint {i} row {j} d {d}: {a} vs {c}"
                        );
                    }
                }
                assert!((Jet::<1>::poly(nu.row(i, 0), Jet::constant(0.3)).value() - 1.0).abs() < 1e-14);
            }
            // Greville abscissae are increasing and the uniform formula is the general one.
            let un = Layout::uniform(0.0, 0.5, 6, k);
            let nu = Layout::nonuniform((0..7).map(|i| 0.5 * i as f64).collect(), k);
            let (xu, xn) = (un.abscissae(), nu.abscissae());
            assert_eq!(xu.len(), 6 + k - 1);
            for m in 0..xu.len() {
                assert!((xu[m] - xn[m]).abs() < 1e-12);
                assert!(m == 0 || xn[m] > xn[m - 1]);
            }
        }
    }

    #[test]
    fn locate_finds_the_segment() {
        let nu = Layout::nonuniform(vec![0.0, 0.1, 0.5, 2.0], 4);
        assert_eq!(nu.locate(0.0), (0, 0.0));
        assert_eq!(nu.locate(0.3).0, 1);
        assert!((nu.locate(0.3).1 - 0.5).abs() < 1e-15);
        assert_eq!(nu.locate(2.0), (2, 1.0));
        assert_eq!(nu.locate(0.5).0, 2);
    }
}
