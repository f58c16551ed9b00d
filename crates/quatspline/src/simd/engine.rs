//! The batch path of `evaluate_into` / `angular_into`: chunks of samples are validated at
//! once, located (a cursor for sorted runs, the bucket [`Locator`](super::Locator) otherwise)
//! and handed to the spline's [`BatchKernel`]. A chunk holding any time outside the domain
//! (or not finite) goes through the per-sample reference path, which raises, clamps and
//! reports the first offending index exactly as before.

use super::BatchKernel;
use crate::error::{Error, Result};
use crate::spline::{Frame, Spline};

/// Samples per chunk (segment indices live on the stack).
pub const CHUNK: usize = 256;

/// Runs `kern` on every chunk of in-domain samples, `reference` on the others.
#[allow(clippy::too_many_arguments)]
fn chunks(
    s: &dyn Spline,
    k: &dyn BatchKernel,
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
    let last = s.segments() - 1;
    let mut seg = [0u32; CHUNK];
    let mut cur = 0usize;
    for (c, (tc, oc)) in t.chunks(CHUNK).zip(out.chunks_mut(CHUNK * width)).enumerate() {
        let first_c = first + c * CHUNK;
        // NaN fails both comparisons, so it lands in the reference path too
        if !tc.iter().all(|&x| x >= lo && x <= hi) {
            reference(tc, first_c, oc)?;
            continue;
        }
        for (i, &x) in tc.iter().enumerate() {
            if !loc.fits(cur, x) {
                cur = if cur < last && loc.fits(cur + 1, x) { cur + 1 } else { loc.locate(x) };
            }
            seg[i] = cur as u32;
        }
        if !kern(&seg[..tc.len()], tc, &mut oc[..tc.len() * width]) {
            reference(tc, first_c, oc)?;
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
    let isa = super::isa()?;
    let kern = |seg: &[u32], tc: &[f64], o: &mut [f64]| {
        k.evaluate(isa, seg, tc, order, o);
        true
    };
    Some(chunks(s, k, t, first, 4 * (order + 1), out, kern, reference))
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
    let isa = super::isa()?;
    let kern = |seg: &[u32], tc: &[f64], o: &mut [f64]| k.angular(isa, seg, tc, order, frame, o);
    Some(chunks(s, k, t, first, 3, out, kern, reference))
}
