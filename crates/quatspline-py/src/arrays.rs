//! Array plumbing shared by every binding: shape checks, row access, output allocation,
//! error mapping and the panic guard.

use numpy::ndarray::ArrayView2;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::{PyMemoryError, PyOverflowError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use quatspline::{Error, Quat};
use rayon::prelude::*;
use std::borrow::Cow;

/// Maps the core's error to a Python exception: `RuntimeError` for internal errors,
/// `ValueError` for everything the caller can fix.
pub fn to_py(e: Error) -> PyErr {
    match e {
        Error::Internal(_) | Error::NotConverged { .. } => PyRuntimeError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// A non-negative integer argument (an order, a count, a resolution, an index): the one place
/// where Python integers cross into the core. Any int that fits a `usize` converts; one that
/// does not (negative, or beyond 2⁶⁴ − 1) is a `ValueError` — never PyO3's `OverflowError` —
/// with the value shown briefly (`~1e21`, not every digit). A non-integer stays a `TypeError`.
/// The range each argument accepts is then checked by its function, naming the argument.
#[derive(Debug, Clone, Copy)]
pub struct Count(pub usize);

impl<'a, 'py> FromPyObject<'a, 'py> for Count {
    type Error = PyErr;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        match obj.extract::<usize>() {
            Ok(v) => Ok(Count(v)),
            Err(e) if e.is_instance_of::<PyOverflowError>(obj.py()) => {
                let digits = obj.str().map(|s| s.to_string()).unwrap_or_default();
                Err(PyValueError::new_err(format!(
                    "expected an integer from 0 to {}, got {}",
                    usize::MAX,
                    short_int(&digits)
                )))
            }
            Err(e) => Err(e),
        }
    }
}

/// A decimal integer as messages show it: in full up to 15 digits, else `~1eN` (sign kept).
pub fn short_int(digits: &str) -> String {
    let (sign, mag) = match digits.strip_prefix('-') {
        Some(m) => ("-", m),
        None => ("", digits),
    };
    if mag.len() <= 15 {
        digits.to_string()
    } else {
        format!("{sign}~1e{}", mag.len() - 1)
    }
}

/// The thread pool set by `set_num_threads` (None: rayon's global pool, one thread per core).
static POOL: std::sync::RwLock<Option<std::sync::Arc<rayon::ThreadPool>>> = std::sync::RwLock::new(None);

/// Sets the number of threads for batch work (0 = one per core).
pub fn set_num_threads(n: usize) -> PyResult<()> {
    let pool = if n == 0 {
        None
    } else {
        Some(std::sync::Arc::new(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| PyRuntimeError::new_err(e.to_string()))?,
        ))
    };
    *POOL.write().map_err(|_| PyRuntimeError::new_err("thread pool lock poisoned"))? = pool;
    Ok(())
}

/// The number of threads batch work uses.
pub fn num_threads() -> usize {
    match POOL.read().ok().and_then(|p| p.as_ref().map(|p| p.current_num_threads())) {
        Some(n) => n,
        None => rayon::current_num_threads(),
    }
}

/// Runs `f` with the GIL released, inside the configured pool; a panic becomes a
/// `RuntimeError` naming `what`.
pub fn guarded<T: Send>(
    py: Python<'_>,
    what: &str,
    f: impl FnOnce() -> Result<T, Error> + Send,
) -> PyResult<T> {
    let pool = POOL.read().ok().and_then(|p| p.clone());
    let r = py.detach(|| {
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match pool {
            Some(p) => p.install(f),
            None => f(),
        }))
    });
    match r {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(e)) => Err(to_py(e)),
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown panic".into());
            Err(PyRuntimeError::new_err(format!("internal error in {what} (please report): {msg}")))
        }
    }
}

/// An uninitialised C-contiguous float64 (rows, width) output, or a `MemoryError` naming its
/// size: the size is checked for overflow first and the array comes from `numpy.empty`, whose
/// failure is a Python exception (rust-numpy's `PyArray::new` panics on a failed allocation,
/// and that panic reached Python as `PanicException`).
pub fn alloc2<'py>(
    py: Python<'py>,
    rows: usize,
    width: usize,
    what: &str,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let too_big = || {
        PyMemoryError::new_err(format!(
            "{what}: cannot allocate the ({rows}, {width}) float64 output ({})",
            human_bytes(rows as f64 * width as f64 * 8.0)
        ))
    };
    match rows.checked_mul(width).and_then(|e| e.checked_mul(8)) {
        Some(b) if b <= isize::MAX as usize => {}
        _ => return Err(too_big()),
    }
    let empty = py.import("numpy")?.getattr("empty")?;
    match empty.call1(((rows, width),)) {
        Ok(a) => Ok(a.cast_into::<PyArray2<f64>>()?),
        Err(e) if e.is_instance_of::<PyMemoryError>(py) => Err(too_big()),
        Err(e) => Err(e),
    }
}

/// A copy of `it` (exactly `len` items) in a Vec whose allocation failure is a `MemoryError`
/// (a failed `Vec` allocation would abort the process).
pub fn try_vec<T>(len: usize, it: impl Iterator<Item = T>, what: &str) -> PyResult<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| {
        PyMemoryError::new_err(format!(
            "{what}: cannot allocate {} for {len} items",
            human_bytes(len as f64 * std::mem::size_of::<T>() as f64)
        ))
    })?;
    v.extend(it);
    Ok(v)
}

fn human_bytes(b: f64) -> String {
    let units = ["bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut x = b;
    let mut k = 0;
    while x >= 1024.0 && k + 1 < units.len() {
        x /= 1024.0;
        k += 1;
    }
    if k == 0 {
        format!("{b:.0} bytes")
    } else {
        format!("{x:.1} {}", units[k])
    }
}

/// Runs `f` on the calling thread with the GIL held (for small calls, where releasing the
/// GIL and entering the pool cost more than the work); a panic becomes a `RuntimeError`.
pub fn guarded_here<T>(what: &str, f: impl FnOnce() -> Result<T, Error>) -> PyResult<T> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(e)) => Err(to_py(e)),
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown panic".into());
            Err(PyRuntimeError::new_err(format!("internal error in {what} (please report): {msg}")))
        }
    }
}

/// Read access to the rows of an (N, W) array with any strides (a slice when C-contiguous).
pub struct Rows<'a> {
    pub view: ArrayView2<'a, f64>,
    pub flat: Option<&'a [f64]>,
    pub name: &'static str,
}

impl<'a> Rows<'a> {
    /// Checks that `a` has shape (N, width) and that every element is finite.
    pub fn new(a: &'a PyReadonlyArray2<'_, f64>, name: &'static str, width: usize) -> PyResult<Self> {
        let r = Self::unchecked(a, name, width)?;
        r.check_finite()?;
        Ok(r)
    }

    /// Checks only the shape (N, width); the caller checks the elements, with
    /// [`Rows::check_finite`] or block by block (see [`all_finite`]) before reading them.
    pub fn unchecked(a: &'a PyReadonlyArray2<'_, f64>, name: &'static str, width: usize) -> PyResult<Self> {
        let view = a.as_array();
        if view.ncols() != width {
            return Err(PyValueError::new_err(format!(
                "{name}: expected shape (..., {width}), got (..., {})",
                view.ncols()
            )));
        }
        let flat = view.to_slice();
        Ok(Rows { view, flat, name })
    }

    /// The error naming the first element that is not finite.
    pub fn check_finite(&self) -> PyResult<()> {
        let (view, width) = (&self.view, self.view.ncols());
        let bad = match self.flat {
            Some(s) => s.iter().position(|v| !v.is_finite()),
            // A broadcast input (row stride 0) repeats its first row: check that row once, so
            // a huge broadcast is validated in O(width) and its output size is what bounds it.
            None if view.nrows() > 0 && view.strides()[0] == 0 => {
                view.row(0).iter().position(|v| !v.is_finite())
            }
            None => view.iter().position(|v| !v.is_finite()),
        };
        match bad {
            Some(k) => Err(to_py(Error::NonFinite { arg: self.name, index: k / width.max(1) })),
            None => Ok(()),
        }
    }

    pub fn len(&self) -> usize {
        self.view.nrows()
    }

    /// Interpolation parameters: |t| ≤ 1e12 (beyond, t·θ carries no bits of the angle and
    /// sin/cos of an overflowing product would be NaN).
    pub fn parameters(self) -> PyResult<Self> {
        self.check_parameters()?;
        Ok(self)
    }

    /// The check of [`Rows::parameters`] alone.
    pub fn check_parameters(&self) -> PyResult<()> {
        let v = &self.view;
        let first = if v.nrows() > 0 && v.strides()[0] == 0 {
            v.slice(numpy::ndarray::s![0..1, ..])
        } else {
            v.view()
        };
        if let Some(k) = first.iter().position(|v| v.abs() > 1e12) {
            return Err(PyValueError::new_err(format!(
                "{}: element {k} is beyond the supported range |t| ≤ 1e12",
                self.name
            )));
        }
        Ok(())
    }

    #[inline(always)]
    pub fn row<const W: usize>(&self, i: usize) -> [f64; W] {
        match self.flat {
            Some(s) => {
                let r = &s[i * W..i * W + W];
                std::array::from_fn(|k| r[k])
            }
            None => std::array::from_fn(|k| self.view[[i, k]]),
        }
    }

    /// Row `i` as a quaternion, as given.
    #[inline(always)]
    pub fn quat(&self, i: usize) -> Quat {
        Quat::from_wxyz(self.row::<4>(i))
    }

    /// Row `i` as a rotation: normalised, zero norm an error naming the row.
    #[inline(always)]
    pub fn rotation(&self, i: usize) -> Result<Quat, Error> {
        self.quat(i).try_normalize().map_err(|_| Error::ZeroNorm { arg: self.name, index: i })
    }

    #[inline(always)]
    pub fn scalar(&self, i: usize) -> f64 {
        self.row::<1>(i)[0]
    }
}

// ---- conversions: every binding file takes and returns its arrays through these ----------

/// A 1-D array as a vector.
pub fn vec_of(a: &PyReadonlyArray1<'_, f64>) -> Vec<f64> {
    a.as_array().iter().copied().collect()
}

/// An optional 1-D array (key times) as a vector.
pub fn times_of(t: &Option<PyReadonlyArray1<'_, f64>>) -> Option<Vec<f64>> {
    t.as_ref().map(vec_of)
}

/// Elements per parallel block of the key checks; shorter inputs are checked on this thread.
const KEY_BLOCK: usize = 1 << 16;

/// The index of the first element of `s` that is not finite (in parallel blocks for long
/// slices: the first block with one, then its first).
fn first_non_finite(s: &[f64]) -> Option<usize> {
    if s.len() < 2 * KEY_BLOCK {
        return if all_finite(s) { None } else { s.iter().position(|v| !v.is_finite()) };
    }
    let bad = s.par_chunks(KEY_BLOCK).map(|c| !all_finite(c)).collect::<Vec<bool>>();
    let b = bad.iter().position(|&x| x)?;
    let c = &s[b * KEY_BLOCK..((b + 1) * KEY_BLOCK).min(s.len())];
    c.iter().position(|v| !v.is_finite()).map(|k| b * KEY_BLOCK + k)
}

/// Spline keys (N, 4) as quaternions, as given: shape and finiteness checked with messages
/// naming `name` (as [`quats_of`]); a C-contiguous, aligned array is read in place (no copy —
/// the constructor makes the one copy it keeps), any other is copied once.
pub fn keys_in<'a>(q: &'a PyReadonlyArray2<'_, f64>, name: &'static str) -> PyResult<Cow<'a, [Quat]>> {
    const _: () = assert!(
        std::mem::size_of::<Quat>() == 4 * std::mem::size_of::<f64>()
            && std::mem::align_of::<Quat>() == std::mem::align_of::<f64>()
    );
    let rows = Rows::unchecked(q, name, 4)?;
    match rows.flat {
        Some(s) if s.as_ptr().cast::<Quat>().is_aligned() => {
            if let Some(k) = first_non_finite(s) {
                return Err(to_py(Error::NonFinite { arg: name, index: k / 4 }));
            }
            // SAFETY: `Quat` is `repr(C)` of four f64 (w, x, y, z), the size and alignment of
            // [f64; 4] (asserted above); the pointer is aligned and the slice holds len/4 of them.
            Ok(Cow::Borrowed(unsafe { std::slice::from_raw_parts(s.as_ptr().cast::<Quat>(), s.len() / 4) }))
        }
        _ => Ok(Cow::Owned(quats_of(q, name)?)),
    }
}

/// Optional key times, read in place when contiguous (the core checks them).
pub fn times_in<'a>(t: &'a Option<PyReadonlyArray1<'_, f64>>) -> Option<Cow<'a, [f64]>> {
    t.as_ref().map(|a| match a.as_slice() {
        Ok(s) => Cow::Borrowed(s),
        Err(_) => Cow::Owned(vec_of(a)),
    })
}

/// Rows (N, W), shape and finiteness checked with messages naming `name`.
pub fn rows_of<const W: usize>(a: &PyReadonlyArray2<'_, f64>, name: &'static str) -> PyResult<Vec<[f64; W]>> {
    let rows = Rows::new(a, name, W)?;
    Ok((0..rows.len()).map(|i| rows.row::<W>(i)).collect())
}

/// Rows (N, 4) as quaternions, as given (see [`rows_of`]).
pub fn quats_of(q: &PyReadonlyArray2<'_, f64>, name: &'static str) -> PyResult<Vec<Quat>> {
    Ok(rows_of::<4>(q, name)?.into_iter().map(Quat::from_wxyz).collect())
}

/// An (n, W) array from rows.
pub fn to_array<'py, const W: usize>(
    py: Python<'py>,
    rows: Vec<[f64; W]>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = rows.len();
    flat_array(py, rows.into_iter().flatten().collect(), n, W)
}

/// An (n, w) array from a flat row-major buffer (one move, no per-row allocation).
pub fn flat_array<'py>(
    py: Python<'py>,
    v: Vec<f64>,
    n: usize,
    w: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    PyArray1::from_vec(py, v).reshape([n, w]).map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// Checks that all row counts are equal (the Python layer broadcasts first).
pub fn same_len(parts: &[(&str, usize)]) -> PyResult<usize> {
    let n = parts[0].1;
    for (name, m) in parts {
        if *m != n {
            let all: Vec<String> = parts.iter().map(|(a, b)| format!("{a}: {b}")).collect();
            return Err(PyValueError::new_err(format!(
                "{name}: batch sizes differ ({}); they must broadcast",
                all.join(", ")
            )));
        }
    }
    Ok(n)
}

/// Whether every element of `s` is finite: a branch-free scan per 256 elements (it
/// vectorises), for block-wise checks of inputs that the kernel is about to read anyway (the
/// block is then in cache; a serial check before the parallel blocks costs a pass over memory).
#[inline]
pub fn all_finite(s: &[f64]) -> bool {
    s.chunks(256).all(|c| c.iter().fold(true, |ok, v| ok & v.is_finite()))
}

/// Whether every element of `s` is a valid interpolation parameter (finite, |t| ≤ 1e12; see
/// [`Rows::parameters`]), as [`all_finite`] scans.
#[inline]
pub fn all_parameters(s: &[f64]) -> bool {
    s.chunks(256).all(|c| c.iter().fold(true, |ok, v| ok & (v.abs() <= 1e12)))
}

/// Rows per parallel task; inputs smaller than two tasks run on the calling thread.
const CHUNK: usize = 8192;

/// Allocates an (n, W) output and fills row i with `f(i)`: GIL released, split across the
/// rayon pool for large inputs (`RAYON_NUM_THREADS` sets its size), panics guarded. On an
/// error the first failing row (by index) is reported, whatever thread met an error first.
pub fn fill<'py, const W: usize>(
    py: Python<'py>,
    what: &str,
    n: usize,
    f: impl Fn(usize) -> Result<[f64; W], Error> + Sync,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    // Every element is written below before the array is returned; on error it is dropped.
    let out = alloc2(py, n, W, what)?;
    {
        let mut rw = out.readwrite();
        let slice = rw.as_slice_mut().map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        guarded(py, what, || {
            let serial = |block: &mut [f64], first: usize| -> Result<(), Error> {
                for (j, row) in block.chunks_exact_mut(W).enumerate() {
                    row.copy_from_slice(&f(first + j)?);
                }
                Ok(())
            };
            if n < 2 * CHUNK {
                return serial(slice, 0);
            }
            let r = slice
                .par_chunks_mut(CHUNK * W)
                .enumerate()
                .try_for_each(|(c, block)| serial(block, c * CHUNK));
            if r.is_err() {
                // Deterministic message: find the first failing row.
                for i in 0..n {
                    f(i)?;
                }
            }
            r
        })?;
    }
    Ok(out)
}

/// `fill` on the calling thread only (the reference path for tests).
pub fn fill_serial<'py, const W: usize>(
    py: Python<'py>,
    what: &str,
    n: usize,
    f: impl Fn(usize) -> Result<[f64; W], Error> + Sync,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let out = alloc2(py, n, W, what)?;
    {
        let mut rw = out.readwrite();
        let slice = rw.as_slice_mut().map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        guarded(py, what, || {
            for (i, chunk) in slice.chunks_exact_mut(W).enumerate() {
                chunk.copy_from_slice(&f(i)?);
            }
            Ok(())
        })?;
    }
    Ok(out)
}

/// Allocates an (n, `width`) output and fills it block by block with `f(first_row, block)`
/// (a batch kernel over rows first_row..): GIL released, blocks of `CHUNK` rows across the
/// rayon pool for large inputs, panics guarded. On errors the one of the lowest block is
/// reported (each block reports its own first failing row), whatever thread finished first.
pub fn fill_blocks<'py>(
    py: Python<'py>,
    what: &str,
    n: usize,
    width: usize,
    f: impl Fn(usize, &mut [f64]) -> Result<(), Error> + Sync,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    // Every element is written below before the array is returned; on error it is dropped.
    let out = alloc2(py, n, width, what)?;
    {
        let mut rw = out.readwrite();
        let slice = rw.as_slice_mut().map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        guarded(py, what, || {
            if n < 2 * CHUNK {
                return f(0, slice);
            }
            let first_err = slice
                .par_chunks_mut(CHUNK * width)
                .enumerate()
                .filter_map(|(c, block)| f(c * CHUNK, block).err().map(|e| (c, e)))
                .min_by_key(|(c, _)| *c);
            match first_err {
                Some((_, e)) => Err(e),
                None => Ok(()),
            }
        })?;
    }
    Ok(out)
}
