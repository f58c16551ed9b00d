//! Choosing λ: generalised cross-validation on the Gauss–Newton linearisation, a coarse log
//! grid and Brent's method (see the module doc of [`super`]).

use super::assembly::Lin;
use super::banded::Band;
use crate::error::Result;

/// GCV of the linearised problem at λ: (score, tr A). `h` is workspace for H = G + λP and
/// its factor (reused between calls).
pub(super) fn gcv_at(lin: &Lin, lam: f64, h: &mut Band) -> Result<(f64, f64)> {
    lin.g.axpy_into(lam, &lin.p, h);
    h.cholesky_in_place()?;
    gcv_of_factor(lin, lam, h)
}

/// [`gcv_at`] for the last use of a linearisation: H = G + λP is formed in the storage of P
/// (the same sums, so the same score), which saves a band.
pub(super) fn gcv_final(lin: Lin, lam: f64) -> Result<(f64, f64)> {
    let Lin { g, p: mut h, gd, gp, rwr, pcp, nobs } = lin;
    for (x, y) in h.a.iter_mut().zip(&g.a) {
        *x = y + lam * *x;
    }
    h.cholesky_in_place()?;
    gcv_of_factor(&Lin { g, p: Band::zeros(0, 0), gd, gp, rwr, pcp, nobs }, lam, &h)
}

/// GCV at λ from the factor `hf` of H = G + λP (only G, the gradients and sums of `lin`).
fn gcv_of_factor(lin: &Lin, lam: f64, hf: &Band) -> Result<(f64, f64)> {
    // The step's RSS and the trace are independent given the factor: one thread each.
    let (rss, tr) = rayon::join(
        || {
            let rhs: Vec<f64> = lin.gd.iter().zip(&lin.gp).map(|(a, b)| -(a + lam * b)).collect();
            let d = hf.solve(&rhs);
            let gdd = lin.g.matvec(&d);
            (lin.rwr + 2.0 * dotv(&d, &lin.gd) + dotv(&d, &gdd)).max(0.0)
        },
        || hf.trace_inverse_product(&lin.g),
    );
    let den = lin.nobs - tr;
    let score = if den > 1e-9 * lin.nobs { lin.nobs * rss / (den * den) } else { f64::INFINITY };
    Ok((score, tr))
}

/// The largest λ for which the normal matrix G + λP is still resolved in double precision:
/// `LAMBDA_RESOLVED` · max diag G / max diag P. Beyond it the penalty's null space, which
/// only G pins down, drowns in P's rounding and the banded Cholesky meets negative pivots.
/// A fixed λ above the cap is fitted at the cap, and the result says so
/// (`lambda_requested`): on short data the fit has long reached the minimum-penalty curve
/// there; on long data the penalty's slowest modes still bend it (P's condition grows like
/// n^(2m)), and no larger λ would be resolved.
pub(crate) fn lambda_cap(g: &Band, p: &Band) -> f64 {
    let dmax = |b: &Band| b.diag().into_iter().fold(0.0, f64::max);
    LAMBDA_RESOLVED * dmax(g) / dmax(p).max(f64::MIN_POSITIVE)
}

/// See [`lambda_cap`]. Measured on 112 orientation and position fits (12–2000 samples, uneven
/// times, both penalties, knots per sample and per 3 samples) at λ = c · max diag G / max diag
/// P: the Cholesky failed at the old cap c = 3e16 in 86 of them and at c ≥ 9e15 in some; none
/// at c ≤ 3e15. 1e15 keeps a factor 9 below the first failure.
pub(super) const LAMBDA_RESOLVED: f64 = 1e15;

pub(super) fn dotv(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Brent's minimiser (R. P. Brent, Algorithms for Minimization without Derivatives, 1973,
/// ch. 5, `fmin`: golden section with parabolic interpolation) of f on [a, b], starting from
/// x₀ with f(x₀) = f₀ known, until x is within `tol` of the minimum (or `max_eval` calls).
/// Non-finite values (a failed factorisation) fall back to golden-section steps.
pub(super) fn brent(
    f: &mut dyn FnMut(f64) -> f64,
    mut a: f64,
    mut b: f64,
    x0: f64,
    f0: f64,
    tol: f64,
    max_eval: usize,
) -> (f64, f64) {
    const CGOLD: f64 = 0.381_966_011_250_105_1;
    let (mut x, mut w, mut v) = (x0, x0, x0);
    let (mut fx, mut fw, mut fv) = (f0, f0, f0);
    let (mut d, mut e) = (0.0f64, 0.0f64);
    for _ in 0..max_eval {
        let xm = 0.5 * (a + b);
        let tol2 = 2.0 * tol;
        if (x - xm).abs() <= tol2 - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol && fx.is_finite() && fw.is_finite() && fv.is_finite() {
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            } else {
                q = -q;
            }
            let etemp = e;
            e = d;
            if p.abs() < (0.5 * q * etemp).abs() && p > q * (a - x) && p < q * (b - x) {
                d = p / q;
                let u = x + d;
                if u - a < tol2 || b - u < tol2 {
                    d = tol.copysign(xm - x);
                }
                golden = false;
            }
        }
        if golden {
            e = if x >= xm { a - x } else { b - x };
            d = CGOLD * e;
        }
        let u = if d.abs() >= tol { x + d } else { x + tol.copysign(d) };
        let fu = f(u);
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    (x, fx)
}

/// Tolerance of the λ search in ln λ (λ to 0.2 %; λ counts as settled between linearisations
/// when it moves less than 1 %).
pub(super) const LN_LAMBDA_TOL: f64 = 2e-3;

/// Minimises GCV over ln λ in [lo, hi]; returns (λ, GCV).
///
/// Without a previous λ (the first search): the best of a coarse grid of `grid` points,
/// refined by Brent's method between its grid neighbours. With one: a bracket of ±0.1 in ln λ around it, widened by doubling towards lower
/// values (down to 10⁻⁶ lo), then Brent's method to [`LN_LAMBDA_TOL`]. The caller re-selects at every
/// linearisation until λ moves less than 1 %, so the final λ is always a Brent minimum.
pub(super) fn select_lambda(
    lin: &Lin,
    lo: f64,
    hi: f64,
    grid: usize,
    prev: Option<f64>,
    h: &mut Band,
) -> Result<(f64, f64)> {
    let (xlo, xhi) = (lo.ln(), hi.ln());
    let Some(prev) = prev else {
        let xs: Vec<f64> = (0..grid).map(|i| xlo + (xhi - xlo) * i as f64 / (grid - 1) as f64).collect();
        // One candidate at a time in one H (each uses both threads: the RSS and the trace
        // run side by side): one H per thread would hold a fourth band.
        let vals: Vec<f64> =
            xs.iter().map(|&x| gcv_at(lin, x.exp(), h).map(|r| r.0).unwrap_or(f64::INFINITY)).collect();
        // Ties (a flat GCV: residuals that vanish for every λ) go to the largest λ, the
        // smoothest curve that fits as well.
        let ib = (0..grid).rev().min_by(|&i, &j| vals[i].total_cmp(&vals[j])).unwrap_or(0);
        // Brent between the grid neighbours of the best point.
        let (a, b) = (xs[ib.saturating_sub(1)], xs[(ib + 1).min(grid - 1)]);
        let mut f = |x: f64| gcv_at(lin, x.exp(), h).map(|r| r.0).unwrap_or(f64::INFINITY);
        let (x, fx) = brent(&mut f, a, b, xs[ib], vals[ib], LN_LAMBDA_TOL, 40);
        return Ok((x.exp(), fx));
    };
    // Later linearisations may go below the grid (noise-free data: GCV falls towards λ → 0
    // until tr A reaches the observations), by at most 10⁻⁶.
    let xlo = xlo - 6.0 * std::f64::consts::LN_10;
    let mut f = |x: f64| gcv_at(lin, x.exp(), h).map(|r| r.0).unwrap_or(f64::INFINITY);
    let xm = prev.ln().clamp(xlo, xhi);
    let mut step = 0.1;
    let (mut a, mut m, mut b) = ((xm - step).max(xlo), xm, (xm + step).min(xhi));
    let (mut fa, mut fm, mut fb) = (f(a), f(m), f(b));
    for _ in 0..60 {
        if fm <= fa && fm <= fb {
            break;
        }
        step *= 2.0;
        if fa < fb {
            (b, fb, m, fm) = (m, fm, a, fa);
            if m <= xlo {
                break;
            }
            a = (m - step).max(xlo);
            fa = f(a);
        } else {
            (a, fa, m, fm) = (m, fm, b, fb);
            if m >= xhi {
                break;
            }
            b = (m + step).min(xhi);
            fb = f(b);
        }
    }
    let _ = (fa, fb);
    let (x, fx) = brent(&mut f, a, b, m, fm, LN_LAMBDA_TOL, 40);
    Ok((x.exp(), fx))
}
