//! Bindings of the algebra, conversions and two-keyframe interpolation (flat batches).

use crate::arrays::Count;
use crate::arrays::{all_finite, all_parameters, fill, fill_blocks, same_len, to_py, Rows};
use numpy::{PyArray2, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use quatspline::convert::{self, EulerSeq};
use quatspline::simd::Isa;
use quatspline::{interp, special, DualQuat, Error, Quat};

type Arr<'py> = PyReadonlyArray2<'py, f64>;
type Out<'py> = PyResult<Bound<'py, PyArray2<f64>>>;

fn unit_dq(rows: &Rows, i: usize) -> Result<DualQuat, Error> {
    DualQuat::from_array(rows.row::<8>(i))
        .try_normalize()
        .map_err(|_| Error::ZeroNorm { arg: rows.name, index: i })
}

#[pyfunction]
fn normalize<'py>(py: Python<'py>, q: Arr<'py>) -> Out<'py> {
    let q = Rows::new(&q, "q", 4)?;
    fill(py, "normalize", q.len(), |i| Ok(q.rotation(i)?.to_wxyz()))
}

#[pyfunction]
fn multiply<'py>(py: Python<'py>, p: Arr<'py>, q: Arr<'py>) -> Out<'py> {
    let (p, q) = (Rows::new(&p, "p", 4)?, Rows::new(&q, "q", 4)?);
    let n = same_len(&[("p", p.len()), ("q", q.len())])?;
    fill(py, "multiply", n, |i| Ok((p.quat(i) * q.quat(i)).to_wxyz()))
}

#[pyfunction]
fn conjugate<'py>(py: Python<'py>, q: Arr<'py>) -> Out<'py> {
    let q = Rows::new(&q, "q", 4)?;
    fill(py, "conjugate", q.len(), |i| Ok(q.quat(i).conj().to_wxyz()))
}

#[pyfunction]
fn inverse<'py>(py: Python<'py>, q: Arr<'py>) -> Out<'py> {
    let q = Rows::new(&q, "q", 4)?;
    fill(py, "inverse", q.len(), |i| {
        q.quat(i).try_inverse().map(Quat::to_wxyz).map_err(|_| Error::ZeroNorm { arg: "q", index: i })
    })
}

#[pyfunction]
fn exp<'py>(py: Python<'py>, q: Arr<'py>) -> Out<'py> {
    let q = Rows::new(&q, "q", 4)?;
    fill(py, "exp", q.len(), |i| Ok(q.quat(i).exp().to_wxyz()))
}

#[pyfunction]
fn log<'py>(py: Python<'py>, q: Arr<'py>) -> Out<'py> {
    let q = Rows::new(&q, "q", 4)?;
    fill(py, "log", q.len(), |i| {
        let x = q.quat(i);
        if x.w.abs().max(x.x.abs()).max(x.y.abs()).max(x.z.abs()) < f64::MIN_POSITIVE {
            return Err(Error::ZeroNorm { arg: "q", index: i });
        }
        Ok(x.log().to_wxyz())
    })
}

#[pyfunction]
fn power<'py>(py: Python<'py>, q: Arr<'py>, t: Arr<'py>) -> Out<'py> {
    let (q, t) = (Rows::new(&q, "q", 4)?, Rows::new(&t, "t", 1)?.parameters()?);
    let n = same_len(&[("q", q.len()), ("t", t.len())])?;
    fill(py, "power", n, |i| Ok(q.rotation(i)?.powf(t.scalar(i)).to_wxyz()))
}

#[pyfunction]
fn rotate<'py>(py: Python<'py>, q: Arr<'py>, v: Arr<'py>) -> Out<'py> {
    let (q, v) = (Rows::new(&q, "q", 4)?, Rows::new(&v, "vectors", 3)?);
    let n = same_len(&[("q", q.len()), ("vectors", v.len())])?;
    fill(py, "rotate", n, |i| Ok(q.rotation(i)?.rotate(v.row::<3>(i))))
}

#[pyfunction]
fn as_matrix<'py>(py: Python<'py>, q: Arr<'py>) -> Out<'py> {
    let q = Rows::new(&q, "q", 4)?;
    fill(py, "as_matrix", q.len(), |i| {
        let m = convert::to_matrix(q.rotation(i)?);
        Ok(std::array::from_fn::<f64, 9, _>(|k| m[k / 3][k % 3]))
    })
}

#[pyfunction]
fn from_matrix<'py>(py: Python<'py>, m: Arr<'py>) -> Out<'py> {
    let m = Rows::new(&m, "matrix", 9)?;
    fill(py, "from_matrix", m.len(), |i| {
        let r = m.row::<9>(i);
        let mat: convert::Mat3 = std::array::from_fn(|a| std::array::from_fn(|b| r[3 * a + b]));
        convert::try_from_matrix(&mat).map(Quat::to_wxyz).map_err(|e| match e {
            Error::Invalid { message, .. } => Error::invalid("matrix", format!("matrix {i}: {message}")),
            other => other,
        })
    })
}

#[pyfunction]
fn as_rotvec<'py>(py: Python<'py>, q: Arr<'py>) -> Out<'py> {
    let q = Rows::new(&q, "q", 4)?;
    fill(py, "as_rotvec", q.len(), |i| Ok(convert::to_rotvec(q.rotation(i)?)))
}

#[pyfunction]
fn from_rotvec<'py>(py: Python<'py>, r: Arr<'py>) -> Out<'py> {
    let r = Rows::new(&r, "rotvec", 3)?;
    fill(py, "from_rotvec", r.len(), |i| Ok(convert::from_rotvec(r.row::<3>(i)).to_wxyz()))
}

#[pyfunction]
fn from_axis_angle<'py>(py: Python<'py>, axis: Arr<'py>, angle: Arr<'py>) -> Out<'py> {
    let (a, g) = (Rows::new(&axis, "axis", 3)?, Rows::new(&angle, "angle", 1)?);
    let n = same_len(&[("axis", a.len()), ("angle", g.len())])?;
    fill(py, "from_axis_angle", n, |i| {
        convert::try_from_axis_angle(a.row::<3>(i), g.scalar(i))
            .map(Quat::to_wxyz)
            .map_err(|_| Error::invalid("axis", format!("axis {i} is zero")))
    })
}

/// `seq` of 1, 2 or 3 axes (as scipy); `angles` (N, len(seq)).
#[pyfunction]
fn from_euler<'py>(py: Python<'py>, seq: &str, angles: Arr<'py>) -> Out<'py> {
    let (axes, extrinsic) = convert::parse_rotation_sequence(seq).map_err(to_py)?;
    let a = Rows::new(&angles, "angles", axes.len())?;
    fill(py, "from_euler", a.len(), |i| {
        let mut g = [0.0; 3];
        for (k, v) in g.iter_mut().enumerate().take(axes.len()) {
            *v = a.view[[i, k]];
        }
        Ok(convert::from_rotation_sequence(&axes, extrinsic, &g[..axes.len()]).to_wxyz())
    })
}

#[pyfunction]
fn as_euler<'py>(py: Python<'py>, q: Arr<'py>, seq: &str) -> Out<'py> {
    let s = seq.parse::<EulerSeq>().map_err(to_py)?;
    let q = Rows::new(&q, "q", 4)?;
    fill(py, "as_euler", q.len(), |i| Ok(convert::to_euler(s, q.rotation(i)?).0))
}

#[pyfunction]
fn lerp<'py>(py: Python<'py>, q0: Arr<'py>, q1: Arr<'py>, t: Arr<'py>) -> Out<'py> {
    let (a, b, t) =
        (Rows::new(&q0, "q0", 4)?, Rows::new(&q1, "q1", 4)?, Rows::new(&t, "t", 1)?.parameters()?);
    let n = same_len(&[("q0", a.len()), ("q1", b.len()), ("t", t.len())])?;
    fill(py, "lerp", n, |i| Ok(interp::lerp(a.quat(i), b.quat(i), t.scalar(i)).to_wxyz()))
}

#[pyfunction]
fn nlerp<'py>(py: Python<'py>, q0: Arr<'py>, q1: Arr<'py>, t: Arr<'py>, long_path: bool) -> Out<'py> {
    let (a, b, t) =
        (Rows::new(&q0, "q0", 4)?, Rows::new(&q1, "q1", 4)?, Rows::new(&t, "t", 1)?.parameters()?);
    let n = same_len(&[("q0", a.len()), ("q1", b.len()), ("t", t.len())])?;
    fill(py, "nlerp", n, |i| {
        interp::try_nlerp(a.rotation(i)?, b.rotation(i)?, t.scalar(i), long_path).map(Quat::to_wxyz).map_err(
            |_| Error::invalid("t", format!("nlerp of antipodal keys passes through zero at row {i}")),
        )
    })
}

/// The shared path of the pairs functions (`slerp`, `sclerp`): rows `a`, `b` of `width`
/// numbers and parameters `t`, checked in the order (and with the messages) of `Rows::new` and
/// `parameters`. Contiguous rows go to the SIMD engine's pairs `kernel` (AVX2 where the CPU has
/// it) in parallel blocks that check their own inputs, where the kernel then finds them in
/// cache (a serial pass before them took ~40% of the time on 2 threads); any error re-runs the
/// serial checks first, so the error raised is the one they name. Other layouts: the serial
/// checks, then `serial(n)` row by row.
fn pairs<'py>(
    py: Python<'py>,
    what: &str,
    (a, b, t): (&Rows, &Rows, &Rows),
    width: usize,
    kernel: impl Fn(Isa, &[f64], &[f64], &[f64], &mut [f64]) -> Result<(), Error> + Sync,
    serial: impl FnOnce(usize) -> Out<'py>,
) -> Out<'py> {
    let validate = || -> PyResult<()> {
        a.check_finite()?;
        b.check_finite()?;
        t.check_finite()?;
        t.check_parameters()
    };
    let n = match same_len(&[(a.name, a.len()), (b.name, b.len()), (t.name, t.len())]) {
        Ok(n) => n,
        Err(e) => return validate().and(Err(e)),
    };
    if let (Some(fa), Some(fb), Some(ft), Some(isa)) = (a.flat, b.flat, t.flat, quatspline::simd::isa()) {
        let out = fill_blocks(py, what, n, width, |first, block| {
            let r = first..first + block.len() / width;
            let (ra, rb) = (&fa[width * r.start..width * r.end], &fb[width * r.start..width * r.end]);
            if !(all_finite(ra) && all_finite(rb) && all_parameters(&ft[r.clone()])) {
                return Err(Error::invalid(a.name, "non-finite input (re-checked serially)"));
            }
            kernel(isa, ra, rb, &ft[r], block).map_err(|e| match e {
                Error::ZeroNorm { arg, index } => Error::ZeroNorm { arg, index: first + index },
                e => e,
            })
        });
        return out.or_else(|e| validate().and(Err(e)));
    }
    validate()?;
    serial(n)
}

#[pyfunction]
fn slerp<'py>(py: Python<'py>, q0: Arr<'py>, q1: Arr<'py>, t: Arr<'py>, long_path: bool) -> Out<'py> {
    let (a, b, t) =
        (Rows::unchecked(&q0, "q0", 4)?, Rows::unchecked(&q1, "q1", 4)?, Rows::unchecked(&t, "t", 1)?);
    pairs(
        py,
        "slerp",
        (&a, &b, &t),
        4,
        |isa, q0, q1, tt, block| quatspline::simd::pairs::slerp_pairs(isa, q0, q1, tt, long_path, block),
        |n| {
            fill(py, "slerp", n, |i| {
                Ok(interp::slerp(a.rotation(i)?, b.rotation(i)?, t.scalar(i), long_path).to_wxyz())
            })
        },
    )
}

#[pyfunction]
fn lin_euler<'py>(py: Python<'py>, q0: Arr<'py>, q1: Arr<'py>, t: Arr<'py>, seq: &str) -> Out<'py> {
    let s = seq.parse::<EulerSeq>().map_err(to_py)?;
    let (a, b, t) =
        (Rows::new(&q0, "q0", 4)?, Rows::new(&q1, "q1", 4)?, Rows::new(&t, "t", 1)?.parameters()?);
    let n = same_len(&[("q0", a.len()), ("q1", b.len()), ("t", t.len())])?;
    fill(py, "lin_euler", n, |i| {
        Ok(interp::lin_euler(s, a.rotation(i)?, b.rotation(i)?, t.scalar(i)).to_wxyz())
    })
}

#[pyfunction]
fn lin_mat<'py>(py: Python<'py>, q0: Arr<'py>, q1: Arr<'py>, t: Arr<'py>) -> Out<'py> {
    let (a, b, t) =
        (Rows::new(&q0, "q0", 4)?, Rows::new(&q1, "q1", 4)?, Rows::new(&t, "t", 1)?.parameters()?);
    let n = same_len(&[("q0", a.len()), ("q1", b.len()), ("t", t.len())])?;
    fill(py, "lin_mat", n, |i| Ok(interp::lin_mat(a.rotation(i)?, b.rotation(i)?, t.scalar(i)).to_wxyz()))
}

#[pyfunction]
fn dq_from_pose<'py>(py: Python<'py>, q: Arr<'py>, t: Arr<'py>) -> Out<'py> {
    let (q, t) = (Rows::new(&q, "q", 4)?, Rows::new(&t, "t", 3)?);
    let n = same_len(&[("q", q.len()), ("t", t.len())])?;
    fill(py, "dq_from_pose", n, |i| {
        Ok(DualQuat::from_rotation_translation(q.rotation(i)?, t.row::<3>(i)).to_array())
    })
}

/// Returns (N, 7): rotation (w, x, y, z) then translation; the Python layer splits it.
#[pyfunction]
fn dq_to_pose<'py>(py: Python<'py>, dq: Arr<'py>) -> Out<'py> {
    let d = Rows::new(&dq, "dq", 8)?;
    fill(py, "dq_to_pose", d.len(), |i| {
        let (r, t) = unit_dq(&d, i)?.to_rotation_translation();
        Ok([r.w, r.x, r.y, r.z, t[0], t[1], t[2]])
    })
}

#[pyfunction]
fn dq_normalize<'py>(py: Python<'py>, dq: Arr<'py>) -> Out<'py> {
    let d = Rows::new(&dq, "dq", 8)?;
    fill(py, "dq_normalize", d.len(), |i| Ok(unit_dq(&d, i)?.to_array()))
}

#[pyfunction]
fn dq_multiply<'py>(py: Python<'py>, a: Arr<'py>, b: Arr<'py>) -> Out<'py> {
    let (a, b) = (Rows::new(&a, "a", 8)?, Rows::new(&b, "b", 8)?);
    let n = same_len(&[("a", a.len()), ("b", b.len())])?;
    fill(py, "dq_multiply", n, |i| {
        Ok((DualQuat::from_array(a.row::<8>(i)) * DualQuat::from_array(b.row::<8>(i))).to_array())
    })
}

/// kind: 0 quaternion conjugate, 1 dual conjugate, 2 both.
#[pyfunction]
fn dq_conjugate<'py>(py: Python<'py>, dq: Arr<'py>, kind: u8) -> Out<'py> {
    let d = Rows::new(&dq, "dq", 8)?;
    if kind > 2 {
        return Err(PyValueError::new_err("kind: expected 0, 1 or 2"));
    }
    fill(py, "dq_conjugate", d.len(), |i| {
        let x = DualQuat::from_array(d.row::<8>(i));
        Ok(match kind {
            0 => x.conj(),
            1 => x.dual_conj(),
            _ => x.full_conj(),
        }
        .to_array())
    })
}

#[pyfunction]
fn dq_transform_point<'py>(py: Python<'py>, dq: Arr<'py>, p: Arr<'py>) -> Out<'py> {
    let (d, p) = (Rows::new(&dq, "dq", 8)?, Rows::new(&p, "points", 3)?);
    let n = same_len(&[("dq", d.len()), ("points", p.len())])?;
    fill(py, "dq_transform_point", n, |i| Ok(unit_dq(&d, i)?.transform_point(p.row::<3>(i))))
}

/// Returns (N, 8): axis (3), angle, displacement, moment (3).
#[pyfunction]
fn dq_screw<'py>(py: Python<'py>, dq: Arr<'py>) -> Out<'py> {
    let d = Rows::new(&dq, "dq", 8)?;
    fill(py, "dq_screw", d.len(), |i| {
        let s = unit_dq(&d, i)?.screw();
        Ok([s.axis[0], s.axis[1], s.axis[2], s.angle, s.displacement, s.moment[0], s.moment[1], s.moment[2]])
    })
}

/// Shortest screw unless `long_path`: q̂ and −q̂ (the same pose) give the same power.
#[pyfunction]
#[pyo3(signature = (dq, t, long_path=false))]
fn dq_power<'py>(py: Python<'py>, dq: Arr<'py>, t: Arr<'py>, long_path: bool) -> Out<'py> {
    let (d, t) = (Rows::new(&dq, "dq", 8)?, Rows::new(&t, "t", 1)?.parameters()?);
    let n = same_len(&[("dq", d.len()), ("t", t.len())])?;
    fill(py, "dq_power", n, |i| {
        let q = unit_dq(&d, i)?;
        let q = if !long_path && q.r.w < 0.0 { q.scale(-1.0) } else { q };
        Ok(q.powf(t.scalar(i)).to_array())
    })
}

#[pyfunction]
fn sclerp<'py>(py: Python<'py>, dq0: Arr<'py>, dq1: Arr<'py>, t: Arr<'py>) -> Out<'py> {
    let (a, b, t) =
        (Rows::unchecked(&dq0, "dq0", 8)?, Rows::unchecked(&dq1, "dq1", 8)?, Rows::unchecked(&t, "t", 1)?);
    pairs(py, "sclerp", (&a, &b, &t), 8, quatspline::simd::pairs::sclerp_pairs, |n| {
        fill(
            py,
            "sclerp",
            n,
            |i| Ok(interp::sclerp(unit_dq(&a, i)?, unit_dq(&b, i)?, t.scalar(i)).to_array()),
        )
    })
}

/// dqs: (N, 8K) rows of K poses; weights: (N, K).
#[pyfunction]
fn dlb<'py>(py: Python<'py>, dqs: Arr<'py>, weights: Arr<'py>, k: Count) -> Out<'py> {
    let k = k.0;
    let d = Rows::new(&dqs, "dqs", 8 * k)?;
    let w = Rows::new(&weights, "weights", k)?;
    let n = same_len(&[("dqs", d.len()), ("weights", w.len())])?;
    fill(py, "dlb", n, |i| {
        let poses: Vec<DualQuat> = (0..k)
            .map(|j| {
                let a: [f64; 8] = std::array::from_fn(|c| d.view[[i, 8 * j + c]]);
                DualQuat::from_array(a)
                    .try_normalize()
                    .map_err(|_| Error::ZeroNorm { arg: "dqs", index: i * k + j })
            })
            .collect::<Result<_, _>>()?;
        let ws: Vec<f64> = (0..k).map(|j| w.view[[i, j]]).collect();
        interp::try_dlb(&poses, &ws).map(DualQuat::to_array).map_err(|_| {
            Error::invalid("weights", format!("row {i}: the weighted sum has zero rotation part"))
        })
    })
}

/// Test hook: evaluates a named singular-ratio helper of `quatspline::special`.
#[pyfunction]
fn special_fn<'py>(py: Python<'py>, name: &str, x: Arr<'py>) -> Out<'py> {
    let f = special::by_name(name)
        .ok_or_else(|| PyValueError::new_err(format!("name: unknown helper {name:?}")))?;
    let x = Rows::new(&x, "x", 2)?;
    fill(py, "special", x.len(), |i| {
        let [a, b] = x.row::<2>(i);
        Ok([f(a, b)])
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(normalize, m)?)?;
    m.add_function(wrap_pyfunction!(multiply, m)?)?;
    m.add_function(wrap_pyfunction!(conjugate, m)?)?;
    m.add_function(wrap_pyfunction!(inverse, m)?)?;
    m.add_function(wrap_pyfunction!(exp, m)?)?;
    m.add_function(wrap_pyfunction!(log, m)?)?;
    m.add_function(wrap_pyfunction!(power, m)?)?;
    m.add_function(wrap_pyfunction!(rotate, m)?)?;
    m.add_function(wrap_pyfunction!(as_matrix, m)?)?;
    m.add_function(wrap_pyfunction!(from_matrix, m)?)?;
    m.add_function(wrap_pyfunction!(as_rotvec, m)?)?;
    m.add_function(wrap_pyfunction!(from_rotvec, m)?)?;
    m.add_function(wrap_pyfunction!(from_axis_angle, m)?)?;
    m.add_function(wrap_pyfunction!(from_euler, m)?)?;
    m.add_function(wrap_pyfunction!(as_euler, m)?)?;
    m.add_function(wrap_pyfunction!(lerp, m)?)?;
    m.add_function(wrap_pyfunction!(nlerp, m)?)?;
    m.add_function(wrap_pyfunction!(slerp, m)?)?;
    m.add_function(wrap_pyfunction!(lin_euler, m)?)?;
    m.add_function(wrap_pyfunction!(lin_mat, m)?)?;
    m.add_function(wrap_pyfunction!(dq_from_pose, m)?)?;
    m.add_function(wrap_pyfunction!(dq_to_pose, m)?)?;
    m.add_function(wrap_pyfunction!(dq_normalize, m)?)?;
    m.add_function(wrap_pyfunction!(dq_multiply, m)?)?;
    m.add_function(wrap_pyfunction!(dq_conjugate, m)?)?;
    m.add_function(wrap_pyfunction!(dq_transform_point, m)?)?;
    m.add_function(wrap_pyfunction!(dq_screw, m)?)?;
    m.add_function(wrap_pyfunction!(dq_power, m)?)?;
    m.add_function(wrap_pyfunction!(sclerp, m)?)?;
    m.add_function(wrap_pyfunction!(dlb, m)?)?;
    m.add_function(wrap_pyfunction!(special_fn, m)?)?;
    Ok(())
}
