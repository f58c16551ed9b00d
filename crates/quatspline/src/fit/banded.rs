//! Symmetric positive-definite banded matrices: Cholesky factorisation, solves and the
//! selected inverse (the entries of H⁻¹ inside the band) in O(n p²) time and O(n p) memory
//! for n unknowns and half-bandwidth p.
//!
//! Storage: lower band, `a[i·(p+1) + d] = H[i][i − d]` for d = 0 … p (entries with i − d < 0
//! are unused). Cholesky H = L Lᵀ overwrites the band with L (Golub & Van Loan, Matrix
//! Computations, 4th ed., Alg. 4.3.5, band Cholesky).
//!
//! Selected inversion (Takahashi, Fagan & Chen 1973; Hutchinson & de Hoog 1985 for smoothing
//! splines): with Σ = H⁻¹ = L⁻ᵀ L⁻¹, LᵀΣ = L⁻¹ is upper-triangular in its upper part, so
//! for j ≥ i: Σ_ij = (δ_ij / L_ii − Σ_{k=i+1}^{i+p} L_ki Σ_kj) / L_ii, evaluated for i = n−1 … 0
//! and j = i+p … i. Only band entries of Σ are ever needed, which gives tr(H⁻¹ G) for any
//! banded G — the trace of the hat matrix used by generalised cross-validation.

use crate::error::{Error, Result};

/// A symmetric banded matrix (lower band storage).
#[derive(Debug, Clone)]
pub struct Band {
    pub n: usize,
    pub p: usize,
    pub a: Vec<f64>,
}

impl Band {
    pub fn zeros(n: usize, p: usize) -> Self {
        Band { n, p, a: vec![0.0; n * (p + 1)] }
    }

    #[inline(always)]
    pub fn idx(&self, i: usize, j: usize) -> usize {
        // i ≥ j, i − j ≤ p
        i * (self.p + 1) + (i - j)
    }

    /// H[i][j] for |i − j| ≤ p.
    #[inline(always)]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        if i >= j {
            self.a[self.idx(i, j)]
        } else {
            self.a[self.idx(j, i)]
        }
    }

    /// Adds a dense symmetric block `blk` (m×m, row-major, full) at rows/cols `off … off+m`.
    pub fn add_block(&mut self, off: usize, m: usize, blk: &[f64], scale: f64) {
        for r in 0..m {
            for c in 0..=r {
                let i = self.idx(off + r, off + c);
                self.a[i] += scale * blk[r * m + c];
            }
        }
    }

    /// self + s·other (same shape).
    pub fn axpy(&self, s: f64, other: &Band) -> Band {
        let a = self.a.iter().zip(&other.a).map(|(x, y)| x + s * y).collect();
        Band { n: self.n, p: self.p, a }
    }

    /// out = self + s·other (same shape; `out` reused, no allocation).
    pub fn axpy_into(&self, s: f64, other: &Band, out: &mut Band) {
        out.n = self.n;
        out.p = self.p;
        out.a.clear();
        out.a.extend(self.a.iter().zip(&other.a).map(|(x, y)| x + s * y));
    }

    /// self ← self + s·other (same shape; in place: the same sums as [`Band::axpy_into`]).
    pub fn axpy_assign(&mut self, s: f64, other: &Band) {
        for (x, y) in self.a.iter_mut().zip(&other.a) {
            *x += s * y;
        }
    }

    /// y = H x.
    pub fn matvec(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n];
        for i in 0..self.n {
            let lo = i.saturating_sub(self.p);
            for j in lo..=i {
                let v = self.a[self.idx(i, j)];
                y[i] += v * x[j];
                if j != i {
                    y[j] += v * x[i];
                }
            }
        }
        y
    }

    /// The diagonal.
    pub fn diag(&self) -> Vec<f64> {
        (0..self.n).map(|i| self.a[i * (self.p + 1)]).collect()
    }

    /// Cholesky factor L (same storage). Fails with the pivot index if H is not numerically
    /// positive definite.
    pub fn cholesky(&self) -> Result<Band> {
        let mut l = self.clone();
        l.cholesky_in_place()?;
        Ok(l)
    }

    /// Overwrites H with its Cholesky factor L (no copy; on failure the band holds a partial
    /// factor and must not be used).
    pub fn cholesky_in_place(&mut self) -> Result<()> {
        let (n, p) = (self.n, self.p);
        let w = p + 1;
        let a = &mut self.a[..];
        for j in 0..n {
            // Row j of L left of the diagonal: L[j][j−d] = a[j·w + d], d = 1 … min(j, p).
            let dj = j.min(p);
            let mut s = a[j * w];
            for d in 1..=dj {
                let v = a[j * w + d];
                s -= v * v;
            }
            if s.is_nan() || s <= 0.0 || !s.is_finite() {
                return Err(Error::Internal(format!(
                    "banded Cholesky: matrix not positive definite at pivot {j} (value {s:e})"
                )));
            }
            let dg = s.sqrt();
            a[j * w] = dg;
            let inv = 1.0 / dg;
            let hi = (j + p).min(n - 1);
            // L[i][j] = (H[i][j] − Σ_{k<j} L[i][k] L[j][k]) / L[j][j], k ≥ i − p: independent
            // for every i, so two rows at a time (two dependency chains; each sum in the same
            // order as one at a time, so the factor is the same to the bit).
            let mut i = j + 1;
            while i < hi {
                let e = i - j;
                let m0 = dj.min(p - e);
                let m1 = dj.min(p - e - 1);
                let (head, tail) = a.split_at_mut(i * w);
                let rj = &head[j * w..j * w + w];
                let (ri, ri1) = tail[..2 * w].split_at_mut(w);
                let (mut s0, mut s1) = (ri[e], ri1[e + 1]);
                for d in 1..=m1 {
                    s0 -= ri[e + d] * rj[d];
                    s1 -= ri1[e + 1 + d] * rj[d];
                }
                for d in m1 + 1..=m0 {
                    s0 -= ri[e + d] * rj[d];
                }
                ri[e] = s0 * inv;
                ri1[e + 1] = s1 * inv;
                i += 2;
            }
            if i == hi {
                let e = i - j;
                let m = dj.min(p - e);
                let (head, tail) = a.split_at_mut(i * w);
                let rj = &head[j * w..j * w + w];
                let ri = &mut tail[..w];
                let mut s = ri[e];
                for d in 1..=m {
                    s -= ri[e + d] * rj[d];
                }
                ri[e] = s * inv;
            }
        }
        Ok(())
    }

    /// Solves L Lᵀ x = b with `self` = L from [`Band::cholesky`].
    pub fn solve(&self, b: &[f64]) -> Vec<f64> {
        let (n, p, w) = (self.n, self.p, self.p + 1);
        let mut y = b.to_vec();
        for i in 0..n {
            let lo = i.saturating_sub(p);
            let mut s = y[i];
            for k in lo..i {
                s -= self.a[i * w + (i - k)] * y[k];
            }
            y[i] = s / self.a[i * w];
        }
        for i in (0..n).rev() {
            let hi = (i + p).min(n - 1);
            let mut s = y[i];
            for k in i + 1..=hi {
                s -= self.a[k * w + (k - i)] * y[k];
            }
            y[i] = s / self.a[i * w];
        }
        y
    }

    /// The band of Σ = H⁻¹ from the factor L = `self` (same storage as H).
    pub fn selected_inverse(&self) -> Band {
        let (n, p, w) = (self.n, self.p, self.p + 1);
        let mut s = Band::zeros(n, p);
        for i in (0..n).rev() {
            let hi = (i + p).min(n - 1);
            let lii = self.a[i * w];
            for j in (i..=hi).rev() {
                let mut acc = if i == j { 1.0 / lii } else { 0.0 };
                for k in i + 1..=hi {
                    // Σ_kj with k, j in (i, i+p]: inside the band.
                    let skj = if k >= j { s.a[k * w + (k - j)] } else { s.a[j * w + (j - k)] };
                    acc -= self.a[k * w + (k - i)] * skj;
                }
                s.a[j * w + (j - i)] = acc / lii;
            }
        }
        s
    }

    /// tr(A B) for symmetric banded A, B of the same shape.
    pub fn trace_product(&self, b: &Band) -> f64 {
        let w = self.p + 1;
        let mut t = 0.0;
        for i in 0..self.n {
            t += self.a[i * w] * b.a[i * w];
            let lo = i.saturating_sub(self.p);
            for j in lo..i {
                t += 2.0 * self.a[i * w + (i - j)] * b.a[i * w + (i - j)];
            }
        }
        t
    }

    /// tr(H⁻¹ B) from the factor L = `self` for a symmetric banded B of the same shape: the
    /// selected inversion of [`Band::selected_inverse`] fused with the trace, keeping only the
    /// last p + 1 columns of Σ = H⁻¹ (O(p²) memory instead of the O(n p) band of Σ).
    pub fn trace_inverse_product(&self, b: &Band) -> f64 {
        let (n, p, w) = (self.n, self.p, self.p + 1);
        // Ring of columns: col[slot(i) + d] = Σ[i + d][i], d = 0 … p, slot(i) = (i mod w)·w.
        let mut col = vec![0.0; w * w];
        let mut lc = vec![0.0; w];
        let mut slot = vec![0usize; w];
        let mut t = 0.0;
        for i in (0..n).rev() {
            let hi = (i + p).min(n - 1);
            let m = hi - i;
            let lii = self.a[i * w];
            let base = i % w;
            for e in 0..=m {
                // L[i+e][i] and the ring slot of column i + e.
                lc[e] = self.a[(i + e) * w + e];
                let r = base + e;
                slot[e] = if r >= w { r - w } else { r } * w;
            }
            for e in (0..=m).rev() {
                // Σ[i + e][i] = (δ_e0 / L_ii − Σ_f L[i+f][i] Σ[i+f][i+e]) / L_ii, f = 1 … m:
                // Σ[i+f][i+e] is in column i+f (f < e) or column i+e (f ≥ e).
                let mut acc = if e == 0 { 1.0 / lii } else { 0.0 };
                for f in 1..e {
                    acc -= lc[f] * col[slot[f] + (e - f)];
                }
                let ce = &col[slot[e]..slot[e] + w];
                for f in e.max(1)..=m {
                    acc -= lc[f] * ce[f - e];
                }
                col[slot[0] + e] = acc / lii;
            }
            let ci = slot[0];
            t += col[ci] * b.a[i * w];
            for e in 1..=m {
                t += 2.0 * col[ci + e] * b.a[(i + e) * w + e];
            }
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn random_spd(n: usize, p: usize, seed: u64) -> Band {
        let mut rng = crate::testing::XorShift64::new(seed);
        let mut rnd = || (rng.next_u64() % 10_000) as f64 / 10_000.0 - 0.5;
        let mut b = Band::zeros(n, p);
        for i in 0..n {
            for d in 1..=p.min(i) {
                let v = rnd();
                let k = b.idx(i, i - d);
                b.a[k] = v;
            }
            let k = b.idx(i, i);
            b.a[k] = 2.0 * p as f64 + 1.0 + rnd();
        }
        b
    }

    fn dense(b: &Band) -> Vec<Vec<f64>> {
        (0..b.n)
            .map(|i| (0..b.n).map(|j| if i.abs_diff(j) <= b.p { b.get(i, j) } else { 0.0 }).collect())
            .collect()
    }

    #[test]
    fn solve_and_selected_inverse_match_dense() {
        let (n, p) = (17, 5);
        let h = random_spd(n, p, 7);
        let l = h.cholesky().unwrap();
        let rhs: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let x = l.solve(&rhs);
        let hx = h.matvec(&x);
        for i in 0..n {
            assert!((hx[i] - rhs[i]).abs() < 1e-12);
        }
        // Dense inverse column by column.
        let s = l.selected_inverse();
        let hd = dense(&h);
        for j in 0..n {
            let e: Vec<f64> = (0..n).map(|i| if i == j { 1.0 } else { 0.0 }).collect();
            let col = l.solve(&e);
            for i in 0..n {
                if i.abs_diff(j) <= p {
                    assert!((s.get(i, j) - col[i]).abs() < 1e-13, "Σ[{i}][{j}]");
                }
                // sanity: H · col = e
                let v: f64 = (0..n).map(|k| hd[i][k] * col[k]).sum();
                assert!((v - e[i]).abs() < 1e-12);
            }
        }
    }

    /// The fused rolling trace equals the trace of the stored selected inverse, and the
    /// in-place factor equals the copying one.
    #[test]
    fn fused_trace_matches_selected_inverse() {
        for (n, p) in [(1, 0), (5, 3), (17, 5), (40, 11), (9, 11)] {
            let h = random_spd(n, p, 11 + n as u64);
            let b = random_spd(n, p, 3 + p as u64);
            let l = h.cholesky().unwrap();
            let mut l2 = h.clone();
            l2.cholesky_in_place().unwrap();
            assert_eq!(l.a, l2.a);
            let want = l.selected_inverse().trace_product(&b);
            let got = l.trace_inverse_product(&b);
            assert!((want - got).abs() <= 1e-13 * want.abs(), "n {n} p {p}: {want} vs {got}");
            let mut out = Band::zeros(0, 0);
            h.axpy_into(0.5, &b, &mut out);
            assert_eq!(out.a, h.axpy(0.5, &b).a);
            let mut inplace = h.clone();
            inplace.axpy_assign(0.5, &b);
            assert_eq!(out.a, inplace.a);
        }
    }

    #[test]
    fn not_positive_definite_is_an_error() {
        let mut h = Band::zeros(3, 1);
        h.a[0] = 1.0;
        h.a[2] = -1.0;
        assert!(h.cholesky().is_err());
    }
}
