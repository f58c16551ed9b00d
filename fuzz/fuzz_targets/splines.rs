//! Spline construction and evaluation from arbitrary bytes: every f64 bit pattern (NaN, inf,
//! denormals, huge and tiny values) as keys, times, shape parameters and query times.
//! Invariant: construction either fails with an `Error` or yields a spline whose every
//! evaluation inside its domain is finite; nothing panics.
#![no_main]

use libfuzzer_sys::fuzz_target;
use quatspline::spline::*;
use quatspline::Quat;

fn floats(data: &[u8]) -> Vec<f64> {
    data.chunks_exact(8).map(|c| f64::from_le_bytes(c.try_into().unwrap())).collect()
}

fn check(s: &dyn Spline, queries: &[f64]) {
    let (a, b) = s.domain();
    let mut out = vec![0.0; 16 * queries.len().max(1)];
    let _ = evaluate_into(s, queries, 0, 3, Extrapolate::Raise, &mut out);
    let inside: Vec<f64> = queries
        .iter()
        .map(|&t| if t.is_finite() { a + (b - a) * (t.abs().fract()) } else { a })
        .collect();
    if evaluate_into(s, &inside, 0, 3, Extrapolate::Clamp, &mut out).is_ok() {
        for (k, v) in out[..16 * inside.len()].iter().enumerate() {
            assert!(v.is_finite(), "{}: non-finite output {v} at {} (t = {})", s.name(), k, inside[k / 16]);
        }
    }
    let _ = quatspline::analysis::continuity(s, 3, 1e-9);
}

/// Inputs up to `-max_len=65536` bytes: with flag 0x40 in the first byte, the next two bytes
/// give the key count (up to 4,200, so more than 1,024 control points — the CumulativeBezier
/// overflow — and beyond its 4,096 limit are reachable when the input is long enough: 40
/// bytes per key); otherwise 1 … 8 keys as before.
fuzz_target!(|data: &[u8]| {
    if data.len() < 2 {
        return;
    }
    let big = data[0] & 0x40 != 0 && data.len() >= 3;
    let (want, rest) = if big {
        ((u16::from_le_bytes([data[1], data[2]]) as usize % 4200) + 1, &data[3..])
    } else {
        ((data[0] % 8) as usize + 1, &data[1..])
    };
    let head = [data[0]];
    let f = floats(rest);
    let n = want.min(f.len() / 5);
    if n == 0 {
        return;
    }
    let keys: Vec<Quat> = (0..n).map(|i| Quat::new(f[4 * i], f[4 * i + 1], f[4 * i + 2], f[4 * i + 3])).collect();
    let times: Vec<f64> = f[4 * n..5 * n].to_vec();
    let extra = &f[5 * n..];
    let p = |k: usize| extra.get(k).copied().unwrap_or(0.5);
    let queries: Vec<f64> = extra.iter().take(6).copied().collect();
    let use_times = head[0] & 0x80 != 0;
    let t = if use_times { Some(&times[..]) } else { None };
    let mut built: Vec<Box<dyn Spline>> = Vec::new();
    if let Ok(s) = PiecewiseSlerp::new(&keys, t, true) { built.push(Box::new(s)); }
    if let Ok(s) = PiecewiseNlerp::new(&keys, t) { built.push(Box::new(s)); }
    if let Ok(s) = PiecewiseLinEuler::new(&keys, t, "ZYX") { built.push(Box::new(s)); }
    if let Ok(s) = PiecewiseLinMat::new(&keys, t) { built.push(Box::new(s)); }
    if let Ok(s) = Squad::new(&keys, t, true) { built.push(Box::new(s)); }
    if let Ok(s) = CatmullRom::new(&keys, t, CatmullRomEnds::Reflect, true) { built.push(Box::new(s)); }
    if let Ok(s) = NaturalSpline::new(&keys, t, NaturalEnds::Natural, true) { built.push(Box::new(s)); }
    if let Ok(s) = C3Spline::new(&keys, t, &[p(0)], &[p(1)], C3Variant::Knot, true) { built.push(Box::new(s)); }
    if let Ok(s) = C3Spline::new(&keys, t, &[p(0)], &[p(1)], C3Variant::Patent, false) { built.push(Box::new(s)); }
    if let Ok(s) = CumulativeBSpline::new(&keys, p(2), p(3), 4, true) { built.push(Box::new(s)); }
    if let Ok(s) = BetaSpline::new(&keys, &[p(4)], &[p(5)], None, true) { built.push(Box::new(s)); }
    if let Ok(s) = SphericalBezier::new(&keys, (0.0, 1.0), true) { built.push(Box::new(s)); }
    if let Ok(s) = CumulativeBezier::new(&keys, (0.0, 1.0), true) { built.push(Box::new(s)); }
    for s in &built {
        check(&**s, &queries);
    }
});
