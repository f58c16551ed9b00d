//! The batch path of `evaluate_into` / `angular_into`: chunks of samples are validated at
//! once, located (a cursor for sorted runs, the bucket [`Locator`](crate::simd::Locator) otherwise)
//! and handed to the spline's [`BatchKernel`] in runs of in-domain samples. A time outside the
//! domain (or not finite) goes alone through the per-sample reference path, which raises,
//! clamps (or extrapolates) and reports the first offending index exactly as before.

use super::Spline;
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::simd::{self, BatchKernel, Isa};

/// Samples per chunk (segment indices live on the stack).
pub const CHUNK: usize = 256;

/// Runs `kern` on every chunk of in-domain samples, `reference` on the others.
#[allow(clippy::too_many_arguments)]
fn chunks(
    s: &dyn Spline,
    k: &dyn BatchKernel,
    isa: Isa,
    t: &[f64],
    first: usize,
    width: usize,
    out: &mut [f64],
    mut kern: impl FnMut(&[u32], &[f64], &mut [f64]) -> bool,
    mut reference: impl FnMut(&[f64], usize, &mut [f64]) -> Result<()>,
) -> Result<()> {
    if out.len() < t.len() * width {
        return Err(Error::Internal(format!(
            "output buffer holds {} numbers, {} samples need {}",
            out.len(),
            t.len(),
            t.len() * width
        )));
    }
    let (lo, hi) = s.domain();
    let loc = k.locator();
    let mut seg = [0u32; CHUNK];
    let mut cur = 0usize;
    for (c, (tc, oc)) in t.chunks(CHUNK).zip(out.chunks_mut(CHUNK * width)).enumerate() {
        let first_c = first + c * CHUNK;
        // runs of in-domain samples go to the kernel; each other sample (outside the domain or
        // not finite: NaN fails both comparisons) to the reference path, alone, so that no
        // in-domain row depends on its neighbours
        let inside = |x: f64| x >= lo && x <= hi;
        // one pass: every sample inside the domain? in increasing order?
        let (mut all_in, mut sorted) = (true, true);
        for (x, y) in tc.iter().zip(&tc[1..]) {
            all_in &= (*x >= lo) & (*x <= hi);
            sorted &= x <= y;
        }
        let x = tc[tc.len() - 1];
        all_in &= (x >= lo) & (x <= hi);
        if all_in {
            // the common case: the whole chunk is one run
            loc.locate_run(isa, tc, &mut seg[..tc.len()], &mut cur, sorted);
            if !kern(&seg[..tc.len()], tc, oc) {
                reference(tc, first_c, oc)?;
            }
            continue;
        }
        let mut i = 0;
        while i < tc.len() {
            if !inside(tc[i]) {
                reference(&tc[i..i + 1], first_c + i, &mut oc[i * width..(i + 1) * width])?;
                i += 1;
                continue;
            }
            let mut j = i + 1;
            while j < tc.len() && inside(tc[j]) {
                j += 1;
            }
            let run = &tc[i..j];
            loc.locate_run(isa, run, &mut seg[i..j], &mut cur, run.windows(2).all(|w| w[0] <= w[1]));
            let o = &mut oc[i * width..j * width];
            if !kern(&seg[i..j], &tc[i..j], o) {
                reference(&tc[i..j], first_c + i, o)?;
            }
            i = j;
        }
    }
    Ok(())
}

/// The batch path of `evaluate_into`; None when the spline has no kernels or the mode is
/// `reference`.
pub fn evaluate(
    s: &dyn Spline,
    t: &[f64],
    first: usize,
    order: usize,
    reference: impl FnMut(&[f64], usize, &mut [f64]) -> Result<()>,
    out: &mut [f64],
) -> Option<Result<()>> {
    let k = s.batch()?;
    let isa = simd::isa()?;
    let kern = |seg: &[u32], tc: &[f64], o: &mut [f64]| k.evaluate(isa, seg, tc, order, o);
    Some(chunks(s, k, isa, t, first, 4 * (order + 1), out, kern, reference))
}

/// The batch path of `angular_into` (see [`evaluate`]).
pub fn angular(
    s: &dyn Spline,
    t: &[f64],
    first: usize,
    order: usize,
    frame: Frame,
    reference: impl FnMut(&[f64], usize, &mut [f64]) -> Result<()>,
    out: &mut [f64],
) -> Option<Result<()>> {
    let k = s.batch()?;
    let isa = simd::isa()?;
    let kern = |seg: &[u32], tc: &[f64], o: &mut [f64]| k.angular(isa, seg, tc, order, frame, o);
    Some(chunks(s, k, isa, t, first, 3, out, kern, reference))
}
