//! Throwaway golden dump (deleted before the branch's last commit): every batch kernel's
//! output through the engine (values, derivatives, both frames), the pairs kernels and the
//! vector sin/cos/atan2, as f64 bit patterns, for `cmp` before and after a restructuring.
//! Run once with QUATSPLINE_SIMD=scalar and once with the default.

#![allow(clippy::approx_constant)]

use quatspline::simd::{self, pairs, Isa};
use quatspline::spline::*;
use quatspline::Quat;
use std::io::Write;

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn walk(n: usize, seed: u64, step: f64) -> Vec<Quat> {
    let mut r = Rng(seed);
    let mut q = vec![Quat::new(0.5, 0.5, -0.5, 0.5)];
    for _ in 1..n {
        let a = step * (0.2 + r.next());
        let ax = [r.next() - 0.5, r.next() - 0.5, r.next() - 0.5];
        let m = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
        let (s, c) = (0.5 * a).sin_cos();
        q.push(*q.last().unwrap() * Quat::new(c, s * ax[0] / m, s * ax[1] / m, s * ax[2] / m));
    }
    q
}

fn steps(n: usize, seed: u64, half: f64) -> Vec<Quat> {
    let mut r = Rng(seed);
    let mut q = vec![Quat::new(0.5, -0.5, 0.5, 0.5)];
    for _ in 1..n {
        let ax = [r.next() - 0.5, r.next() - 0.5, r.next() - 0.5];
        let m = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
        let (s, c) = half.sin_cos();
        q.push(*q.last().unwrap() * Quat::new(c, s * ax[0] / m, s * ax[1] / m, s * ax[2] / m));
    }
    q
}

fn times(n: usize, seed: u64) -> Vec<f64> {
    let mut r = Rng(seed);
    let mut t = vec![-3.0];
    for _ in 1..n {
        t.push(t.last().unwrap() + 0.05 + 2.0 * r.next());
    }
    t
}

fn splines() -> Vec<(String, Box<dyn Spline>)> {
    let q = walk(30, 1, 1.2);
    let t = times(30, 2);
    let mut v: Vec<(String, Box<dyn Spline>)> = Vec::new();
    let mut add = |n: &str, s: Box<dyn Spline>| v.push((n.to_string(), s));
    add("slerp", Box::new(PiecewiseSlerp::new(&q, Some(&t), true).unwrap()));
    add("beta", Box::new(BetaSpline::new(&q, &[1.3], &[0.4], Some(&t[..28]), true).unwrap()));
    add("c3p", Box::new(C3Spline::new(&q, Some(&t), &[0.3], &[-0.2], C3Variant::Patent, true).unwrap()));
    add("c3k", Box::new(C3Spline::new(&q, Some(&t), &[0.4], &[0.1], C3Variant::Knot, true).unwrap()));
    for n in 2..=12 {
        add("cbez", Box::new(CumulativeBezier::new(&q[..n], (-1.0, 2.5), true).unwrap()));
    }
    for k in 2..=12 {
        add("bspline", Box::new(CumulativeBSpline::new(&q, 0.7, -1.0, k, true).unwrap()));
    }
    let mut qw = walk(30, 7, 3.0);
    for (i, q) in qw.iter_mut().enumerate() {
        if i % 3 == 1 {
            *q = -*q;
        }
    }
    add("bspline wide", Box::new(CumulativeBSpline::new(&qw, 0.7, -1.0, 4, false).unwrap()));
    add("c3k wide", Box::new(C3Spline::new(&qw, Some(&t), &[0.4], &[0.1], C3Variant::Knot, false).unwrap()));
    add(
        "c3p wide",
        Box::new(C3Spline::new(&qw, Some(&t), &[0.3], &[-0.2], C3Variant::Patent, false).unwrap()),
    );
    add("nat", Box::new(NaturalSpline::new(&q, Some(&t), NaturalEnds::Natural, true).unwrap()));
    add(
        "nat clamped",
        Box::new(
            NaturalSpline::new(&q, Some(&t), NaturalEnds::Clamped { start: None, end: None }, true).unwrap(),
        ),
    );
    let qs = walk(30, 4, 0.02);
    add("nat small", Box::new(NaturalSpline::new(&qs, Some(&t), NaturalEnds::Natural, true).unwrap()));
    let qt = walk(30, 4, 1e-7);
    add("nat tiny", Box::new(NaturalSpline::new(&qt, Some(&t), NaturalEnds::Natural, true).unwrap()));
    let ql = walk(30, 5, 2.6);
    add("nat large", Box::new(NaturalSpline::new(&ql, Some(&t), NaturalEnds::Natural, true).unwrap()));
    let mut tc = t.clone();
    tc.push(t[29] + 0.8);
    add(
        "nat closed",
        Box::new(NaturalSpline::with_keyframes(&q, Some(&tc), NaturalEnds::Closed, false, true).unwrap()),
    );
    let mut r = Rng(6);
    let mut vecs = |scale: f64| -> Vec<[f64; 3]> {
        (0..30)
            .map(|_| [scale * (r.next() - 0.5), scale * (r.next() - 0.5), scale * (r.next() - 0.5)])
            .collect()
    };
    let (rates, accels) = (vecs(2.0), vecs(3.0));
    add(
        "herm3",
        Box::new(Hermite::new(&q, Some(&t), &rates, None, Frame::Body, KeyEnds::Open, true).unwrap()),
    );
    add(
        "herm5",
        Box::new(
            Hermite::new(&q, Some(&t), &rates, Some(&accels), Frame::World, KeyEnds::Open, true).unwrap(),
        ),
    );
    // slerp family
    let mut qh = q.clone();
    qh[11] = qh[10];
    qh[12] = qh[10];
    let mut tclosed = t.clone();
    tclosed.push(t[29] + 0.7);
    let tcb_t: Vec<f64> = (0..30).map(|i| 0.3 * ((i as f64) * 0.7).sin()).collect();
    let tcb_c: Vec<f64> = (0..30).map(|i| 0.4 * ((i as f64) * 1.3).cos()).collect();
    let tcb_b: Vec<f64> = (0..30).map(|i| -0.5 + (i as f64) / 30.0).collect();
    let tcb = Tcb { tension: &tcb_t, continuity: &tcb_c, bias: &tcb_b };
    add("squad", Box::new(Squad::new(&q, Some(&t), true).unwrap()));
    add("squad2", Box::new(Squad::new(&q[..2], Some(&t[..2]), true).unwrap()));
    add("squad rest", Box::new(Squad::with_keyframes(&q, Some(&t), KeyEnds::Rest, false, true).unwrap()));
    add(
        "squad closed",
        Box::new(Squad::with_keyframes(&qh, Some(&tclosed), KeyEnds::Closed, true, true).unwrap()),
    );
    add("cr", Box::new(CatmullRom::new(&q, Some(&t), CatmullRomEnds::Reflect, true).unwrap()));
    add("cr dup", Box::new(CatmullRom::new(&q, None, CatmullRomEnds::Duplicate, true).unwrap()));
    add(
        "cr cc",
        Box::new(CatmullRom::with_keyframes(&q, None, Some(0.5), TcbEnds::Closed, false, true).unwrap()),
    );
    add(
        "kb",
        Box::new(KochanekBartels::new(&q, Some(&t), None, tcb, TcbEnds::Reflect, false, true).unwrap()),
    );
    let qm = walk(60, 21, 1.0);
    add(
        "cr mixed",
        Box::new(CatmullRom::new(&qm, Some(&times(60, 6)), CatmullRomEnds::Reflect, true).unwrap()),
    );
    let qs = walk(40, 3, 0.5);
    add(
        "cr small",
        Box::new(CatmullRom::new(&qs, Some(&times(40, 5)), CatmullRomEnds::Reflect, true).unwrap()),
    );
    let qz = walk(40, 3, 1e-9);
    add(
        "cr tiny",
        Box::new(CatmullRom::new(&qz, Some(&times(40, 5)), CatmullRomEnds::Reflect, true).unwrap()),
    );
    for n in [2, 3, 4, 5, 8, 9, 16, 17] {
        for (k, step) in [(0u64, 1.5), (30, 0.4), (60, 0.2), (90, 1e-8)] {
            let c = walk(n, k + n as u64, step);
            add("bez", Box::new(SphericalBezier::new(&c, (-1.0, 2.5), true).unwrap()));
        }
    }
    for half in [0.1499, 0.15, 0.1501, 0.2999, 0.3, 0.3001, 0.4999, 0.5, 0.5001, 1e-12, 1e-8, 1.5707963] {
        let c = steps(8, 43, half);
        add("bez steps", Box::new(SphericalBezier::new(&c, (0.0, 1.0), true).unwrap()));
        let c = steps(4, 44, half);
        add("bez4 steps", Box::new(SphericalBezier::new(&c, (0.0, 1.0), true).unwrap()));
        let c = steps(20, 45, half);
        add("cr steps", Box::new(CatmullRom::new(&c, None, CatmullRomEnds::Reflect, true).unwrap()));
        add("squad steps", Box::new(Squad::new(&c, None, true).unwrap()));
    }
    // far-apart control points (angles near π, no canonicalisation), antipodal neighbours
    let wild = steps(6, 77, std::f64::consts::FRAC_PI_2 - 1e-9);
    add("bez wild", Box::new(SphericalBezier::new(&wild, (0.0, 1.0), false).unwrap()));
    let anti = steps(6, 78, std::f64::consts::PI - 1e-9);
    add("bez anti", Box::new(SphericalBezier::new(&anti, (0.0, 1.0), false).unwrap()));
    add("slerp anti", Box::new(PiecewiseSlerp::new(&anti, None, false).unwrap()));
    v
}

fn probe_times(s: &dyn Spline, seed: u64) -> Vec<f64> {
    let j = s.joints();
    let (a, b) = s.domain();
    let mut t = Vec::new();
    for w in j.windows(2) {
        let (l, r) = (w[0], w[1]);
        let h = r - l;
        let mid = l + 0.5 * h;
        t.extend([l, l.next_up(), mid, mid.next_up(), mid.next_down(), l + 0.3 * h, r.next_down()]);
        t.extend([l + 1e-12 * h, l + 1e-8 * h, r - 1e-12 * h, r - 1e-8 * h, l + 1e-300]);
    }
    t.push(b);
    let mut r = Rng(seed);
    t.extend((0..1500).map(|_| a + (b - a) * r.next()));
    t.retain(|&x| x >= a && x <= b);
    t
}

fn put(out: &mut Vec<u8>, v: &[f64]) {
    for x in v {
        out.extend_from_slice(&x.to_bits().to_le_bytes());
    }
}

fn main() {
    let path = std::env::args().nth(1).expect("output path");
    let mut out = Vec::new();
    let mut count = 0usize;
    for (name, s) in splines() {
        let sorted = {
            let mut t = probe_times(&*s, 3);
            t.sort_by(f64::total_cmp);
            t
        };
        let shuffled = probe_times(&*s, 3);
        for t in [&sorted, &shuffled] {
            // the whole vector, and short runs (vector tails)
            let mut runs: Vec<&[f64]> = vec![&t[..]];
            for n in 1..=9 {
                runs.push(&t[10..10 + n]);
            }
            for tt in runs {
                for order in 0..=3 {
                    let mut o = vec![0.0; tt.len() * 4 * (order + 1)];
                    evaluate_into(&*s, tt, 0, order, Extrapolate::Raise, &mut o)
                        .unwrap_or_else(|e| panic!("{name}: {e}"));
                    put(&mut out, &o);
                    count += o.len();
                }
                for order in 1..=3 {
                    for frame in [Frame::Body, Frame::World] {
                        let mut o = vec![0.0; tt.len() * 3];
                        angular_into(&*s, tt, 0, order, frame, Extrapolate::Raise, &mut o).unwrap();
                        put(&mut out, &o);
                        count += o.len();
                    }
                }
            }
        }
    }
    // pairs kernels
    let isa = simd::isa().unwrap_or(Isa::Scalar);
    let mut r = Rng(99);
    let mut q0 = Vec::new();
    let mut q1 = Vec::new();
    let mut tp = Vec::new();
    let base = |r: &mut Rng| {
        let q = Quat::new(r.next() - 0.5, r.next() - 0.5, r.next() - 0.5, r.next() - 0.5);
        q.normalize()
    };
    let ts = [0.0, 1.0, 0.5, 1e-300, 1e-12, 1.0 - 1e-16, 0.3, -0.5, 1.5, 0.999];
    for i in 0..3000 {
        let a = base(&mut r);
        let ang = match i % 12 {
            0 => 0.0,
            1 => 1e-12,
            2 => 1e-8,
            3 => std::f64::consts::PI - 1e-9,
            4 => std::f64::consts::PI,
            5 => 1e-300,
            _ => 3.0 * r.next(),
        };
        let ax = [r.next() - 0.5, r.next() - 0.5, r.next() - 0.5];
        let m = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
        let (s, c) = (0.5 * ang).sin_cos();
        let mut b = a * Quat::new(c, s * ax[0] / m, s * ax[1] / m, s * ax[2] / m);
        if i % 7 == 3 {
            b = -b;
        }
        let mut aw = a.to_wxyz();
        let mut bw = b.to_wxyz();
        let scale = match i % 11 {
            1 => 3.7,
            2 => 1e-150,
            3 => 1e200,
            4 => 1.0 + 3e-16,
            5 => 1e-160,
            _ => 1.0,
        };
        aw.iter_mut().for_each(|x| *x *= scale);
        if i % 13 == 5 {
            bw.iter_mut().for_each(|x| *x *= 0.25);
        }
        q0.extend(aw);
        q1.extend(bw);
        tp.push(if i % 3 == 0 { ts[(i / 3) % ts.len()] } else { r.next() });
    }
    for long in [false, true] {
        for n in [3000usize, 1, 2, 3, 5, 7, 9, 13] {
            let mut o = vec![0.0; 4 * n];
            match pairs::slerp_pairs(isa, &q0[..4 * n], &q1[..4 * n], &tp[..n], long, &mut o) {
                Ok(()) => put(&mut out, &o),
                Err(e) => out.extend_from_slice(e.to_string().as_bytes()),
            }
        }
    }
    // a zero key: the error
    let mut z = q0[..40].to_vec();
    z[20..24].fill(0.0);
    let mut o = vec![0.0; 40];
    let e = pairs::slerp_pairs(isa, &z, &q1[..40], &tp[..10], false, &mut o).unwrap_err();
    out.extend_from_slice(e.to_string().as_bytes());
    // sclerp: dual quaternions (rotation, translation parts)
    let mut a8 = Vec::new();
    let mut b8 = Vec::new();
    for i in 0..3000 {
        let (ra, rb) = (&q0[4 * i..4 * i + 4], &q1[4 * i..4 * i + 4]);
        a8.extend_from_slice(ra);
        a8.extend([r.next() - 0.5, r.next() - 0.5, r.next() - 0.5, r.next() - 0.5]);
        b8.extend_from_slice(rb);
        if i % 5 == 0 {
            b8.extend([0.0; 4]);
        } else {
            b8.extend([r.next() - 0.5, r.next() - 0.5, r.next() - 0.5, r.next() - 0.5]);
        }
    }
    for n in [3000usize, 1, 2, 3, 5, 7] {
        let mut o = vec![0.0; 8 * n];
        match pairs::sclerp_pairs(isa, &a8[..8 * n], &b8[..8 * n], &tp[..n], &mut o) {
            Ok(()) => put(&mut out, &o),
            Err(e) => out.extend_from_slice(e.to_string().as_bytes()),
        }
    }
    // vector sin/cos and atan2 on both instruction sets
    let mut x: Vec<f64> = (0..20001).map(|i| -20.0 + 40.0 * i as f64 / 20000.0).collect();
    x.extend([0.0, -0.0, 1e-300, 5e-324, 1e-8, 823_549.5, 823_549.7, 1e7, f64::NAN, f64::INFINITY]);
    let y: Vec<f64> = x.iter().map(|v| (v * 1.7).sin() * 3.0).collect();
    for isa in [Isa::Scalar, Isa::Avx2] {
        let (mut s, mut c, mut a) = (vec![0.0; x.len()], vec![0.0; x.len()], vec![0.0; x.len()]);
        simd::sin_cos_slice(isa, &x, &mut s, &mut c);
        simd::atan2_slice(isa, &y, &x, &mut a);
        put(&mut out, &s);
        put(&mut out, &c);
        put(&mut out, &a);
    }
    std::fs::File::create(&path).unwrap().write_all(&out).unwrap();
    eprintln!("{count} spline numbers, {} bytes, isa {:?}", out.len(), isa);
}
