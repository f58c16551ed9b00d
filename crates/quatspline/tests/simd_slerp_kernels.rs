//! The slerp-family batch kernels (Squad, Catmull–Rom / Kochanek–Bartels, spherical Bézier),
//! the vector atan2 and the pairs kernel against their scalar references (the per-sample jet
//! path, libm, `interp::slerp`) on both instruction sets: sorted and unsorted times, runs
//! crossing segments mid-vector, lengths 0–9, samples exactly at joints and ends, every
//! derivative order through the engine (the kernels cover values; derivatives keep the jets),
//! keyframe options (rest, closed, holds, α), chunking independence.

mod common;

use common::{isas, max_rel, reference_eval, shuffled, times, walk, Rng};
use quatspline::simd::{self, pairs, Isa};
use quatspline::spline::{
    angular_into, angular_reference_into, evaluate_into, evaluate_reference_into, CatmullRom, CatmullRomEnds,
    Extrapolate, Frame, KeyEnds, KochanekBartels, SphericalBezier, Spline, Squad, Tcb, TcbEnds,
};
use quatspline::Quat;

/// Keys whose neighbours are exactly `half` apart (the angle between the 4-vectors; rotation
/// 2·half) about random axes.
fn steps(n: usize, seed: u64, half: f64) -> Vec<Quat> {
    let mut r = Rng(seed);
    let mut q = vec![Quat::new(0.5, -0.5, 0.5, 0.5)];
    for _ in 1..n {
        let ax = [r.next() - 0.5, r.next() - 0.5, r.next() - 0.5];
        let m = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
        let (s, c) = half.sin_cos();
        let next = *q.last().unwrap() * Quat::new(c, s * ax[0] / m, s * ax[1] / m, s * ax[2] / m);
        q.push(next);
    }
    q
}

fn splines() -> Vec<(String, Box<dyn Spline>)> {
    let q = walk(30, 1, 1.2);
    let t = times(30, 2);
    // keys with a hold (keys 10..=12 equal)
    let mut qh = q.clone();
    qh[11] = qh[10];
    qh[12] = qh[10];
    let mut tclosed = t.clone();
    tclosed.push(t[29] + 0.7);
    let tcb_t: Vec<f64> = (0..30).map(|i| 0.3 * ((i as f64) * 0.7).sin()).collect();
    let tcb_c: Vec<f64> = (0..30).map(|i| 0.4 * ((i as f64) * 1.3).cos()).collect();
    let tcb_b: Vec<f64> = (0..30).map(|i| -0.5 + (i as f64) / 30.0).collect();
    let tcb = Tcb { tension: &tcb_t, continuity: &tcb_c, bias: &tcb_b };
    let mut v: Vec<(String, Box<dyn Spline>)> = vec![
        ("squad".into(), Box::new(Squad::new(&q, Some(&t), true).unwrap())),
        ("squad 2 keys".into(), Box::new(Squad::new(&q[..2], Some(&t[..2]), true).unwrap())),
        (
            "squad rest".into(),
            Box::new(Squad::with_keyframes(&q, Some(&t), KeyEnds::Rest, false, true).unwrap()),
        ),
        (
            "squad closed holds".into(),
            Box::new(Squad::with_keyframes(&qh, Some(&tclosed), KeyEnds::Closed, true, true).unwrap()),
        ),
        (
            "catmull_rom".into(),
            Box::new(CatmullRom::new(&q, Some(&t), CatmullRomEnds::Reflect, true).unwrap()),
        ),
        (
            "catmull_rom dup".into(),
            Box::new(CatmullRom::new(&q, None, CatmullRomEnds::Duplicate, true).unwrap()),
        ),
        (
            "catmull_rom centripetal closed".into(),
            Box::new(CatmullRom::with_keyframes(&q, None, Some(0.5), TcbEnds::Closed, false, true).unwrap()),
        ),
        (
            "catmull_rom holds rest".into(),
            Box::new(CatmullRom::with_keyframes(&qh, Some(&t), None, TcbEnds::Rest, true, true).unwrap()),
        ),
        (
            "kochanek_bartels".into(),
            Box::new(KochanekBartels::new(&q, Some(&t), None, tcb, TcbEnds::Reflect, false, true).unwrap()),
        ),
    ];
    // beyond 16 points the records live on the heap and the pyramid is taller (up to 65)
    for n in [2, 3, 4, 8, 16, 17, 33, 65] {
        let c = walk(n, 7 + n as u64, 1.5);
        v.push((format!("bezier {n}"), Box::new(SphericalBezier::new(&c, (-1.0, 2.5), true).unwrap())));
    }
    // small angles between control points (≤ 0.24 rad halved: the second series tier, and
    // ≤ 0.12: the first, as in the benchmark's curve): the series slerp of every level
    // (`simd::slerp::SERIES_MAX_ANGLE`)
    for n in [2, 3, 4, 8, 9, 16, 17, 33, 65] {
        let c = walk(n, 30 + n as u64, 0.4);
        v.push((format!("bezier {n} small"), Box::new(SphericalBezier::new(&c, (-1.0, 2.5), true).unwrap())));
        let c = walk(n, 60 + n as u64, 0.2);
        v.push((format!("bezier {n} tiny"), Box::new(SphericalBezier::new(&c, (-1.0, 2.5), true).unwrap())));
    }
    // every neighbour at a series tier's largest angle, and just beyond it
    // (`simd::slerp::SERIES_MAX_ANGLE`: 0.15, 0.3 and 0.5)
    for (tag, half) in [
        ("at 1st", 0.1499),
        ("beyond 1st", 0.1501),
        ("at 2nd", 0.2999),
        ("beyond 2nd", 0.3001),
        ("at 3rd", 0.4999),
        ("beyond 3rd", 0.5001),
    ] {
        let c = steps(8, 43, half);
        v.push((
            format!("bezier 8 {tag} switch"),
            Box::new(SphericalBezier::new(&c, (0.0, 1.0), true).unwrap()),
        ));
    }
    // Catmull–Rom on steps from 0.04 to 0.6 rad (halved): segments of every series tier and
    // of the trigonometric path side by side
    let qm = walk(60, 21, 1.0);
    v.push((
        "catmull_rom mixed tiers".into(),
        Box::new(CatmullRom::new(&qm, Some(&times(60, 6)), CatmullRomEnds::Reflect, true).unwrap()),
    ));
    // Catmull–Rom on small steps: segments on both paths side by side
    let qs = walk(40, 3, 0.5);
    v.push((
        "catmull_rom small".into(),
        Box::new(CatmullRom::new(&qs, Some(&times(40, 5)), CatmullRomEnds::Reflect, true).unwrap()),
    ));
    // far-apart control points (angles near π between neighbours, no canonicalisation)
    let mut r = Rng(77);
    let wild: Vec<Quat> = (0..6).map(|_| r.quat()).collect();
    v.push(("bezier wild".into(), Box::new(SphericalBezier::new(&wild, (0.0, 1.0), false).unwrap())));
    v
}

/// Probe times with 300 random interior points.
fn probe_times(s: &dyn Spline, seed: u64) -> Vec<f64> {
    common::probe_times(s, seed, 300)
}

/// The kernel's value rows (it must have one for order 0).
fn kernel_values(s: &dyn Spline, isa: Isa, t: &[f64]) -> Vec<f64> {
    common::kernel_eval(s, isa, t, 0)
}

#[test]
fn value_kernels_equal_the_reference_sorted_and_unsorted() {
    for (name, s) in splines() {
        let s = &*s;
        let mut sorted = probe_times(s, 3);
        sorted.sort_by(f64::total_cmp);
        let unsorted = shuffled(&sorted, 99);
        for isa in isas() {
            for (kind, t) in [("sorted", &sorted), ("unsorted", &unsorted)] {
                let e = max_rel(s, t, &kernel_values(s, isa, t), &reference_eval(s, t, 0), 4, 0);
                assert!(e <= 1.0, "{name} {isa:?} {kind}: {e:e}");
            }
            // each row its own bits whatever shares its vector (segments of different series
            // tiers and of the trigonometric path mixed within vectors when unsorted)
            let (a, b) = (kernel_values(s, isa, &sorted), kernel_values(s, isa, &unsorted));
            for (i, x) in unsorted.iter().enumerate() {
                let k = sorted.partition_point(|v| v < x);
                assert!(
                    a[4 * k..4 * k + 4]
                        .iter()
                        .zip(&b[4 * i..4 * i + 4])
                        .all(|(p, q)| p.to_bits() == q.to_bits()),
                    "{name} {isa:?}: row of t = {x} differs between sorted and unsorted input"
                );
            }
        }
    }
}

/// Through the engine (both modes the process can run: auto and forced scalar are the same
/// kernels as above; here the chunking, locating and the jets for derivatives): every order
/// and every rate, sorted and unsorted, clamped samples in the middle.
#[test]
fn engine_equals_reference_for_every_order_and_frame() {
    for (name, s) in splines() {
        let s = &*s;
        let (a, b) = s.domain();
        let mut r = Rng(5);
        let mut t: Vec<f64> = (0..600).map(|i| a + (b - a) * i as f64 / 599.0).collect();
        t.extend((0..300).map(|_| a + (b - a) * r.next()));
        let u = shuffled(&t, 4);
        for tt in [&t, &u] {
            for order in 0..=3 {
                let mut fast = vec![0.0; tt.len() * 4 * (order + 1)];
                evaluate_into(s, tt, 0, order, Extrapolate::Raise, &mut fast).unwrap();
                let e = max_rel(s, tt, &fast, &reference_eval(s, tt, order), 4 * (order + 1), 0);
                assert!(e <= 1.0, "{name} engine order {order}: {e:e}");
            }
            for order in 1..=3 {
                for frame in [Frame::Body, Frame::World] {
                    let mut fast = vec![0.0; tt.len() * 3];
                    let mut refr = vec![0.0; tt.len() * 3];
                    angular_into(s, tt, 0, order, frame, Extrapolate::Raise, &mut fast).unwrap();
                    angular_reference_into(s, tt, 0, order, frame, Extrapolate::Raise, &mut refr).unwrap();
                    let e = max_rel(s, tt, &fast, &refr, 3, order);
                    assert!(e <= 1.0, "{name} engine angular {order} {frame:?}: {e:e}");
                }
            }
        }
        let mut tc = t.clone();
        tc[100] = b + 1.0;
        tc[400] = a - 5.0;
        let mut fast = vec![0.0; tc.len() * 4];
        let mut refr = vec![0.0; tc.len() * 4];
        evaluate_into(s, &tc, 0, 0, Extrapolate::Clamp, &mut fast).unwrap();
        evaluate_reference_into(s, &tc, 0, 0, Extrapolate::Clamp, &mut refr).unwrap();
        assert!(max_rel(s, &tc, &fast, &refr, 4, 0) <= 1.0, "{name} clamp");
        evaluate_into(s, &tc, 0, 0, Extrapolate::Linear, &mut fast).unwrap();
        evaluate_reference_into(s, &tc, 0, 0, Extrapolate::Linear, &mut refr).unwrap();
        assert_eq!(&fast[400..404], &refr[400..404], "{name} linear extrapolation row");
        tc[700] = f64::NAN;
        let err = evaluate_into(s, &tc, 10, 0, Extrapolate::Raise, &mut fast).unwrap_err().to_string();
        let want =
            evaluate_reference_into(s, &tc, 10, 0, Extrapolate::Raise, &mut refr).unwrap_err().to_string();
        assert_eq!(err, want);
    }
}

#[test]
fn short_runs_crossing_segments_and_exact_joints() {
    for (name, s) in splines() {
        let s = &*s;
        let j = s.joints();
        let (l, right) = (j[0], if j.len() > 2 { j[2] } else { j[1] });
        let base: Vec<f64> = (0..9).map(|i| l + (right - l) * (0.05 + 0.9 * i as f64 / 8.0)).collect();
        for isa in isas() {
            for len in 0..=9 {
                for start in 0..(9 - len).max(1) {
                    let t = &base[start..start + len];
                    let e = max_rel(s, t, &kernel_values(s, isa, t), &reference_eval(s, t, 0), 4, 0);
                    assert!(e <= 1.0, "{name} {isa:?} len {len} start {start}: {e:e}");
                }
            }
            let t: Vec<f64> = j.to_vec();
            let e = max_rel(s, &t, &kernel_values(s, isa, &t), &reference_eval(s, &t, 0), 4, 0);
            assert!(e <= 1.0, "{name} {isa:?} joints: {e:e}");
        }
    }
}

#[test]
fn rows_do_not_depend_on_chunking_and_isas_agree() {
    for (name, s) in splines() {
        let s = &*s;
        let t = shuffled(&probe_times(s, 8), 3);
        for isa in isas() {
            let whole = kernel_values(s, isa, &t);
            let mut pieces = Vec::new();
            for c in t.chunks(7) {
                pieces.extend(kernel_values(s, isa, c));
            }
            assert!(whole == pieces, "{name} {isa:?}");
        }
        if simd::avx2_available() {
            let e =
                max_rel(s, &t, &kernel_values(s, Isa::Avx2, &t), &kernel_values(s, Isa::Scalar, &t), 4, 0);
            assert!(e <= 1.0, "{name}: {e:e}");
        }
        // AVX-512 (8 lanes) gives AVX2's (4 lanes) rows bit for bit
        if simd::avx512_available() {
            assert!(kernel_values(s, Isa::Avx512, &t) == kernel_values(s, Isa::Avx2, &t), "{name}");
        }
    }
}

/// Every degree a spherical Bézier curve takes has the kernel (the largest table included),
/// and the engine's rows are the kernel's.
#[test]
fn bezier_of_every_degree_has_the_kernel() {
    // the kernel's limit is the curve's: one more point is refused at construction
    let over = walk(simd::slerp::MAX_POINTS + 1, 3, 1.0);
    assert!(SphericalBezier::new(&over, (0.0, 1.0), true).is_err());
    for n in [2, 16, 17, 40, simd::slerp::MAX_POINTS] {
        let c = walk(n, 3, 1.0);
        let s = SphericalBezier::new(&c, (0.0, 1.0), true).unwrap();
        assert!(s.batch().is_some(), "{n} points");
        let t: Vec<f64> = (0..50).map(|i| i as f64 / 49.0).collect();
        let mut fast = vec![0.0; 200];
        evaluate_into(&s, &t, 0, 0, Extrapolate::Raise, &mut fast).unwrap();
        if let Some(isa) = simd::isa() {
            assert_eq!(fast, kernel_values(&s, isa, &t), "{n} points");
        }
    }
}

fn ulps(a: f64, b: f64) -> f64 {
    if a == b {
        return 0.0;
    }
    (a - b).abs() / (b.abs().max(f64::MIN_POSITIVE) * f64::EPSILON)
}

/// The vector atan2 within 2 ulp of libm over every quadrant, the reduction's branch edges
/// (|y|/|x| near 0.66 and tan 3π/8), tiny and huge ratios, signed zeros.
#[test]
fn vector_atan2_within_two_ulp_of_libm() {
    let mut y = Vec::new();
    let mut x = Vec::new();
    let mut r = Rng(12);
    for _ in 0..200_000 {
        let (a, b) = (r.next() * 2.0 - 1.0, r.next() * 2.0 - 1.0);
        let e = (r.next() * 40.0 - 20.0).exp2();
        y.push(a * e);
        x.push(b);
    }
    for k in 0..20_000 {
        let ang = std::f64::consts::PI * (k as f64 / 10_000.0 - 1.0);
        y.push(ang.sin());
        x.push(ang.cos());
    }
    for ratio in [0.66f64, 2.414_213_562_373_095, 1.0, 1e-300, 1e-20, 1e20, 1e300] {
        for d in -20i64..=20 {
            let v = f64::from_bits(ratio.to_bits().wrapping_add(d as u64));
            for (sy, sx) in [(1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)] {
                y.push(sy * v);
                x.push(sx);
            }
        }
    }
    for (a, b) in [
        (0.0, 1.0),
        (-0.0, 1.0),
        (0.0, -1.0),
        (-0.0, -1.0),
        (1.0, 0.0),
        (-1.0, 0.0),
        (0.0, 0.0),
        (0.0, -0.0),
        (-0.0, -0.0),
        (1e-310, 1.0),
        (1.0, 1e-310),
    ] {
        y.push(a);
        x.push(b);
    }
    for isa in isas() {
        let mut out = vec![0.0; y.len()];
        simd::atan2_slice(isa, &y, &x, &mut out);
        let mut worst: f64 = 0.0;
        for i in 0..y.len() {
            let want = y[i].atan2(x[i]);
            assert_eq!(
                out[i].is_sign_negative(),
                want.is_sign_negative(),
                "{isa:?} atan2({}, {})",
                y[i],
                x[i]
            );
            worst = worst.max(ulps(out[i], want));
            assert!(ulps(out[i], want) <= 2.0, "{isa:?} atan2({}, {}) = {} vs {want}", y[i], x[i], out[i]);
        }
        eprintln!("{isa:?}: worst {worst} ulp");
        let mut o = [0.0];
        simd::atan2_slice(isa, &[f64::NAN], &[1.0], &mut o);
        assert!(o[0].is_nan());
    }
}

fn pair_data(n: usize, seed: u64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut r = Rng(seed);
    let (mut a, mut b, mut t) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..n {
        let p = r.quat();
        let q = match i % 7 {
            0 => p,                                                               // equal keys
            1 => -p,                                                              // opposite signs
            2 => (p * Quat::new(1.0, 1e-9 * r.next(), -3e-10, 1e-9)).normalize(), // nearly equal
            3 => (-p * Quat::new(1e-9, 1.0, 0.0, 0.0)).normalize(),               // nearly opposite
            _ => r.quat(),
        };
        // some keys not normalised (scaled) — the kernel normalises as the scalar path does
        let scale = if i % 5 == 0 { 3.7 } else { 1.0 };
        a.extend(p.to_wxyz().map(|c| c * scale));
        b.extend(q.to_wxyz());
        t.push(match i % 11 {
            0 => 0.0,
            1 => 1.0,
            2 => -0.25,
            3 => 1.5,
            _ => r.next(),
        });
    }
    (a, b, t)
}

#[test]
fn slerp_pairs_equal_the_scalar_slerp() {
    for long_path in [false, true] {
        let (a, b, t) = pair_data(1003, 21);
        let n = t.len();
        let mut want = vec![0.0; 4 * n];
        pairs::slerp_pairs_reference(&a, &b, &t, long_path, &mut want).unwrap();
        for isa in isas() {
            let mut got = vec![f64::NAN; 4 * n];
            pairs::slerp_pairs(isa, &a, &b, &t, long_path, &mut got).unwrap();
            for i in 0..n {
                for c in 0..4 {
                    let (g, w) = (got[4 * i + c], want[4 * i + c]);
                    assert!((g - w).abs() <= 1e-14, "{isa:?} long {long_path} row {i}: {g} vs {w}");
                }
                if t[i] == 0.0 || t[i] == 1.0 {
                    assert_eq!(&got[4 * i..4 * i + 4], &want[4 * i..4 * i + 4], "exact end, row {i}");
                }
            }
            // tails and chunking: every length 0–9 and every split give the same rows
            for len in 0..=9 {
                let mut o = vec![0.0; 4 * len];
                pairs::slerp_pairs(
                    isa,
                    &a[4..4 + 4 * len],
                    &b[4..4 + 4 * len],
                    &t[1..1 + len],
                    long_path,
                    &mut o,
                )
                .unwrap();
                assert_eq!(&o[..], &got[4..4 + 4 * len], "{isa:?} len {len}");
            }
        }
    }
}

#[test]
fn slerp_pairs_report_the_first_zero_key() {
    let (mut a, mut b, t) = ([1.0, 0.0, 0.0, 0.0].repeat(9), [0.0, 1.0, 0.0, 0.0].repeat(9), vec![0.5; 9]);
    b[4 * 6..4 * 6 + 4].copy_from_slice(&[0.0; 4]);
    a[4 * 7..4 * 7 + 4].copy_from_slice(&[0.0; 4]);
    // a tiny key (its squared norm underflows) and a huge one normalise (scaled first), as in
    // the scalar path; a denormal one is reported as zero there and here
    a[4 * 2..4 * 2 + 4].copy_from_slice(&[1e-200, 3e-201, 0.0, 0.0]);
    a[4 * 3..4 * 3 + 4].copy_from_slice(&[0.0, 2e200, 1e200, 0.0]);
    let mut o = vec![0.0; 24];
    let mut r = vec![0.0; 24];
    for isa in isas() {
        pairs::slerp_pairs(isa, &a[..24], &b[..24], &t[..6], false, &mut o).unwrap();
        pairs::slerp_pairs_reference(&a[..24], &b[..24], &t[..6], false, &mut r).unwrap();
        assert!(o.iter().zip(&r).all(|(x, y)| (x - y).abs() <= 1e-14), "{isa:?}: {o:?} vs {r:?}");
    }
    b[4 * 4..4 * 4 + 4].copy_from_slice(&[1e-310, 0.0, 0.0, 0.0]);
    let e = pairs::slerp_pairs(Isa::Scalar, &a[..24], &b[..24], &t[..6], false, &mut o).unwrap_err();
    assert!(e.to_string().starts_with("q1") && e.to_string().contains('4'), "{e}");
    b[4 * 4..4 * 4 + 4].copy_from_slice(&[0.0, 0.0, 1.0, 0.0]);
    for isa in isas() {
        let mut o = vec![0.0; 36];
        let e = pairs::slerp_pairs(isa, &a, &b, &t, false, &mut o).unwrap_err().to_string();
        let mut r = vec![0.0; 36];
        let want = pairs::slerp_pairs_reference(&a, &b, &t, false, &mut r).unwrap_err().to_string();
        assert_eq!(e, want);
        assert!(e.contains("q1") && e.contains('6'), "{e}");
    }
}

fn dq_of(r: Quat, t: [f64; 3]) -> [f64; 8] {
    quatspline::DualQuat::from_rotation_translation(r, t).to_array()
}

#[test]
fn sclerp_pairs_equal_the_scalar_sclerp() {
    let mut r = Rng(31);
    let n = 1001;
    let (mut a, mut b, mut t) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..n {
        let (p, q) = (r.quat(), r.quat());
        let tp = [4.0 * r.next() - 2.0, 4.0 * r.next() - 2.0, 4.0 * r.next() - 2.0];
        let tq = [4.0 * r.next() - 2.0, 4.0 * r.next() - 2.0, 4.0 * r.next() - 2.0];
        let (x, y) = match i % 6 {
            0 => (dq_of(p, tp), dq_of(p, tq)), // pure translation
            1 => (dq_of(p, tp), dq_of(p, tp)), // the same pose
            2 => (dq_of(p, tp), dq_of(-(p * Quat::new(1e-9, 0.3, -0.2, 0.9).normalize()), tq)), // w ≈ 0
            3 => (dq_of(p, tp), dq_of((p * Quat::new(1.0, 2e-9, 0.0, -1e-9)).normalize(), tq)), // tiny angle
            _ => (dq_of(p, tp), dq_of(q, tq)),
        };
        // some rows not normalised (scaled)
        let sc = if i % 5 == 0 { 2.5 } else { 1.0 };
        a.extend(x.map(|c| c * sc));
        b.extend(y);
        t.push(if i % 9 == 0 {
            0.0
        } else if i % 9 == 1 {
            1.0
        } else {
            1.4 * r.next() - 0.2
        });
    }
    let mut want = vec![0.0; 8 * n];
    pairs::sclerp_pairs_reference(&a, &b, &t, &mut want).unwrap();
    for isa in isas() {
        let mut got = vec![f64::NAN; 8 * n];
        pairs::sclerp_pairs(isa, &a, &b, &t, &mut got).unwrap();
        for i in 0..n {
            let (g, w) = (&got[8 * i..8 * i + 8], &want[8 * i..8 * i + 8]);
            let scale = w.iter().map(|v| v * v).sum::<f64>().sqrt().max(1.0);
            for c in 0..8 {
                assert!((g[c] - w[c]).abs() <= 1e-14 * scale, "{isa:?} row {i} comp {c}: {g:?} vs {w:?}");
            }
        }
        for len in 0..=9 {
            let mut o = vec![0.0; 8 * len];
            pairs::sclerp_pairs(
                isa,
                &a[8 * 3..8 * (3 + len)],
                &b[8 * 3..8 * (3 + len)],
                &t[3..3 + len],
                &mut o,
            )
            .unwrap();
            assert_eq!(&o[..], &got[8 * 3..8 * (3 + len)], "{isa:?} len {len}");
        }
        // a zero rotation part: the first one is reported, as by the scalar path
        let mut bad = b[..8 * 9].to_vec();
        bad[8 * 5..8 * 5 + 4].copy_from_slice(&[0.0; 4]);
        let mut o = vec![0.0; 72];
        let e = pairs::sclerp_pairs(isa, &a[..72], &bad, &t[..9], &mut o).unwrap_err().to_string();
        let w = pairs::sclerp_pairs_reference(&a[..72], &bad, &t[..9], &mut o).unwrap_err().to_string();
        assert_eq!(e, w);
        assert!(e.starts_with("dq1") && e.contains('5'), "{e}");
    }
}
