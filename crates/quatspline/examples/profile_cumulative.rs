//! Times the cumulative family's batch path on one core: CPU time of this thread, so that
//! other processes on a shared machine inflate it less than wall time (a profile, not the
//! peer benchmark). 1,000 keys (the walk of `benches/core.rs`), 10⁶ sorted samples.
//!
//!   cargo run --release -p quatspline --example profile_cumulative -- [case|all] [reps] [samples]
//!
//! Cases: bspl / bspw / bspb / bspa / bspj (cubic B-spline value, ω world, ω body, α world,
//! jerk world), c3 / c3w / c3b / c3a / c3j (the same for the C³ knot spline). `QS_CHUNK=c` evaluates c samples at a time into one small buffer (no
//! memory traffic for the output); `QS_UNSORTED=1` shuffles the times.
use quatspline::spline::*;
use quatspline::Quat;

/// CPU time of this thread in ns (Linux; wall time elsewhere).
#[cfg(target_os = "linux")]
fn cpu_ns() -> f64 {
    #[repr(C)]
    struct Ts {
        s: i64,
        ns: i64,
    }
    extern "C" {
        fn clock_gettime(clk: i32, ts: *mut Ts) -> i32;
    }
    const CLOCK_THREAD_CPUTIME_ID: i32 = 3;
    let mut ts = Ts { s: 0, ns: 0 };
    // SAFETY: a valid clock id and a pointer to a timespec-shaped struct.
    unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.s as f64 * 1e9 + ts.ns as f64
}

#[cfg(not(target_os = "linux"))]
fn cpu_ns() -> f64 {
    static START: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
    START.get_or_init(std::time::Instant::now).elapsed().as_nanos() as f64
}

fn main() {
    let which = std::env::args().nth(1).unwrap_or_else(|| "all".into());
    let reps: usize = std::env::args().nth(2).and_then(|s| s.parse().ok()).unwrap_or(9);
    let n = 1000;
    let mut q = vec![Quat::new(0.5, 0.5, -0.5, 0.5)];
    for k in 1..n {
        let a = 0.3 + 0.05 * (k % 8) as f64;
        let (s, c) = (0.5 * a).sin_cos();
        let ax = [(k as f64).sin(), (1.7 * k as f64).cos(), 0.5];
        let m = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
        q.push(q[k - 1] * Quat::new(c, s * ax[0] / m, s * ax[1] / m, s * ax[2] / m));
    }
    let m: usize = std::env::args().nth(3).and_then(|s| s.parse().ok()).unwrap_or(1_000_000);
    let mut t: Vec<f64> = (0..m).map(|i| i as f64 * 999.0 / (m - 1) as f64).collect();
    let mut tb: Vec<f64> = (0..m).map(|i| i as f64 * 997.0 / (m - 1) as f64).collect();
    if std::env::var("QS_UNSORTED").is_ok_and(|v| v == "1") {
        // a fixed pseudo-random permutation (xorshift Fisher–Yates)
        let mut rng = quatspline::testing::XorShift64::new(0x9E37_79B9_7F4A_7C15);
        for i in (1..m).rev() {
            let j = (rng.next_u64() % (i as u64 + 1)) as usize;
            t.swap(i, j);
            tb.swap(i, j);
        }
    }
    let b = CumulativeBSpline::new(&q, 1.0, 0.0, 4, true).unwrap();
    let c3 = C3Spline::new(&q, None, &[0.3125], &[0.0], C3Variant::Knot, true).unwrap();
    let mut out = vec![0.0; 4 * m];
    // kind: 0 value, 1 ω body, 2 ω world, 3 α world, 4 jerk world
    let cases: Vec<(&str, &dyn Spline, &[f64], usize)> = vec![
        ("bspl", &b, &tb, 0),
        ("bspw", &b, &tb, 2),
        ("bspb", &b, &tb, 1),
        ("bspa", &b, &tb, 3),
        ("bspj", &b, &tb, 4),
        ("c3", &c3, &t, 0),
        ("c3w", &c3, &t, 2),
        ("c3b", &c3, &t, 1),
        ("c3a", &c3, &t, 3),
        ("c3j", &c3, &t, 4),
    ];
    for (name, s, tt, kind) in cases {
        if which != "all" && which != name {
            continue;
        }
        let mut best = f64::INFINITY;
        let reps = reps * (1_000_000 / m).max(1);
        for _ in 0..reps {
            let c0 = cpu_ns();
            // QS_CHUNK=c: every chunk of c samples into the same small buffer (no memory traffic)
            let c = std::env::var("QS_CHUNK").ok().and_then(|v| v.parse().ok()).unwrap_or(m);
            for tc in tt.chunks(c) {
                let n = tc.len();
                match kind {
                    0 => evaluate_into(s, tc, 0, 0, Extrapolate::Raise, &mut out[..4 * n]).unwrap(),
                    1 => {
                        angular_into(s, tc, 0, 1, Frame::Body, Extrapolate::Raise, &mut out[..3 * n]).unwrap()
                    }
                    k => angular_into(s, tc, 0, k - 1, Frame::World, Extrapolate::Raise, &mut out[..3 * n])
                        .unwrap(),
                }
            }
            best = best.min((cpu_ns() - c0) / m as f64);
        }
        println!("{name}: {best:.2} ns/sample (cpu, best of {reps})  [{:.3}]", out[12345 % out.len()]);
    }
}
