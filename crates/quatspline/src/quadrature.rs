//! Gauss–Legendre quadrature: the one home of the crate's nodes and weights.
//!
//! An n-point Gauss–Legendre rule integrates every polynomial of degree ≤ 2n − 1 exactly
//! (tested below for each rule). The nodes are the roots of the Legendre polynomial Pₙ; the
//! weights wᵢ = 2/((1 − xᵢ²) Pₙ'(xᵢ)²) on [−1, 1] (Abramowitz & Stegun 25.4.29).
//! - [`gauss_legendre01`]: n ≤ 8 points on [0, 1], computed by Newton's method on Pₙ (the
//!   fit's penalty integrals and the minimum-energy quadrature);
//! - [`GL8_X`], [`GL8_W`]: the 8-point rule on [−1, 1] as decimal constants (the adaptive
//!   arc-length quadrature of `spline/reparam.rs`);
//! - [`GL2_01`]: the 2-point nodes ½ ∓ √3/6 on [0, 1] (weights ½, ½), the Magnus step of
//!   `integrate.rs`.

/// Gauss–Legendre nodes and weights on [0, 1] (n ≤ 8), by Newton's method on Pₙ from the
/// Chebyshev-like first guess cos(π(i + ¾)/(n + ½)); sorted by node.
pub fn gauss_legendre01(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 0 { 1.0 } else { p1 };
            let pm = if n == 1 { 1.0 } else { p0 };
            dp = n as f64 * (x * pn - pm) / (x * x - 1.0);
            let dx = pn / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        out.push((0.5 * (1.0 - x), 0.5 * w));
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

/// Gauss–Legendre nodes on [−1, 1], 8 points (ascending; weights [`GL8_W`]).
pub const GL8_X: [f64; 8] = [
    -0.960_289_856_497_536_2,
    -0.796_666_477_413_626_7,
    -0.525_532_409_916_329,
    -0.183_434_642_495_649_8,
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_2,
];

/// Gauss–Legendre weights on [−1, 1], 8 points (for the nodes [`GL8_X`]; they sum to 2).
pub const GL8_W: [f64; 8] = [
    0.101_228_536_290_376_26,
    0.222_381_034_453_374_47,
    0.313_706_645_877_887_3,
    0.362_683_783_378_362,
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_47,
    0.101_228_536_290_376_26,
];

/// The 2-point Gauss–Legendre nodes on [0, 1]: ½ − √3/6 and ½ + √3/6 (weights ½ each).
pub const GL2_01: [f64; 2] = [0.5 - 0.288_675_134_594_812_9, 0.5 + 0.288_675_134_594_812_9];

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫₀¹ xᵈ dx = 1/(d + 1) for every degree d ≤ 2n − 1, within rounding.
    fn exact_on_01(rule: &[(f64, f64)], n: usize) {
        for d in 0..2 * n {
            let s: f64 = rule.iter().map(|&(x, w)| w * x.powi(d as i32)).sum();
            let want = 1.0 / (d as f64 + 1.0);
            assert!((s - want).abs() < 4e-16 * (n as f64), "n {n} degree {d}: {s} vs {want}");
        }
        // and not degree 2n: the rule's error on x²ⁿ over [0, 1] is (n!)⁴/((2n + 1)((2n)!)²)
        // (Abramowitz & Stegun 25.4.30 with f⁽²ⁿ⁾ = (2n)!), checked where it is above rounding
        let fact = |k: usize| (1..=k).map(|v| v as f64).product::<f64>();
        let err = fact(n).powi(4) / ((2 * n + 1) as f64 * fact(2 * n).powi(2));
        if err > 1e-12 {
            let s: f64 = rule.iter().map(|&(x, w)| w * x.powi(2 * n as i32)).sum();
            let miss = 1.0 / (2.0 * n as f64 + 1.0) - s;
            assert!((miss - err).abs() < 1e-3 * err, "n {n}: {miss} vs {err}");
        }
    }

    #[test]
    fn gauss_legendre01_integrates_degree_2n_minus_1_exactly() {
        for n in 1..=8 {
            let rule = gauss_legendre01(n);
            assert_eq!(rule.len(), n);
            assert!(rule.windows(2).all(|p| p[0].0 < p[1].0));
            exact_on_01(&rule, n);
        }
    }

    #[test]
    fn gl8_integrates_degree_15_exactly_on_minus_one_one() {
        assert!(GL8_X.windows(2).all(|p| p[0] < p[1]));
        for d in 0..16 {
            let s: f64 = GL8_X.iter().zip(GL8_W).map(|(&x, w)| w * x.powi(d)).sum();
            let want = if d % 2 == 1 { 0.0 } else { 2.0 / (d as f64 + 1.0) };
            assert!((s - want).abs() < 2e-15, "degree {d}: {s} vs {want}");
        }
        // the same rule as gauss_legendre01(8), mapped to [−1, 1]
        for (i, (u, w)) in gauss_legendre01(8).into_iter().enumerate() {
            assert!((2.0 * u - 1.0 - GL8_X[i]).abs() < 1e-15 && (2.0 * w - GL8_W[i]).abs() < 1e-15);
        }
    }

    #[test]
    fn gl2_integrates_cubics_exactly() {
        let rule = [(GL2_01[0], 0.5), (GL2_01[1], 0.5)];
        exact_on_01(&rule, 2);
    }
}
