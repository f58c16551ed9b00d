//! Throwaway golden dump for the rust-math restructuring (deleted before the last commit).
//! Prints the f64 bits (Debug of every result) of every function the restructuring touches.

use quatspline::fit::{self, FitOptions, Knots, Penalty, Robust, Smoothing};
use quatspline::integrate::{integrate, RateModel};
use quatspline::se3::{PoseBSpline, PoseFormulation, ScrewSpline};
use quatspline::spline::{
    evaluate_into, Extrapolate, Frame, Hermite, KeyEnds, NaturalEnds, NaturalSpline, Reparameterized, Spline,
};
use quatspline::{convert, special, DualQuat, Quat};
use std::sync::Arc;

fn hard() -> Vec<f64> {
    let mut v = vec![0.0, 1e-300, 1e-200, 1e-150, 1e-20, 1e-12, 1e-10, 1e-8, 1e-6, 1e-5];
    for s in [1e-4f64, 1e-3, 1e-2, 0.02, 0.05, 0.1, 0.3, 0.5, 1.0] {
        for k in -3i64..=3 {
            v.push(f64::from_bits(s.to_bits().wrapping_add(k as u64)));
        }
        v.push(s * (1.0 - 1e-9));
        v.push(s * (1.0 + 1e-9));
    }
    let pi = std::f64::consts::PI;
    v.extend([0.7, 1.3, 2.0, 2.5, 3.0, pi - 1e-6, pi - 1e-9, pi - 1e-12, pi, 4.0, 6.0, 7.0]);
    let mut x = 1e-7;
    while x < 7.0 {
        v.push(x);
        x *= 1.037;
    }
    v
}

fn bits(out: &mut String, x: f64) {
    out.push_str(&format!("{:016x} ", x.to_bits()));
}

fn rng_quats(n: usize, seed: u64, scale: f64) -> Vec<Quat> {
    let mut r = quatspline::testing::XorShift64::new(seed);
    let mut uni = || ((r.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
    let mut q = Quat::IDENTITY;
    (0..n)
        .map(|_| {
            let v = [scale * (uni() - 0.5), scale * (uni() - 0.5), scale * (uni() - 0.5)];
            q = q * convert::from_rotvec(v);
            q
        })
        .collect()
}

fn dump_spline(out: &mut String, name: &str, s: &dyn Spline) {
    out.push_str(&format!("\n{name}\n"));
    let (a, b) = s.domain();
    let m = 97;
    let t: Vec<f64> =
        (0..=m).map(|i| a + (b - a) * i as f64 / m as f64).chain(s.joints().iter().copied()).collect();
    for &ti in &t {
        let seg = s.locate(ti);
        let j = s.segment_jet4(seg, ti).derivatives();
        out.push_str(&format!("{j:?}\n"));
        if let Some(j6) = s.segment_jet6(seg, ti) {
            out.push_str(&format!("{:?}\n", j6.derivatives()));
        }
    }
    let mut buf = vec![0.0; t.len() * 16];
    evaluate_into(s, &t, 0, 3, Extrapolate::Raise, &mut buf).ok();
    for x in buf {
        bits(out, x);
    }
    out.push('\n');
}

fn main() {
    let mut out = String::new();
    let h = hard();
    // special
    for &x in &h {
        for x in [x, -x] {
            bits(&mut out, special::sinc(x));
            for c in [1.0, 0.5, 2.0, -1.0, 1e-3] {
                bits(&mut out, special::atan2_over(x.abs(), c));
            }
            for a in [0.0, 0.25, 0.5, 0.999, 1.0, 1.5] {
                bits(&mut out, special::sin_ratio(a, x.abs()));
            }
        }
    }
    out.push('\n');
    // fit::so3 and quaternion exp/log, conversions
    for &x in &h {
        for dir in [[1.0, 0.0, 0.0], [0.6, -0.8, 0.0], [0.48, 0.6, 0.64]] {
            let v = [x * dir[0], x * dir[1], x * dir[2]];
            out.push_str(&format!(
                "{:?} {:?} {:?} {:?} {:?}\n",
                fit::so3::jr(v),
                fit::so3::jr_inv(v),
                fit::so3::jl_inv(v),
                fit::so3::dist_hess_sqrt(v),
                fit::so3::exp(v)
            ));
            let q = convert::from_rotvec(v);
            out.push_str(&format!(
                "{:?} {:?} {:?} {:?} {:?}\n",
                q,
                convert::to_rotvec(q),
                fit::so3::log(q),
                Quat::pure(v).exp(),
                q.log()
            ));
            for t in [0.0, 0.3, 0.5, 1.0] {
                out.push_str(&format!("{:?} ", quatspline::interp::slerp(Quat::IDENTITY, q, t, false)));
                let d = DualQuat::from_rotation_translation(q, [0.3, -0.2, x]);
                out.push_str(&format!("{:?} ", d.powf(t)));
            }
            let d = DualQuat::from_rotation_translation(q, [0.3, -0.2, 0.1]);
            out.push_str(&format!("{:?}\n", d.screw()));
        }
    }
    for n in 1..=8 {
        out.push_str(&format!("{:?}\n", fit::gauss_legendre01(n)));
    }
    // splines on keys with hard angles
    for (seed, scale) in
        [(1u64, 1e-12), (2, 1e-8), (3, 1e-3), (4, 0.2), (5, 0.6), (6, 1.5), (7, 3.0), (8, 6.0)]
    {
        let keys = rng_quats(9, seed, scale);
        let times: Vec<f64> = (0..9).map(|i| i as f64 * 0.7 + 0.1 * (i % 3) as f64).collect();
        for ends in [
            NaturalEnds::Natural,
            NaturalEnds::Rest,
            NaturalEnds::Closed,
            NaturalEnds::Clamped { start: None, end: None },
        ] {
            if let Ok(s) = NaturalSpline::with_keyframes(&keys, Some(&times), ends, true, true) {
                out.push_str(&format!("rates {:?}\n", s.key_rates()));
                dump_spline(&mut out, &format!("natural {seed} {ends:?}"), &s);
                if seed == 5 {
                    let arc = Reparameterized::arc_length(Arc::new(s.clone())).unwrap();
                    out.push_str(&format!("len {:?}\n", arc.length()));
                    dump_spline(&mut out, "arc", &arc);
                    out.push_str(&format!("{:?}\n", quatspline::spline::max_rate(&s, 2)));
                }
            }
        }
        let rates: Vec<[f64; 3]> = (0..9).map(|i| [0.1 * i as f64, -0.2, 0.05 * scale]).collect();
        let acc: Vec<[f64; 3]> = (0..9).map(|i| [0.01, 0.1 * i as f64, -0.3 * scale]).collect();
        for frame in [Frame::Body, Frame::World] {
            for a in [None, Some(&acc[..])] {
                let s = Hermite::new(&keys, Some(&times), &rates, a, frame, KeyEnds::Open, true).unwrap();
                dump_spline(&mut out, "hermite", &s);
            }
        }
        let pos: Vec<[f64; 3]> = (0..9).map(|i| [i as f64, (i as f64).sin(), 0.1 * scale]).collect();
        if let Ok(s) = ScrewSpline::new(&keys, &pos, Some(&times), true, &[0.0; 9], &[1.0; 9]) {
            dump_spline(&mut out, "screw", &s);
        }
        let knots: Vec<f64> = (0..9 + 4).map(|i| i as f64).collect();
        for f in [PoseFormulation::Se3, PoseFormulation::Split] {
            if let Ok(s) = PoseBSpline::new(&keys, &pos, &knots, 4, f) {
                dump_spline(&mut out, "pose", &s);
            }
        }
        let w: Vec<[f64; 3]> = (0..9).map(|i| [0.3 * scale, -0.1 * i as f64, 0.7]).collect();
        for m in [RateModel::Zoh, RateModel::Linear, RateModel::Cubic] {
            for fr in [Frame::Body, Frame::World] {
                out.push_str(&format!("{:?}\n", integrate(&times, &w, keys[0], fr, m)));
            }
        }
    }
    // fits
    let n = 120;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.05 + 0.001 * ((i * 7) % 5) as f64).collect();
    let data: Vec<Quat> = t
        .iter()
        .enumerate()
        .map(|(i, &s)| {
            let e = if i % 17 == 3 { 2.5 } else { 0.01 * ((i * 13) % 7) as f64 - 0.03 };
            convert::from_rotvec([0.8 * (0.5 * s).sin() + e, 0.6 * (0.37 * s).cos() - 0.3 * e, 0.2 * s])
        })
        .collect();
    let pos: Vec<[f64; 3]> = t.iter().map(|&s| [s.sin(), s * s * 0.1, (2.0 * s).cos()]).collect();
    for pen in [Penalty::Acceleration, Penalty::Jerk] {
        for sm in [Smoothing::Auto, Smoothing::Fixed(0.0), Smoothing::Fixed(1e-3), Smoothing::Fixed(10.0)] {
            for rob in [Robust::None, Robust::Huber, Robust::Cauchy] {
                for knots in [
                    Knots::Default,
                    Knots::Spacing(0.4),
                    Knots::Array(vec![t[0], 1.0, 2.5, 3.0, 4.1, t[n - 1]]),
                    Knots::Spacing(0.04),
                ] {
                    let opts = FitOptions {
                        penalty: pen,
                        smoothing: sm,
                        robust: rob,
                        knots: knots.clone(),
                        ..Default::default()
                    };
                    let mut prog = |_: &str, _: usize, _: f64| true;
                    let r = fit::fit(&t, &data, None, &opts, &mut prog);
                    out.push_str(&format!("fit {pen:?} {sm:?} {rob:?} {knots:?}\n{r:?}\n"));
                    let p = fit::position::fit_positions(&t, &pos, None, pen, None, sm, &knots, rob, None);
                    out.push_str(&format!("pos {p:?}\n"));
                }
            }
        }
        let keys = rng_quats(6, 11, 1.2);
        let kt: Vec<f64> = (0..6).map(|i| i as f64).collect();
        for per in [1, 3] {
            let mut prog = |_: &str, _: usize, _: f64| true;
            let r = fit::min_energy::min_energy_bspline(&kt, &keys, pen, per, &mut prog);
            out.push_str(&format!("mebs {r:?}\n"));
        }
    }
    let keys = rng_quats(6, 12, 1.2);
    let kt: Vec<f64> = (0..6).map(|i| i as f64 * 0.8).collect();
    for res in [0, 2] {
        for ends in [NaturalEnds::Natural, NaturalEnds::Rest] {
            let mut prog = |_: &str, _: usize, _: f64| true;
            if let Ok(s) = fit::min_energy::MinEnergySpline::new(&keys, Some(&kt), ends, res, &mut prog) {
                out.push_str(&format!("me energy {:?}\n", s.energy_of()));
                dump_spline(&mut out, "minenergy", &s);
            }
        }
    }
    print!("{out}");
}
