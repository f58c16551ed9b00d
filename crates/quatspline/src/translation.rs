//! Position splines for pose trajectories: piecewise linear (C⁰) or the natural cubic spline
//! (C², zero second derivative at both ends; the classic tridiagonal construction, solved by
//! the Thomas algorithm), per coordinate, with exact velocity and acceleration.

use crate::error::{Error, Result};
use crate::vec3::Vec3;

/// How positions are interpolated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TranslationKind {
    Linear,
    Cubic,
}

/// An interpolating position spline through points at times.
#[derive(Debug, Clone)]
pub struct PositionSpline {
    times: Vec<f64>,
    points: Vec<Vec3>,
    /// Second derivatives at the knots (zero for linear).
    m: Vec<Vec3>,
}

impl PositionSpline {
    /// `times` strictly increasing (checked by the caller's key validation), one point each.
    pub fn new(times: &[f64], points: &[Vec3], kind: TranslationKind) -> Result<Self> {
        let n = times.len();
        if points.len() != n {
            return Err(Error::invalid(
                "positions",
                format!("expected {n} positions (one per key), got {}", points.len()),
            ));
        }
        if let Some(i) = points.iter().position(|p| p.iter().any(|v| !v.is_finite())) {
            return Err(Error::NonFinite { arg: "positions", index: i });
        }
        let mut m = vec![[0.0; 3]; n];
        if kind == TranslationKind::Cubic && n > 2 {
            // h_{i−1} M_{i−1} + 2(h_{i−1} + h_i) M_i + h_i M_{i+1} = 6 (Δ_i − Δ_{i−1}), M₀ = M_{n−1} = 0
            let h: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
            for c in 0..3 {
                let k = n - 2;
                let mut diag = vec![0.0; k];
                let mut rhs = vec![0.0; k];
                for j in 0..k {
                    let i = j + 1;
                    diag[j] = 2.0 * (h[i - 1] + h[i]);
                    rhs[j] = 6.0
                        * ((points[i + 1][c] - points[i][c]) / h[i]
                            - (points[i][c] - points[i - 1][c]) / h[i - 1]);
                }
                for j in 1..k {
                    let w = h[j] / diag[j - 1];
                    diag[j] -= w * h[j];
                    rhs[j] -= w * rhs[j - 1];
                }
                let mut x = vec![0.0; k];
                x[k - 1] = rhs[k - 1] / diag[k - 1];
                for j in (0..k - 1).rev() {
                    x[j] = (rhs[j] - h[j + 1] * x[j + 1]) / diag[j];
                }
                for j in 0..k {
                    m[j + 1][c] = x[j];
                }
            }
        }
        Ok(PositionSpline { times: times.to_vec(), points: points.to_vec(), m })
    }

    /// Position, velocity and acceleration on segment `i` at time t.
    pub fn eval(&self, i: usize, t: f64) -> [Vec3; 3] {
        let h = self.times[i + 1] - self.times[i];
        let a = (self.times[i + 1] - t) / h;
        let b = (t - self.times[i]) / h;
        let (p0, p1, m0, m1) = (self.points[i], self.points[i + 1], self.m[i], self.m[i + 1]);
        let mut out = [[0.0; 3]; 3];
        for c in 0..3 {
            out[0][c] =
                a * p0[c] + b * p1[c] + ((a * a * a - a) * m0[c] + (b * b * b - b) * m1[c]) * h * h / 6.0;
            out[1][c] =
                (p1[c] - p0[c]) / h + ((1.0 - 3.0 * a * a) * m0[c] + (3.0 * b * b - 1.0) * m1[c]) * h / 6.0;
            out[2][c] = a * m0[c] + b * m1[c];
        }
        out
    }
}
