//! Assembly of the Gauss–Newton normal equations: the data half (JᵀWJ, JᵀWr, rᵀWr) and the
//! penalty half (P, Jₚᵀ C p, pᵀCp, by Gauss–Legendre quadrature per knot interval), straight
//! into band storage, in parallel over fixed chunks with an ordered reduction.

use super::banded::Band;
use super::model::{self, Cols, Factors, Model, MAXK};
use super::so3;
use super::types::{Data, Penalty};
use crate::jet::Jet;
use crate::vec3::{self, Vec3};
use rayon::prelude::*;

/// Quadrature points per knot interval for the penalty integral: k − 1 − m for a smoothing fit
/// — exact in the Euclidean (small-rotation) limit, where |ω^(m)|² is a polynomial of degree
/// 2(k − 2 − m), and within 2·10⁻⁶ (relative) of a converged rule at 0.03 rad per knot interval,
/// 2·10⁻³ at 1–2 rad (test `penalty_quadrature_accuracy`) — and k when interpolating (λ = 0,
/// minimum-energy curves, whose energy is the result).
pub(super) fn penalty_nodes(k: usize, m: usize, interpolate: bool) -> usize {
    if interpolate {
        k
    } else {
        (k - 1 - m).max(1)
    }
}

/// Segments per work unit of the parallel assembly, and samples per partial sum. Fixed (never
/// derived from the thread count): every sum is taken in the same order on any number of
/// threads, so the fit is bit-identical whatever the pool size.
pub(super) const CHUNK: usize = 512;

#[cfg(test)]
pub(super) const SUM_CHUNK: usize = 4096;

/// The half-bandwidth that asks [`assemble`] for the sums alone (see [`sums_only`]).
const SUMS_ONLY: usize = usize::MAX;

/// A band argument for [`data_half`] and [`pen_half`] that asks for the sums alone (the cost
/// of a trial curve): no matrix, no gradient, no storage.
pub(super) fn sums_only() -> Band {
    Band { n: 0, p: SUMS_ONLY, a: Vec::new() }
}

/// One half of a linearisation: the data term (G = JᵀWJ, Jᵀ W r, rᵀWr, observations) or the
/// penalty term (P, Jₚᵀ C p, pᵀCp).
pub(super) struct Half {
    pub(super) band: Band,
    pub(super) grad: Vec<f64>,
    pub(super) sum: f64,
    pub(super) count: f64,
}

/// The Gauss–Newton pieces at one linearisation.
pub(super) struct Lin {
    pub(super) g: Band,
    pub(super) p: Band,
    pub(super) gd: Vec<f64>,
    pub(super) gp: Vec<f64>,
    pub(super) rwr: f64,
    pub(super) pcp: f64,
    pub(super) nobs: f64,
}

impl Lin {
    /// The (data, penalty) halves back.
    pub(super) fn into_halves(self) -> (Half, Half) {
        (
            Half { band: self.g, grad: self.gd, sum: self.rwr, count: self.nobs },
            Half { band: self.p, grad: self.gp, sum: self.pcp, count: 0.0 },
        )
    }
    pub(super) fn new(data: Half, pen: Half) -> Lin {
        Lin {
            g: data.band,
            p: pen.band,
            gd: data.grad,
            gp: pen.grad,
            rwr: data.sum,
            pcp: pen.sum,
            nobs: data.count,
        }
    }
}

/// Sum of `f` over `0..n` in fixed chunks of [`SUM_CHUNK`], partial sums added in order.
#[cfg(test)]
pub(super) fn ordered_sum(n: usize, f: impl Fn(usize) -> f64 + Sync) -> f64 {
    let parts: Vec<f64> = (0..n.div_ceil(SUM_CHUNK))
        .into_par_iter()
        .map(|c| (c * SUM_CHUNK..((c + 1) * SUM_CHUNK).min(n)).map(&f).sum())
        .collect();
    parts.iter().sum()
}

/// The rows of one chunk of a band under assembly (lower band storage, `w` entries a row):
/// its own rows, inside the band, then the rows its last segments reach beyond (`spill`).
pub(super) struct ChunkBand<'a> {
    pub(super) own: &'a mut [f64],
    pub(super) spill: &'a mut [f64],
    pub(super) w: usize,
}

impl ChunkBand<'_> {
    /// As [`Band::add_block`], rows counted from the chunk's first row.
    #[inline]
    pub(super) fn add_block(&mut self, off: usize, m: usize, blk: &[f64], scale: f64) {
        let w = self.w;
        if w == 0 {
            return;
        }
        let own_rows = self.own.len() / w;
        for r in 0..m {
            let row = off + r;
            let dst = if row < own_rows {
                &mut self.own[row * w..row * w + w]
            } else {
                &mut self.spill[(row - own_rows) * w..(row - own_rows) * w + w]
            };
            for (c, x) in blk[r * m..r * m + r + 1].iter().enumerate() {
                dst[r - c] += scale * x;
            }
        }
    }
}

/// Assembles a block-banded Gauss–Newton matrix (symmetric 3k × 3k blocks at rows 3i for
/// segment i, half-bandwidth 3k − 1) and its gradient directly into band storage, in parallel
/// over fixed chunks of [`CHUNK`] segments. `f(s0, s1, band, grad)` fills a chunk's band rows
/// and a chunk-local gradient whose row 0 is global row 3·s0 and returns partial (sum, count).
/// Chunk c owns the rows of control points [c·CHUNK, (c+1)·CHUNK) and accumulates into them
/// in place; the rows its last segments reach beyond (k − 1 control points) are added
/// afterwards in chunk order. `band`'s storage is reused (no allocation when it is large
/// enough; each chunk zeroes its own rows).
pub(super) fn assemble<F>(nctrl: usize, segs: usize, k: usize, mut band: Band, f: F) -> Half
where
    F: Fn(usize, usize, &mut ChunkBand<'_>, &mut [f64]) -> (f64, f64) + Sync,
{
    if band.p == SUMS_ONLY {
        // The sums alone (no matrix, no gradient): the same chunks and the same order of
        // addition as below, so the sums are the same to the bit.
        let parts: Vec<(f64, f64)> = (0..segs.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let (s0, s1) = (c * CHUNK, ((c + 1) * CHUNK).min(segs));
                f(s0, s1, &mut ChunkBand { own: &mut [], spill: &mut [], w: 0 }, &mut [])
            })
            .collect();
        let (mut sum, mut count) = (0.0, 0.0);
        for (s, c) in parts {
            sum += s;
            count += c;
        }
        return Half { band: Band::zeros(0, 0), grad: Vec::new(), sum, count };
    }
    let nb = 3 * k;
    let w = nb;
    let n = 3 * nctrl;
    band.n = n;
    band.p = nb - 1;
    band.a.resize(n * w, 0.0);
    let mut grad = vec![0.0; n];
    let rows = 3 * CHUNK;
    type Spill = (usize, Vec<f64>, Vec<f64>, f64, f64);
    let spills: Vec<Spill> = band
        .a
        .par_chunks_mut(rows * w)
        .zip(grad.par_chunks_mut(rows))
        .enumerate()
        .map(|(c, (bpiece, gpiece))| {
            bpiece.fill(0.0);
            let s0 = c * CHUNK;
            let s1 = ((c + 1) * CHUNK).min(segs);
            if s0 >= s1 {
                return (0, vec![], vec![], 0.0, 0.0);
            }
            let lrows = 3 * (s1 - s0 + k - 1);
            let own = gpiece.len().min(lrows);
            let mut spill = vec![0.0; (lrows - own) * w];
            let mut lg = vec![0.0; lrows];
            let mut view = ChunkBand { own: &mut bpiece[..own * w], spill: &mut spill, w };
            let (sum, count) = f(s0, s1, &mut view, &mut lg);
            gpiece[..own].copy_from_slice(&lg[..own]);
            (3 * s0 + own, spill, lg[own..].to_vec(), sum, count)
        })
        .collect();
    let (mut sum, mut count) = (0.0, 0.0);
    for (row, sb, sg, s, c) in spills {
        for (x, y) in band.a[row * w..row * w + sb.len()].iter_mut().zip(&sb) {
            *x += y;
        }
        for (x, y) in grad[row..row + sg.len()].iter_mut().zip(&sg) {
            *x += y;
        }
        sum += s;
        count += c;
    }
    Half { band, grad, sum, count }
}

/// Data residual vectors r_s − e_s and angles |r_s| at the current model.
pub(super) fn residuals(model: &Model, data: &Data, offs: &[Vec3]) -> (Vec<Vec3>, Vec<f64>) {
    (0..data.t.len())
        .into_par_iter()
        .map(|s| {
            let (i, u) = model.locate(data.t[s]);
            let q = model.value::<1>(i, Jet::constant(u)).value();
            let r = so3::log(q.conj() * data.y[s]);
            (vec3::sub(r, offs[s]), vec3::norm(r))
        })
        .unzip()
}

#[cfg(test)]
pub(super) fn penalty_value<const N: usize>(model: &Model, m: usize, nodes: &[(f64, f64)]) -> f64 {
    let segs = model.segments();
    ordered_sum(segs, |i| {
        let mut acc = 0.0;
        for &(u, w) in nodes {
            let q = model.value::<N>(i, Jet::variable(u, 1.0 / model.width(i)));
            let om = Model::omega(&q);
            let p: Vec3 = std::array::from_fn(|r| om[r].derivative(m));
            acc += w * model.width(i) * vec3::dot(p, p);
        }
        acc
    })
}

/// The m-th time derivative of δω = ξ̇ + ω × ξ for one column ξ (Leibniz on the jets'
/// coefficients; only the coefficient needed is formed).
#[inline(always)]
pub(super) fn delta_omega_deriv<const N: usize>(om: &model::V<N>, xi: &model::V<N>, m: usize) -> Vec3 {
    const FACT: [f64; 6] = [1.0, 1.0, 2.0, 6.0, 24.0, 120.0];
    let mut c = [0.0; 3];
    for r in 0..3 {
        // coefficient m of shift(ξ): (m + 1) ξ_{m+1} (0 beyond the jet, as in `shift`)
        c[r] = if m + 1 < N { (m + 1) as f64 * xi[r].0[m + 1] } else { 0.0 };
    }
    for a in 0..=m {
        let (o, x) = (|r: usize| om[r].0[a], |r: usize| xi[r].0[m - a]);
        c[0] += o(1) * x(2) - o(2) * x(1);
        c[1] += o(2) * x(0) - o(0) * x(2);
        c[2] += o(0) * x(1) - o(1) * x(0);
    }
    [c[0] * FACT[m], c[1] * FACT[m], c[2] * FACT[m]]
}

/// The penalty half: P = Σ Jₚᵀ C Jₚ, Jₚᵀ C p and pᵀ C p by Gauss quadrature per segment,
/// segment i's share scaled by its weight `wts[i]` when given (locally adaptive smoothing:
/// λ Σᵢ wᵢ ∫_{segment i} |p|² dt, `adaptive.rs`).
/// δω^(m) is linear in ξ with constant coefficients in the Jacobian's right factors, so it is
/// applied to the k jet factors of [`Model::value_and_factors`] (3k constant columns) and the
/// factors' constant 3×3 right multipliers J_r⁻¹, J_l⁻¹ come after, on plain numbers.
pub(super) fn penalty_half<const N: usize>(
    model: &Model,
    m: usize,
    nodes: &[(f64, f64)],
    band: Band,
    wts: Option<&[f64]>,
) -> Half {
    let k = model.order;
    let nb = 3 * k;
    assemble(model.ctrl.len(), model.segments(), k, band, |s0, s1, pb, gp| {
        let mut blk = vec![0.0; nb * nb];
        let mut jac = [[0.0f64; 3]; 3 * MAXK];
        let mut mats: Factors<N> = [[[Jet::constant(0.0); 3]; 3]; MAXK];
        // e[j][c] = δω^(m) of column c of factor j.
        let mut e = [[[0.0f64; 3]; 3]; MAXK];
        let mut pcp = 0.0;
        for i in s0..s1 {
            blk.iter_mut().for_each(|v| *v = 0.0);
            let off = 3 * (i - s0);
            for &(u, w) in nodes {
                let h = model.width(i);
                let c = w * h * wts.map_or(1.0, |v| v[i]);
                let q = model.value_and_factors::<N>(i, Jet::variable(u, 1.0 / h), &mut mats);
                let om = Model::omega(&q);
                let p: Vec3 = std::array::from_fn(|r| om[r].derivative(m));
                pcp += c * vec3::dot(p, p);
                if pb.w == 0 {
                    continue;
                }
                for j in 0..k {
                    for cc in 0..3 {
                        let col = [mats[j][0][cc], mats[j][1][cc], mats[j][2][cc]];
                        e[j][cc] = delta_omega_deriv(&om, &col, m);
                    }
                }
                for mm in 0..k {
                    for cc in 0..3 {
                        let mut v = if mm == 0 { e[0][cc] } else { [0.0; 3] };
                        if mm >= 1 {
                            let jr = model.chain_jacobians(i + mm).0;
                            for l in 0..3 {
                                v = vec3::add(v, vec3::scale(e[mm][l], jr[l][cc]));
                            }
                        }
                        if mm + 1 < k {
                            let jl = model.chain_jacobians(i + mm + 1).1;
                            for l in 0..3 {
                                v = vec3::sub(v, vec3::scale(e[mm + 1][l], jl[l][cc]));
                            }
                        }
                        jac[3 * mm + cc] = v;
                    }
                }
                for a in 0..nb {
                    gp[off + a] += c * vec3::dot(jac[a], p);
                    let row = &mut blk[a * nb..a * nb + a + 1];
                    for (b, x) in row.iter_mut().enumerate() {
                        *x += c * vec3::dot(jac[a], jac[b]);
                    }
                }
            }
            pb.add_block(off, nb, &blk, 1.0);
        }
        (pcp, 0.0)
    })
}

/// The data half: G = Σ wₛ Jₛᵀ Jₛ, Σ wₛ Jₛᵀ rₛ, Σ wₛ |rₛ|² and the number of observations.
pub(super) fn data_half(model: &Model, data: &Data, w: &[f64], offs: &[Vec3], band: Band) -> Half {
    let k = model.order;
    let nb = 3 * k;
    assemble(model.ctrl.len(), model.segments(), k, band, |s0, s1, g, gd| {
        let a = data.t.partition_point(|&t| model.locate(t).0 < s0);
        let b = data.t.partition_point(|&t| model.locate(t).0 < s1);
        let mut cols: Cols<1> = [[[Jet::constant(0.0); 3]; 3]; MAXK];
        let mut blk = vec![0.0; nb * nb];
        let mut cur = usize::MAX;
        let mut rwr = 0.0;
        let mut nobs = 0.0;
        let mut jac = [[0.0f64; 3]; 3 * MAXK];
        for s in a..b {
            if w[s] == 0.0 {
                continue;
            }
            nobs += 3.0;
            let (i, u) = model.locate(data.t[s]);
            if i != cur {
                if cur != usize::MAX {
                    g.add_block(3 * (cur - s0), nb, &blk, 1.0);
                }
                blk.iter_mut().for_each(|v| *v = 0.0);
                cur = i;
            }
            let off = 3 * (i - s0);
            let q = model.value_and_columns::<1>(i, Jet::constant(u), &mut cols).value();
            let r0 = so3::log(q.conj() * data.y[s]);
            let r = vec3::sub(r0, offs[s]);
            let jl = if offs[s] == [0.0; 3] { so3::dist_hess_sqrt(r0) } else { so3::jl_inv(r0) };
            for mm in 0..k {
                for c in 0..3 {
                    let x: Vec3 = std::array::from_fn(|t| cols[mm][c][t].value());
                    let jx = so3::mat_vec(&jl, x);
                    jac[3 * mm + c] = [-jx[0], -jx[1], -jx[2]];
                }
            }
            let ws = w[s];
            rwr += ws * vec3::dot(r, r);
            if g.w == 0 {
                continue;
            }
            for a in 0..nb {
                gd[off + a] += ws * vec3::dot(jac[a], r);
                let row = &mut blk[a * nb..a * nb + a + 1];
                for (b, x) in row.iter_mut().enumerate() {
                    *x += ws * vec3::dot(jac[a], jac[b]);
                }
            }
        }
        if cur != usize::MAX {
            g.add_block(3 * (cur - s0), nb, &blk, 1.0);
        }
        (rwr, nobs)
    })
}

pub(super) fn pen_half(
    model: &Model,
    pen: Penalty,
    nodes: &[(f64, f64)],
    band: Band,
    wts: Option<&[f64]>,
) -> Half {
    match pen {
        Penalty::Acceleration => penalty_half::<3>(model, 1, nodes, band, wts),
        Penalty::Jerk => penalty_half::<4>(model, 2, nodes, band, wts),
    }
}

#[cfg(test)]
pub(super) fn linearise(
    model: &Model,
    data: &Data,
    w: &[f64],
    offs: &[Vec3],
    pen: Penalty,
    nodes: &[(f64, f64)],
) -> Lin {
    let d = data_half(model, data, w, offs, Band::zeros(0, 0));
    Lin::new(d, pen_half(model, pen, nodes, Band::zeros(0, 0), None))
}

#[cfg(test)]
pub(super) fn cost(
    model: &Model,
    data: &Data,
    w: &[f64],
    offs: &[Vec3],
    pen: Penalty,
    nodes: &[(f64, f64)],
    lam: f64,
) -> f64 {
    let (rv, _) = residuals(model, data, offs);
    let d = ordered_sum(rv.len(), |s| w[s] * vec3::dot(rv[s], rv[s]));
    let p = if lam > 0.0 {
        match pen {
            Penalty::Acceleration => penalty_value::<3>(model, 1, nodes),
            Penalty::Jerk => penalty_value::<4>(model, 2, nodes),
        }
    } else {
        0.0
    };
    d + lam * p
}

#[cfg(test)]
mod floor {
    use super::*;
    use crate::fit::start::initial_controls;
    use std::time::Instant;

    /// The floor of a fit at scale: one pass of each assembly, one banded factorisation, one
    /// solve and one trace of H⁻¹G at 10⁶ samples (one knot interval per sample, as the
    /// benchmark's `--scale`); a Gauss–Newton iteration costs at least an assembly of both
    /// halves, a factorisation and a solve, a GCV candidate a factorisation, a solve and a
    /// trace. A measurement, not a test: `cargo test --release -- --ignored floor --nocapture`.
    #[test]
    #[ignore]
    fn floor_at_a_million_samples() {
        let n = 1_000_000;
        let t: Vec<f64> = (0..n).map(|i| i as f64 / 300.0).collect();
        let y: Vec<crate::quat::Quat> = t
            .iter()
            .map(|&s| so3::exp([0.8 * (0.5 * s).sin(), 0.6 * (0.37 * s).cos(), 0.2 * (0.05 * s).sin()]))
            .collect();
        let d = Data { t, y, w: vec![1.0; n] };
        let (k, segs) = (4, n - 1);
        let dt = (d.t[n - 1] - d.t[0]) / segs as f64;
        let model = Model::new(initial_controls(&d, d.t[0], dt, segs, k), dt, d.t[0], k);
        let nodes = crate::quadrature::gauss_legendre01(penalty_nodes(k, 1, false));
        let offs = vec![[0.0; 3]; n];
        let time = |what: &str, f: &mut dyn FnMut()| {
            let (w0, c0) = (Instant::now(), cpu_seconds());
            f();
            eprintln!("{what}: wall {:.3} s, CPU {:.3} s", w0.elapsed().as_secs_f64(), cpu_seconds() - c0);
        };
        let mut dh = None;
        let mut ph = None;
        time("data half", &mut || dh = Some(data_half(&model, &d, &d.w, &offs, Band::zeros(0, 0))));
        time("penalty half", &mut || {
            ph = Some(pen_half(&model, Penalty::Acceleration, &nodes, Band::zeros(0, 0), None))
        });
        let lin = Lin::new(dh.unwrap(), ph.unwrap());
        let mut h = Band::zeros(0, 0);
        time("H = G + λP", &mut || lin.g.axpy_into(1e-6, &lin.p, &mut h));
        time("factorisation", &mut || h.cholesky_in_place().unwrap());
        let mut x = vec![];
        time("solve", &mut || x = h.solve(&lin.gd));
        let mut tr = 0.0;
        time("trace of H⁻¹G", &mut || tr = h.trace_inverse_product(&lin.g));
        time("retraction", &mut || drop(model.retracted(&x, None)));
        eprintln!("(unknowns {}, tr {tr:.3})", lin.gd.len());
    }

    /// User + system CPU seconds of this process (all threads).
    fn cpu_seconds() -> f64 {
        let s = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
        let f: Vec<&str> = s.rsplit(')').next().unwrap_or("").split_whitespace().collect();
        let tick = |i: usize| f.get(i).and_then(|v| v.parse::<f64>().ok()).unwrap_or(0.0);
        (tick(11) + tick(12)) / 100.0
    }
}
