"""The SIMD evaluation engine (issue 2.5): every batch kernel against the per-sample reference
path through the Python API, on every instruction set the CPU has (AVX-512, AVX2, scalar);
the forcing switch (function and environment variable); thread-count independence; the vector
sin/cos against mpmath.

Bound: |kernel − reference| ≤ TOL[k] · max(1, |quantity|, h⁻ᵏ, |ω|ᵏ) per component, for the
k-th derivative (the quantity is the quaternion or rate vector the component belongs to, h the
segment length): 1e-14 for q, q', ω; 5e-14 for q'', α; 2e-13 for q''', jerk. The last is
loose because the C³ "knot" spline's degree-7 weights cancel in their third derivative: the
AVX2 and scalar kernels agree to 6e-16 there while both differ from the jet path by up to
1.3e-13 (which of the two is closer to the exact value is not established).
"""

from __future__ import annotations

import os
import subprocess
import sys

import mpmath as mp
import numpy as np
import pytest
import quatspline as qs

from ..splinekit import random_times, random_walk

Q = random_walk(40, 7, step=0.9)
T = random_times(40, 7)
BATCH = {
    "slerp": lambda: qs.PiecewiseSlerp(Q, T),
    "bspline": lambda: qs.CumulativeBSpline(Q, dt=0.5, t0=T[0]),
    "bspline order 6": lambda: qs.CumulativeBSpline(Q, dt=0.3, t0=1.0, order=6),
    "beta": lambda: qs.BetaSpline(Q, beta1=1.3, beta2=0.4, times=T[:38]),
    "c3 knot": lambda: qs.C3Spline(Q, T),
    "c3 patent": lambda: qs.C3Spline(Q, T, alpha=0.2, beta=0.1, variant="patent"),
    "cumulative_bezier 8": lambda: qs.CumulativeBezier(Q[:8], domain=(T[0], T[-1])),
    "natural": lambda: qs.NaturalSpline(Q, T),  # closed-form derivatives and rates
    "natural large steps": lambda: qs.NaturalSpline(random_walk(30, 9, step=2.6), T[:30]),
}
TOL = {0: 1e-14, 1: 1e-14, 2: 5e-14, 3: 2e-13}  # by derivative order (see the module doc)


@pytest.fixture(autouse=True)
def _restore_mode():
    yield
    qs.set_simd("auto")


def cpu_has(isa):
    """Whether the engine runs `isa` ("avx512", "avx2", "scalar") on this CPU."""
    mode = qs.simd_status()[0]
    qs.set_simd(isa)
    ok = qs.simd_status()[1] == isa
    qs.set_simd(mode)
    return ok


# every mode that forces batch kernels; a mode the CPU lacks is skipped
MODES = ["auto", "avx512", "avx2", "scalar"]


def force(mode):
    """Sets `mode`, skipping the test where the CPU lacks its instruction set."""
    if mode in ("avx512", "avx2") and not cpu_has(mode):
        pytest.skip(f"no {mode} on this CPU")
    qs.set_simd(mode)
    if mode in ("avx512", "avx2"):
        assert qs.simd_status() == (mode, mode)


def worst(s, t, a, b, block, order):
    """max |a − b| / (TOL[k] · max(1, |quantity|, h⁻ᵏ, |ω|ᵏ)) (≤ 1 passes): h is the sample's
    segment length, ω its angular velocity — the k-th derivative is a sum of terms up to
    (|ω| + 1/h)ᵏ in size, and so is its rounding error."""
    if not len(t):
        return 0.0
    mode = qs.simd_status()[0]
    qs.set_simd("reference")
    w = np.linalg.norm(s.angular_velocity(t), axis=1)[:, None]
    qs.set_simd(mode)
    j = s.joints
    seg = np.clip(np.searchsorted(j, t, side="right") - 1, 0, len(j) - 2)
    h = (j[seg + 1] - j[seg])[:, None]
    a = a.reshape(len(t), -1, block)
    b = b.reshape(len(t), -1, block)
    k = np.arange(a.shape[1])[None, :] if block == 4 else np.full((1, 1), order)
    kf = k.astype(float)
    scale = np.maximum(np.maximum(1.0, np.linalg.norm(b, axis=2)), np.maximum(h**-kf, w**kf))
    tol = np.array([TOL[int(v)] for v in k.ravel()]).reshape(k.shape)
    return float(np.max(np.abs(a - b) / (scale * tol)[..., None]))


def sample_sets(s):
    a, b = s.domain
    j = s.joints
    rng = np.random.default_rng(3)
    mids = 0.5 * (j[:-1] + j[1:])
    sorted_t = np.sort(np.concatenate([np.linspace(a, b, 3001), j, mids, np.nextafter(mids, b)]))
    base = np.linspace(j[0] + 0.05 * (j[1] - j[0]), j[min(2, len(j) - 1)], 9)
    sets = {
        "sorted": sorted_t,
        "unsorted": rng.permutation(sorted_t),
        "joints_and_ends": np.concatenate([j, j[::-1]]),
    }
    for n in range(10):  # vector tails, runs crossing a joint mid-vector
        sets[f"len {n}"] = base[:n]
    return sets


def run_all(s):
    out = {}
    for kind, t in sample_sets(s).items():
        t = np.ascontiguousarray(t)
        for order in range(4):
            out[kind, "q", order] = (t, s.derivatives(t, order))
        for order, name in ((1, "angular_velocity"), (2, "angular_acceleration"), (3, "jerk")):
            for frame in ("world", "body"):
                out[kind, frame, order] = (t, getattr(s, name)(t, frame=frame))
    return out


@pytest.mark.parametrize("name", list(BATCH))
@pytest.mark.parametrize("mode", MODES)
def test_kernels_equal_reference(name, mode):
    s = BATCH[name]()
    qs.set_simd("reference")
    ref = run_all(s)
    force(mode)
    assert qs.simd_status()[0] == mode
    got = run_all(s)
    for key, (t, r) in ref.items():
        kind, what, order = key
        block = 4 if what == "q" else 3
        assert got[key][1].shape == r.shape, key
        e = worst(s, t, got[key][1], r, block, order)
        assert e <= 1.0, (key, e)


def test_kernel_actually_in_use():
    # the batch path and the reference path are different code: the rows differ in the last
    # bits somewhere, so this would fail if the engine silently used the reference
    s = BATCH["c3 knot"]()
    t = np.linspace(*s.domain, 5000)
    qs.set_simd("reference")
    ref = s(t)
    qs.set_simd("auto")
    assert qs.simd_status()[1] in ("avx512", "avx2", "scalar")
    if cpu_has("avx512"):
        # auto picks the widest instruction set
        assert qs.simd_status()[1] == "avx512"
    assert not np.array_equal(s(t), ref)
    assert np.max(np.abs(s(t) - ref)) <= 1e-14


@pytest.mark.parametrize("name", ["bspline", "c3 knot", "slerp", "natural"])
@pytest.mark.parametrize("mode", MODES)
def test_thread_count_independent_bits(name, mode):
    force(mode)
    s = BATCH[name]()
    rng = np.random.default_rng(4)
    t = rng.uniform(*s.domain, 60_000)  # unsorted, several parallel chunks
    ts = np.sort(t)
    results = []
    try:
        for n in (1, 2, 3):
            qs.set_num_threads(n)
            results.append((s(t), s(ts), s.angular_velocity(t), s.jerk(ts, frame="body")))
    finally:
        qs.set_num_threads(0)
    for r in results[1:]:
        for a, b in zip(results[0], r):
            np.testing.assert_array_equal(a, b)
    # sorted and unsorted give the same rows, bit for bit
    order = np.argsort(t)
    np.testing.assert_array_equal(results[0][0][order], results[0][1])


def test_clamp_and_errors_unchanged():
    s = qs.CumulativeBSpline(Q, dt=0.5, t0=0.0, extrapolate="clamp")
    a, b = s.domain
    t = np.linspace(a - 1, b + 1, 2000)
    qs.set_simd("reference")
    ref = s.derivatives(t, 2)
    qs.set_simd("auto")
    assert worst(s, np.clip(t, a, b), s.derivatives(t, 2), ref, 4, 0) <= 1.0
    r = qs.CumulativeBSpline(Q, dt=0.5, t0=0.0)
    t = np.linspace(a, b, 2000)
    t[1500] = np.nan
    with pytest.raises(ValueError, match="1500"):
        r(t)
    t[1500] = b
    t[1700] = b + 1.0
    with pytest.raises(ValueError, match="1700"):
        r.angular_velocity(t)


@pytest.mark.parametrize("value", ["off", "scalar", "reference", "avx2", "avx512"])
def test_environment_variable_forces_the_mode(value):
    code = (
        "import numpy as np, quatspline as qs\n"
        "q = qs.normalize(np.random.default_rng(0).normal(size=(20, 4)))\n"
        "s = qs.CumulativeBSpline(q)\n"
        "t = np.linspace(*s.domain, 1001)\n"
        "print(*qs.simd_status())\n"
        "a = s.derivatives(t, 3)\n"
        "qs.set_simd('reference')\n"
        "b = s.derivatives(t, 3)\n"
        "print(float(np.max(np.abs(a - b) / np.maximum(1, np.abs(b)))))\n"
    )
    if value in ("avx2", "avx512") and not cpu_has(value):
        pytest.skip(f"no {value} on this CPU")
    env = dict(os.environ, QUATSPLINE_SIMD=value)
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    status, err = r.stdout.splitlines()
    want = {
        "off": "scalar scalar",
        "scalar": "scalar scalar",
        "reference": "reference reference",
        "avx2": "avx2 avx2",
        "avx512": "avx512 avx512",
    }
    assert status == want[value]
    assert float(err) <= 1e-13


def test_set_simd_rejects_bad_modes():
    expected = "mode: expected 'auto', 'avx512', 'avx2', 'scalar' or 'reference'"
    with pytest.raises(ValueError, match=expected):
        qs.set_simd("fast")
    with pytest.raises(TypeError, match="mode: expected a str"):
        qs.set_simd(1)


def _ulps(got, x, fn):
    mp.mp.dps = 50
    ref = np.array([float(fn(mp.mpf(float(v)))) for v in x])
    scale = np.maximum(np.abs(ref), np.finfo(float).tiny)
    err = np.abs(got - ref) / (scale * np.finfo(float).eps)
    # near zeros of sin/cos, measure against the reduced argument's absolute error instead
    small = np.abs(ref) < 1e-3
    err[small] = np.abs(got - ref)[small] / np.finfo(float).eps
    return float(err.max())


@pytest.mark.parametrize("isa", ["scalar", "avx2", "avx512"])
def test_vector_sin_cos_within_two_ulp_of_mpmath(isa):
    if isa != "scalar" and not cpu_has(isa):
        pytest.skip(f"no {isa} on this CPU")
    rng = np.random.default_rng(5)
    x = np.concatenate(
        [
            rng.uniform(-np.pi, np.pi, 1500),  # angles of the kernels
            rng.uniform(-40, 40, 500),
            10 ** rng.uniform(-300, 0, 200) * rng.choice([-1, 1], 200),
            np.arange(1, 60) * np.pi / 2,  # quadrant boundaries
            np.nextafter(np.pi / 4, 4.0) * np.array([1, -1]),
            rng.uniform(-1e5, 1e5, 200),
            [823549.5, 823549.7, 1e7, 1e300],  # the libm fallback range
        ]
    )
    s, c = qs._core._simd_sin_cos(x, isa)
    assert _ulps(s, x, mp.sin) <= 2.0
    assert _ulps(c, x, mp.cos) <= 2.0
    s, c = qs._core._simd_sin_cos(np.array([np.nan, np.inf]), isa)
    assert np.isnan(s).all() and np.isnan(c).all()


def test_small_call_fast_paths_equal_the_general_path():
    s = BATCH["c3 knot"]()
    a, b = s.domain
    t = np.linspace(a, b, 7)
    general = s(t.reshape(7, 1))[:, 0]  # 2-D input: the general path
    np.testing.assert_array_equal(s(t), general)  # contiguous float64 vector
    for k, v in enumerate(t):
        np.testing.assert_array_equal(s(float(v)), general[k])  # one float
        assert s(float(v)).shape == (4,)
    with pytest.raises(ValueError, match="outside"):
        s(b + 1.0)
    with pytest.raises(ValueError, match="finite"):
        s(float("nan"))
    clamped = qs.C3Spline(Q, T, extrapolate="clamp")
    # held samples take the reference path: equal to the kernel's end value within the bound
    np.testing.assert_allclose(clamped(b + 5.0), clamped(np.array([b]))[0], rtol=0, atol=1e-15)
    # an in-domain row does not depend on out-of-domain neighbours
    tt = np.linspace(a, b, 300)
    tt2 = tt.copy()
    tt2[::7] = b + 1.0
    keep = np.ones(300, bool)
    keep[::7] = False
    np.testing.assert_array_equal(clamped(tt)[keep], clamped(tt2)[keep])


@pytest.mark.parametrize("m", [0, 1, 2, 5, 255, 256, 257])
def test_small_vector_path_any_layout(m):
    # the binding copies vectors of < 256 times without borrow tracking: strided, read-only,
    # other dtypes and the angular path must give the general path's rows and errors
    s = BATCH["c3 knot"]()
    a, b = s.domain
    base = np.linspace(a, b, 2 * m + 1)
    t = np.ascontiguousarray(base[1::2])
    general = s(t.reshape(m, 1)).reshape(m, 4)
    np.testing.assert_array_equal(s(t), general)
    np.testing.assert_array_equal(s(base[1::2]), general)  # strided view
    ro = t.copy()
    ro.flags.writeable = False
    np.testing.assert_array_equal(s(ro), general)
    np.testing.assert_array_equal(s(list(t)), general)
    np.testing.assert_array_equal(s(t.astype(np.float32)), s(t.astype(np.float32).astype(float)))
    w = s.angular_velocity(t.reshape(m, 1)).reshape(m, 3)
    np.testing.assert_array_equal(s.angular_velocity(t), w)
    np.testing.assert_array_equal(
        s.angular_velocity(base[1::2], frame="body"), s.angular_velocity(t, frame="body")
    )
    if m:
        bad = t.copy()
        bad[m - 1] = b + 1.0
        with pytest.raises(ValueError, match=f"index {m - 1}|{m - 1}"):
            s(bad)


# ---- slerp family (Squad, Catmull–Rom / Kochanek–Bartels, spherical Bézier) and pairs ----

QH = Q.copy()
QH[11] = QH[12] = QH[10]  # a hold
SLERP_FAMILY = {
    "squad": lambda: qs.Squad(Q, T),
    "squad closed holds": lambda: qs.Squad(QH, np.append(T, T[-1] + 0.8), ends="closed"),
    "squad rest": lambda: qs.Squad(Q, T, ends="rest"),
    "catmull_rom": lambda: qs.CatmullRom(Q, T),
    "catmull_rom duplicate": lambda: qs.CatmullRom(Q, T, ends="duplicate"),
    "catmull_rom centripetal closed": lambda: qs.CatmullRom(Q[:20], alpha=0.5, ends="closed"),
    "kochanek_bartels": lambda: qs.KochanekBartels(
        Q, T, tension=0.3, continuity=np.linspace(-0.4, 0.4, 40), bias=-0.2
    ),
    "bezier 8": lambda: qs.SphericalBezier(Q[:8], domain=(T[0], T[-1])),
    "bezier 16": lambda: qs.SphericalBezier(Q[:16], domain=(-1.0, 1.0)),
    # beyond 16 points the kernel's records live on the heap and its pyramid is taller
    "bezier 17": lambda: qs.SphericalBezier(Q[:17], domain=(-1.0, 1.0)),
    "bezier 33 small steps": lambda: qs.SphericalBezier(
        random_walk(33, 5, step=0.14), domain=(0.0, 2.0)
    ),
}


@pytest.mark.parametrize("name", list(SLERP_FAMILY))
@pytest.mark.parametrize("mode", MODES)
def test_slerp_family_kernels_equal_reference(name, mode):
    # values by the kernels; derivatives and rates by the batched jets (same rows as reference)
    s = SLERP_FAMILY[name]()
    qs.set_simd("reference")
    ref = run_all(s)
    force(mode)
    got = run_all(s)
    for key, (t, r) in ref.items():
        kind, what, order = key
        block = 4 if what == "q" else 3
        assert got[key][1].shape == r.shape, key
        assert worst(s, t, got[key][1], r, block, order) <= 1.0, key
    t = sample_sets(s)["sorted"]
    qs.set_simd("reference")
    r0 = s(t)
    force(mode)
    assert not np.array_equal(s(t), r0)  # the kernel, not the reference, ran


@pytest.mark.parametrize("name", ["squad", "catmull_rom", "bezier 8", "bezier 33 small steps"])
@pytest.mark.parametrize("mode", MODES)
def test_slerp_family_thread_count_independent_bits(name, mode):
    force(mode)
    s = SLERP_FAMILY[name]()
    t = np.random.default_rng(4).uniform(*s.domain, 60_000)
    try:
        results = []
        for n in (1, 2, 3):
            qs.set_num_threads(n)
            results.append(s(t))
    finally:
        qs.set_num_threads(0)
    for r in results[1:]:
        np.testing.assert_array_equal(results[0], r)
    order = np.argsort(t)
    np.testing.assert_array_equal(results[0][order], s(np.sort(t)))


# ---- arc-length splines: the times mapped first, then the original's kernel ----

ARC = {
    "slerp": lambda: qs.PiecewiseSlerp(Q, T),
    "squad": lambda: qs.Squad(Q, T),
    "catmull_rom": lambda: qs.CatmullRom(Q, T),
    "natural": lambda: qs.NaturalSpline(Q, T),
    "c3": lambda: qs.C3Spline(Q, T),
    "bspline": lambda: qs.CumulativeBSpline(Q, dt=0.5, t0=T[0]),
    "beta": lambda: qs.BetaSpline(Q, beta1=1.3, beta2=0.4, times=T[:38]),
    "bezier 8": lambda: qs.SphericalBezier(Q[:8], domain=(T[0], T[-1])),
}


@pytest.mark.parametrize("name", list(ARC))
@pytest.mark.parametrize("mode", MODES)
def test_arc_length_batch_equals_the_per_sample_path(name, mode):
    # values (and q') by the original's kernel at the mapped times, ω where the original has
    # closed-form rates; higher orders by the jets: every row within the kernels' bound
    s = qs.arc_length(ARC[name]())
    qs.set_simd("reference")
    ref = run_all(s)
    force(mode)
    got = run_all(s)
    for key, (t, r) in ref.items():
        kind, what, order = key
        block = 4 if what == "q" else 3
        assert got[key][1].shape == r.shape, key
        assert worst(s, t, got[key][1], r, block, order) <= 1.0, key
    t = sample_sets(s)["sorted"]
    qs.set_simd("reference")
    r0 = s(t)
    force(mode)
    assert not np.array_equal(s(t), r0)  # the batch path, not the reference, ran


@pytest.mark.parametrize("name", ["slerp", "natural", "bezier 8"])
@pytest.mark.parametrize("mode", MODES)
def test_arc_length_thread_count_independent_bits(name, mode):
    force(mode)
    s = qs.arc_length(ARC[name]())
    t = np.random.default_rng(5).uniform(*s.domain, 60_000)
    try:
        results = []
        for n in (1, 2, 3):
            qs.set_num_threads(n)
            results.append((s(t), s.angular_velocity(t)))
    finally:
        qs.set_num_threads(0)
    for r in results[1:]:
        for a, b in zip(results[0], r):
            np.testing.assert_array_equal(a, b)
    order = np.argsort(t)
    np.testing.assert_array_equal(results[0][0][order], s(np.sort(t)))


def _pairs(n, seed):
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(n, 4))
    b = rng.normal(size=(n, 4))
    b[::7] = a[::7]  # equal keys
    b[1::7] = -a[1::7]  # opposite signs
    t = rng.uniform(-0.2, 1.2, n)
    t[::11] = 0.0
    t[1::11] = 1.0
    return a, b, t


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("long_path", [False, True])
def test_slerp_pairs_equal_reference(mode, long_path):
    a, b, t = _pairs(40_003, 1)  # several parallel blocks and a tail
    qs.set_simd("reference")
    ref = qs.slerp(a, b, t, long_path=long_path)
    force(mode)
    got = qs.slerp(a, b, t, long_path=long_path)
    assert np.max(np.abs(got - ref)) <= 1e-14
    ends = (t == 0.0) | (t == 1.0)
    np.testing.assert_array_equal(got[ends], ref[ends])
    # broadcast (non-contiguous) inputs take the row-by-row path: same values
    contiguous = qs.slerp(np.repeat(a[:1], 50, 0), np.repeat(b[:1], 50, 0), t[:50], long_path)
    broadcast = qs.slerp(a[0], b[0], t[:50], long_path)
    np.testing.assert_allclose(broadcast, contiguous, rtol=0, atol=1e-14)


@pytest.mark.parametrize("threads", [1, 2])
def test_slerp_pairs_bad_input_errors_name_first(threads):
    # the contiguous path checks the inputs block by block in parallel tasks; the error raised
    # is still the serial checks' first one: q0 before q1 before t, then the range of t
    a, b, t = _pairs(40_003, 1)
    a1, b1, t1 = a.copy(), b.copy(), t.copy()
    a1[39_000, 2] = np.nan
    b1[3, 0] = np.inf
    t1[20_000] = 1e13
    qs.set_num_threads(threads)
    try:
        with pytest.raises(ValueError, match=r"^q0: .*element 39000$"):
            qs.slerp(a1, b1, t1)
        with pytest.raises(ValueError, match=r"^q1: .*element 3$"):
            qs.slerp(a, b1, t1)
        with pytest.raises(ValueError, match=r"^t: element 20000 is beyond"):
            qs.slerp(a, b, t1)
        t1[30_000] = np.nan
        with pytest.raises(ValueError, match=r"^t: non-finite .*element 30000$"):
            qs.slerp(a, b, t1)
    finally:
        qs.set_num_threads(0)


@pytest.mark.parametrize("threads", [1, 2])
def test_sclerp_pairs_bad_input_errors_name_first(threads):
    # as for slerp: block-wise checks in the parallel tasks, the serial checks' first error
    rng = np.random.default_rng(4)
    n = 30_001
    a = qs.dq_from_pose(qs.normalize(rng.normal(size=(n, 4))), rng.normal(size=(n, 3)))
    b = qs.dq_from_pose(qs.normalize(rng.normal(size=(n, 4))), rng.normal(size=(n, 3)))
    t = rng.uniform(0, 1, n)
    a1, b1, t1 = a.copy(), b.copy(), t.copy()
    a1[29_000, 6] = np.nan
    b1[5, 1] = -np.inf
    t1[20_000] = -1e13
    qs.set_num_threads(threads)
    try:
        with pytest.raises(ValueError, match=r"^dq0: .*element 29000$"):
            qs.sclerp(a1, b1, t1)
        with pytest.raises(ValueError, match=r"^dq1: .*element 5$"):
            qs.sclerp(a, b1, t1)
        with pytest.raises(ValueError, match=r"^t: element 20000 is beyond"):
            qs.sclerp(a, b, t1)
    finally:
        qs.set_num_threads(0)


@pytest.mark.parametrize("mode", MODES)
def test_sclerp_pairs_equal_reference(mode):
    rng = np.random.default_rng(2)
    n = 30_001
    a = qs.dq_from_pose(qs.normalize(rng.normal(size=(n, 4))), rng.normal(size=(n, 3)))
    b = qs.dq_from_pose(qs.normalize(rng.normal(size=(n, 4))), rng.normal(size=(n, 3)))
    b[::5, :4] = a[::5, :4]  # pure translations
    t = rng.uniform(-0.2, 1.2, n)
    qs.set_simd("reference")
    ref = qs.sclerp(a, b, t)
    force(mode)
    got = qs.sclerp(a, b, t)
    scale = np.maximum(1.0, np.linalg.norm(ref, axis=1))[:, None]
    assert np.max(np.abs(got - ref) / scale) <= 1e-14


def test_pairs_thread_count_independent_and_errors():
    a, b, t = _pairs(50_001, 3)
    da = qs.dq_from_pose(qs.normalize(a), b[:, :3])
    db = qs.dq_from_pose(qs.normalize(b), a[:, 1:])
    try:
        results = []
        for n in (1, 2, 3):
            qs.set_num_threads(n)
            results.append((qs.slerp(a, b, t), qs.sclerp(da, db, t)))
    finally:
        qs.set_num_threads(0)
    for r in results[1:]:
        for x, y in zip(results[0], r):
            np.testing.assert_array_equal(x, y)
    a[30_000] = 0.0
    a[45_000] = 0.0
    with pytest.raises(ValueError, match="q0: quaternion 30000 has zero"):
        qs.slerp(a, b, t)
    db[40_000, :4] = 0.0
    db[20_000, :4] = 0.0
    with pytest.raises(ValueError, match="dq1: quaternion 20000 has zero"):
        qs.sclerp(da, db, t)
