"""Regression tests for issue 2.1's numerics and API items (each failed on main before its fix).

Item numbers refer to issue 2.1 (docs/robustness.md has one row per input).
"""

from __future__ import annotations

import itertools
import re
import warnings

import numpy as np
import pytest
import quatspline as qs
from quatspline.ops import design
from scipy.spatial.transform import Rotation

SEQS = [
    "".join(p)
    for axes in ("xyz", "XYZ")
    for p in itertools.product(axes, repeat=3)
    if p[0] != p[1] and p[1] != p[2]
]


def test_all_24_sequences_listed():
    assert len(SEQS) == 24


# ---- item 2: slerp(q, -q, t, long_path=True) -------------------------------------------------
@pytest.mark.parametrize(
    "q",
    [
        np.array([0, 0, 1, 1]) / np.sqrt(2),  # the example: norm 0 at t = 0.75 on main
        np.array([1.0, 0, 0, 0]),
        np.array([0.5, 0.5, 0.5, 0.5]),
        np.array([0.1, -0.7, 0.3, 0.2]) / np.linalg.norm([0.1, -0.7, 0.3, 0.2]),
    ],
)
def test_slerp_long_path_to_minus_q_is_a_unit_full_turn_about_body_x(q):
    t = np.linspace(-0.5, 1.5, 81)
    m = qs.slerp(q, -q, t, long_path=True)
    np.testing.assert_allclose(np.linalg.norm(m, axis=-1), 1.0, atol=1e-15)
    # The documented axis: q ⊗ (cos πt, sin πt, 0, 0), a 2πt turn about the body x axis.
    want = qs.multiply(q, np.stack([np.cos(np.pi * t), np.sin(np.pi * t), 0 * t, 0 * t], -1))
    np.testing.assert_allclose(m, want, atol=1e-15)
    # The rotation angle is 2πt (mod 2π) — a full turn over [0, 1].
    ang = Rotation.from_quat(qs.as_xyzw(m)).inv() * Rotation.from_quat(qs.as_xyzw(q))
    wrapped = np.abs((2 * np.pi * t + np.pi) % (2 * np.pi) - np.pi)
    np.testing.assert_allclose(ang.magnitude(), wrapped, atol=1e-7)


def test_slerp_long_path_nearly_opposite_keys_stay_unit():
    rng = np.random.default_rng(2)
    q = rng.normal(size=(500, 4))
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    for eps in (1e-15, 1e-12, 1e-9, 1e-6):
        q1 = -q + eps * rng.normal(size=q.shape)
        m = qs.slerp(q, q1, rng.uniform(0, 1, 500), long_path=True)
        np.testing.assert_allclose(np.linalg.norm(m, axis=-1), 1.0, atol=1e-14)


# ---- item 3: as_euler ranges exactly scipy's -------------------------------------------------
def _hard_rotations():
    rng = np.random.default_rng(3)
    out = [rng.normal(size=(300, 4))]
    grid = np.deg2rad(np.arange(-180, 181, 45.0))
    angles = np.array(list(itertools.product(grid, grid, grid)))
    for seq in SEQS:  # gimbal lock (middle 0 / ±90 / 180) and exactly 180° for every sequence
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            out.append(Rotation.from_euler(seq, angles).as_quat(scalar_first=True))
    half_turns = np.array(
        [[0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [0, 1, 1, 0], [0, 1, 0, 1], [0, 0, 1, 1]],
        dtype=float,
    )
    out.append(half_turns)
    out.append(-half_turns)
    q = np.concatenate(out)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


@pytest.mark.parametrize("seq", SEQS)
def test_as_euler_matches_scipy_ranges_exactly_incl_gimbal_lock_and_180(seq):
    q = _hard_rotations()
    ours = qs.as_euler(q, seq)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = Rotation.from_quat(qs.as_xyzw(q)).as_euler(seq)
    # Same ranges: no 2π jumps allowed (on main a middle angle of π came out as −π).
    np.testing.assert_allclose(ours, ref, rtol=0, atol=1e-9)
    assert np.all(np.abs(ours) <= np.pi)
    mid = ours[:, 1]
    if seq[0].lower() == seq[2].lower():
        assert np.all((mid >= 0) & (mid <= np.pi))
    else:
        assert np.all(np.abs(mid) <= np.pi / 2 + 1e-15)


# ---- item 7: from_euler 1- and 2-axis sequences; dq_power sign invariance ---------------------
@pytest.mark.parametrize("seq", ["x", "Y", "z", "zx", "XY", "yz", "ZX", "xyz", "ZYZ"])
def test_from_euler_accepts_one_and_two_axis_sequences_like_scipy(seq):
    rng = np.random.default_rng(7)
    a = rng.uniform(-4, 4, size=(20, len(seq)))
    ref = Rotation.from_euler(seq, a).as_quat(scalar_first=True)
    ours = qs.from_euler(seq, a)
    np.testing.assert_allclose(np.abs(np.sum(ours * ref, axis=-1)), 1.0, atol=1e-14)
    if len(seq) == 1:  # a scalar or a flat array of angles, like scipy
        np.testing.assert_allclose(np.abs(qs.from_euler(seq, a[:, 0]) @ ref.T).diagonal(), 1.0)
        assert qs.from_euler(seq, 0.3).shape == (4,)


@pytest.mark.parametrize("seq", ["", "xx", "xY", "xyzx", "w", "XYY"])
def test_from_euler_bad_sequences_name_seq(seq):
    with pytest.raises(ValueError, match="seq: unknown rotation sequence"):
        qs.from_euler(seq, np.zeros(max(len(seq), 1)))


def test_from_euler_wrong_width_names_angles():
    with pytest.raises(ValueError, match=r"angles: expected shape \(\.\.\., 2\)"):
        qs.from_euler("zx", [1.0, 2.0, 3.0])


def test_dq_power_is_sign_invariant_with_long_path_opt_out():
    rng = np.random.default_rng(8)
    q = rng.normal(size=(200, 4))
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    d = qs.dq_from_pose(q, rng.normal(size=(200, 3)))
    t = rng.uniform(-2, 2, size=200)
    a, b = qs.dq_power(d, t), qs.dq_power(-d, t)
    same = np.minimum(np.abs(a - b).max(-1), np.abs(a + b).max(-1))
    assert same.max() < 1e-12
    # The shortest screw: the rotation part of q̂^½ turns by half the (≤ π) angle.
    ra = qs.dq_to_pose(qs.dq_power(d, 0.5))[0]
    full = Rotation.from_quat(qs.as_xyzw(q)).magnitude()
    half = Rotation.from_quat(qs.as_xyzw(ra)).magnitude()
    np.testing.assert_allclose(half, full / 2, atol=1e-12)
    # Opt-out: the sign as given; −q̂ then goes the long way round.
    la, lb = qs.dq_power(d, t, long_path=True), qs.dq_power(-d, t, long_path=True)
    flipped = q[:, 0] < 0
    np.testing.assert_allclose(la[~flipped], a[~flipped], atol=1e-12)
    diff = np.minimum(np.abs(la - lb).max(-1), np.abs(la + lb).max(-1))
    assert np.all(diff[np.abs(t - np.round(t)) > 0.05] > 1e-6)


# ---- item 15: from_rotvec above |v| ≈ 1.3e154 -------------------------------------------------
def test_from_rotvec_huge_vectors_are_finite_unit_rotations():
    v = np.array([[1e154, 0, 0], [1.3e154, 1.3e154, 0], [1e200, -1e200, 1e200], [1e308, 0, 0]])
    q = qs.from_rotvec(v)
    assert np.all(np.isfinite(q))
    np.testing.assert_allclose(np.linalg.norm(q, axis=-1), 1.0, atol=1e-15)
    # The axis is the direction of v (the angle |v| mod 2π carries no information here).
    d = v / np.max(np.abs(v), axis=-1, keepdims=True)
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    axis = q[:, 1:] / np.linalg.norm(q[:, 1:], axis=-1, keepdims=True)
    np.testing.assert_allclose(np.abs(np.sum(axis * d, -1)), 1.0, atol=1e-15)
    # Where scipy is finite it agrees (same rotation), on both sides of the |v| = 1 branch.
    w = np.array(
        [[0.3, -0.2, 0.5], [1.0, 0, 0], [1 + 1e-15, 0, 0], [3.0, 4.0, 12.0], [1e10, 2e10, 0]]
    )
    ref = Rotation.from_rotvec(w).as_quat(scalar_first=True)
    np.testing.assert_allclose(np.abs(np.sum(qs.from_rotvec(w) * ref, -1)), 1.0, atol=1e-15)


# ---- item 9: no panic reaches Python when numpy cannot allocate --------------------------------
def test_output_allocation_failure_is_memory_error_naming_the_size_not_a_panic():
    s = qs.PiecewiseSlerp(qs.from_euler("z", [0.0, 1.0, 2.0]), [0.0, 1.0, 2.0])
    huge = np.broadcast_to(0.5, (2 * 10**9,))  # no memory behind it: stride 0
    # The binding allocates the (2e9, 16) output first: 238 GiB, refused by numpy → MemoryError.
    with pytest.raises(MemoryError, match=r"Spline\.evaluate: cannot allocate .*238\.4 GiB"):
        s._core.evaluate(huge, 3, "raise")
    # Through the public API: broadcasting keys against 10^12 parameters (a 0-stride view).
    t = np.broadcast_to(0.5, (10**12,))
    with pytest.raises(MemoryError, match=r"slerp: cannot allocate the \(1000000000000, 4\)"):
        qs.slerp([1, 0, 0, 0], [0, 1, 0, 0], t)
    # An exabyte-sized request is refused the same way.
    t = np.broadcast_to(0.5, (2**57,))
    with pytest.raises(MemoryError, match=r"slerp: cannot allocate .*4\.0 EiB"):
        qs.slerp([1, 0, 0, 0], [0, 1, 0, 0], t)
    assert qs.slerp([1, 0, 0, 0], [0, 1, 0, 0], 0.5).shape == (4,)  # still works


# ---- item 4: Squad's inner slerp vs numpy-quaternion ------------------------------------------
def _shoemake_controls(q):
    """Shoemake's uniform-time control points sᵢ = qᵢ exp(−(log(qᵢ* qᵢ₊₁) + log(qᵢ* qᵢ₋₁))/4)."""
    s = q.copy()
    for i in range(1, len(q) - 1):
        a = qs.log(qs.multiply(qs.conjugate(q[i]), q[i + 1]))
        b = qs.log(qs.multiply(qs.conjugate(q[i]), q[i - 1]))
        s[i] = qs.multiply(q[i], qs.exp(-(a + b) / 4))
    return s


@pytest.mark.parametrize("step", [0.3, 0.9, 1.2, 1.5])
def test_squad_agrees_with_numpy_quaternion_exactly_when_its_slerps_are_short(step):
    """README claim: on interior segments of uniformly timed keys our Squad equals
    numpy-quaternion's ``squad`` (to 1e-13) exactly when, in every segment, both of its slerps
    already take the short arc (sᵢ·sᵢ₊₁ ≥ 0 and Slerp(qᵢ, qᵢ₊₁; u)·Slerp(sᵢ, sᵢ₊₁; u) ≥ 0).
    Otherwise numpy-quaternion flips a slerp's end point mid-segment and its curve jumps;
    ours follows the S³ geodesic between the control points as designed and stays C¹."""
    import quaternion

    from ..splinekit import joint_jumps, random_walk

    agree = disagree = 0
    for seed in range(12):
        q = random_walk(10, seed, step=step)
        t = np.arange(10.0)
        ours_s = qs.Squad(q, t)
        assert np.max(joint_jumps(ours_s, 1)[:, 1]) < 1e-12  # C¹ at every joint, any step
        s = _shoemake_controls(q)
        short = True
        for i in range(1, 8):
            u = np.linspace(0, 1, 201)
            a = qs.slerp(q[i], q[i + 1], u, long_path=True)
            b = qs.slerp(s[i], s[i + 1], u, long_path=True)
            short &= bool(np.dot(s[i], s[i + 1]) >= 0 and np.all(np.sum(a * b, -1) >= 0))
        x = np.linspace(1.0, 8.0, 3501)
        ref = quaternion.as_float_array(quaternion.squad(quaternion.as_quat_array(q), t, x))
        ours = ours_s(x)
        diff = np.minimum(np.abs(ours - ref).max(-1), np.abs(ours + ref).max(-1)).max()
        if short:
            agree += 1
            assert diff < 1e-13
        else:
            disagree += 1
            assert diff > 1e-3

            # numpy-quaternion's curve jumps; ours moves smoothly between samples.
            def biggest_step(v):
                return 2 * np.arccos(np.abs(np.sum(v[1:] * v[:-1], -1)).clip(0, 1)).max()

            assert biggest_step(ref) > 10 * biggest_step(ours)
    if step <= 0.9:
        assert disagree == 0
    if step >= 1.5:
        assert disagree > 0


# ---- item 5: CumulativeBezier with thousands of control points ---------------------------------
def test_cumulative_bezier_thousands_of_control_points_match_mpmath_reference():
    """On main every value and derivative was NaN from 1,024 control points on (C(n, i)
    overflowed). Reference: the cumulative basis B̃_j(u) = Σ_{i≥j} C(n,i) uⁱ(1−u)ⁿ⁻ⁱ in mpmath
    (40 digits), then q₀ Π exp(B̃_j log(q_{j−1}* q_j)) in numpy."""
    import mpmath

    from ..splinekit import fd, random_walk

    mpmath.mp.dps = 40
    n1 = 3000
    c = random_walk(n1, 11, step=0.06)
    s = qs.CumulativeBezier(c)
    logs = qs.log(qs.multiply(qs.conjugate(c[:-1]), c[1:]))
    n = n1 - 1
    for u in (0.0, 0.013, 0.25, 0.5, 0.731, 0.999, 1.0):
        um = mpmath.mpf(u)
        terms = [mpmath.binomial(n, i) * um**i * (1 - um) ** (n - i) for i in range(n + 1)]
        cum = np.empty(n + 1)
        acc = mpmath.mpf(0)
        for j in range(n, 0, -1):
            acc += terms[j]
            cum[j] = float(acc)
        q = c[0]
        for j in range(1, n + 1):
            q = qs.multiply(q, qs.exp(cum[j] * logs[j - 1]))
        got = s(u)
        assert np.all(np.isfinite(s.derivatives(u, 3)))
        np.testing.assert_allclose(np.abs(np.dot(got, q)), 1.0, atol=1e-12)
        np.testing.assert_allclose(got, q * np.sign(np.dot(got, q)), atol=1e-10)
    # Exact derivatives against finite differences of the values, well inside the domain.
    x = np.array([0.2, 0.5, 0.8])
    for k in (1, 2):
        f = s if k == 1 else (lambda t: s.derivative(t, 1))
        np.testing.assert_allclose(s.derivative(x, k), fd(f, x, 1e-4), rtol=1e-5, atol=1e-6)


def test_cumulative_bezier_above_its_limit_names_the_limit_and_the_alternative():
    with pytest.raises(
        ValueError, match=r"control_points: 4097 control points: .*at most 4096.*bspline"
    ):
        qs.CumulativeBezier(np.tile([1.0, 0, 0, 0], (4097, 1)))


# ---- item 6: SphericalBezier degree cap; registry methods bounded -----------------------------
def test_spherical_bezier_degree_above_64_is_refused_naming_the_limit_and_alternative():
    from ..splinekit import random_walk

    qs.SphericalBezier(random_walk(65, 1, 0.1))  # degree 64: fine
    with pytest.raises(
        ValueError, match=r"control_points: 400 control points \(degree 399\).*degree 64.*bspline"
    ):
        qs.SphericalBezier(random_walk(400, 1, 0.1))
    # The registry's one-curve methods inherit the limits (3,000 keys took forever before).
    keys = random_walk(3000, 2, 0.06)
    with pytest.raises(ValueError, match="degree 64"):
        qs.spline("bezier", keys)
    with pytest.raises(ValueError, match="at most 4096"):
        qs.spline("cumulative_bezier", np.tile(keys, (2, 1)))
    assert np.all(np.isfinite(qs.spline("cumulative_bezier", keys)(np.linspace(0, 2999, 7))))


# ---- item 15: API inputs ----------------------------------------------------------------------
@pytest.mark.parametrize("method", ["bezier", "cumulative_bezier", "bspline", "beta"])
@pytest.mark.parametrize(
    "times, msg",
    [
        ([0, 1, np.nan, 3, 4, 5], r"times: non-finite value .* at element 2"),
        ([0, 2, 1, 3, 4, 5], r"times: not strictly increasing at index 2"),
        ([0, 1, 2, 3, 4, 1e40], r"times: .*beyond the supported range"),
        ([[0, 1, 2, 3, 4, 5]], r"times: expected 6 times"),
    ],
)
def test_registry_validates_times_for_approximating_methods(method, times, msg):
    from ..splinekit import random_walk

    with pytest.raises(ValueError, match=msg):
        qs.spline(method, random_walk(6, 3), times)


def test_splines_own_their_keys_so_reparameterize_ignores_caller_mutation():
    from ..splinekit import random_walk

    q, t = random_walk(8, 4), np.arange(8.0) * 0.5
    s = qs.spline("squad", q, t)
    want = qs.reparameterize(s)(np.linspace(0, 3.5, 9))
    q[:] = [1.0, 0, 0, 0]
    t[:] = np.arange(8.0)
    np.testing.assert_array_equal(qs.reparameterize(s)(np.linspace(0, 3.5, 9)), want)
    assert not s.params["quats"].flags.writeable


def test_pose_spline_refuses_unknown_extrapolate():
    from ..splinekit import random_walk

    with pytest.raises(
        ValueError,
        match=r"extrapolate: expected one of \('raise', 'clamp', .*'periodic'\), got 'clmap'",
    ):
        qs.PoseSpline(np.arange(5.0), random_walk(5, 1), np.zeros((5, 3)), extrapolate="clmap")


@pytest.mark.parametrize(
    "t, exc, msg",
    [
        (np.nan, ValueError, r"t: expected a finite number, got nan"),
        (1e300, ValueError, r"t: t = 1e\+300 is outside the spline's domain \[0.0, 5.0\]"),
        ("1.0", TypeError, r"t: expected a real number, got str"),
    ],
)
def test_segment_derivatives_rejects_nan_huge_and_non_numbers(t, exc, msg):
    from ..splinekit import random_walk

    s = qs.Squad(random_walk(6, 1), np.arange(6.0))
    with pytest.raises(exc, match=msg):
        s.segment_derivatives(0, t)
    with pytest.raises(TypeError, match=r"segment: expected an integer, got float 2.5"):
        s.segment_derivatives(2.5, 1.0)
    with pytest.raises(ValueError, match=r"segment: expected an integer from 0 to 4, got 5"):
        s.segment_derivatives(5, 1.0)


def test_sample_refuses_a_fractional_count():
    s = qs.PiecewiseSlerp(qs.from_euler("z", [0.0, 1.0]), [0.0, 1.0])
    with pytest.raises(TypeError, match=r"n: expected an integer, got float 2.7"):
        s.sample(n=2.7)
    with pytest.raises(ValueError, match=r"n: expected an integer ≥ 1, got 0"):
        s.sample(n=0)
    with pytest.raises(ValueError, match=r"rate: expected a finite positive number, got -2.0"):
        s.sample(rate=-2.0)
    assert len(s.sample(n=np.int64(3))[0]) == 3


def test_natural_ends_refuse_a_start_or_end_rate():
    from ..splinekit import random_walk

    q = random_walk(5, 2)
    with pytest.raises(ValueError, match=r"start_rate: only used with ends='clamped'"):
        qs.NaturalSpline(q, ends="natural", start_rate=[1.0, 0, 0])
    with pytest.raises(ValueError, match=r"end_rate: only used with ends='clamped'"):
        qs.NaturalSpline(q, end_rate=[1.0, 0, 0])
    qs.NaturalSpline(q, ends="clamped", start_rate=[1.0, 0, 0])


def test_masked_arrays_with_masked_elements_are_refused_and_unmasked_ones_read():
    from ..splinekit import random_walk

    q = random_walk(5, 2)
    m = np.ma.masked_array(q, mask=np.zeros_like(q, bool))
    np.testing.assert_array_equal(qs.Squad(m)(1.5), qs.Squad(q)(1.5))
    m.mask[2, 1] = True
    with pytest.raises(ValueError, match=r"quats: masked array with 1 masked element\(s\)"):
        qs.Squad(m)
    with pytest.raises(ValueError, match=r"t: masked array"):
        qs.Squad(q)(np.ma.masked_array([0.5, 1.0], mask=[False, True]))
    with pytest.raises(ValueError, match=r"q0: masked array"):
        qs.slerp(m, q, 0.5)


# ---- item 16: one error convention (TypeError kind, ValueError value, argument named) ---------
@pytest.mark.parametrize(
    "call, exc, msg",
    [
        (
            lambda s: s.derivative(1.0, order=2.0),
            TypeError,
            r"^order: expected an integer, got float 2.0$",
        ),
        (
            lambda s: s.derivative(1.0, order=4),
            ValueError,
            r"^order: expected an integer from 0 to 3, got 4$",
        ),
        (
            lambda s: s.derivatives(1.0, order="3"),
            TypeError,
            r"^order: expected an integer, got str '3'$",
        ),
        (
            lambda s: qs.CumulativeBSpline(s.params["quats"], order=-1),
            ValueError,
            r"^order: expected 2 ≤ order ≤ 12, got -1$",
        ),
        (
            lambda s: qs.CumulativeBSpline(s.params["quats"], order=4.0),
            TypeError,
            r"^order: expected an integer",
        ),
        (
            lambda s: qs.continuity(s, tol="1e-9"),
            TypeError,
            r"^tol: expected a real number, got str '1e-9'$",
        ),
        (
            lambda s: qs.continuity(s, tol=-1.0),
            ValueError,
            r"^tol: expected a finite positive number, got -1.0$",
        ),
        (
            lambda s: qs.continuity(s, order=1.0),
            TypeError,
            r"^order: expected an integer, got float 1.0$",
        ),
        (
            lambda s: qs.set_num_threads(-1),
            ValueError,
            r"^n: expected an integer from 0 to 1024, got -1$",
        ),
        (lambda s: qs.set_num_threads(2.5), TypeError, r"^n: expected an integer, got float 2.5$"),
        (
            lambda s: qs.rotate_points(s(0.5)[None], [[np.nan, 0, 0]]),
            ValueError,
            r"^points: non-finite value \(NaN or inf\) at element 0$",
        ),
        (
            lambda s: qs.ScrewSpline(s.params["quats"][:3], [0, np.nan, 2], np.zeros((3, 3))),
            ValueError,
            r"^times: non-finite value",
        ),
        (
            lambda s: qs.ScrewSpline(s.params["quats"][:3], [0, 1, 1e40], np.zeros((3, 3))),
            ValueError,
            r"^times: .*beyond the supported range",
        ),
        (
            lambda s: qs.dlb(np.zeros((0, 8)), np.zeros(0)),
            ValueError,
            r"^dqs: expected at least one pose",
        ),
        (
            lambda s: qs.Squad(s.params["quats"], extrapolate=1),
            TypeError,
            r"^extrapolate: expected one of",
        ),
        (lambda s: qs.from_euler(3, [0.0]), TypeError, r"^seq: expected a string"),
    ],
)
def test_error_convention_typeerror_for_kind_valueerror_for_value_naming_the_argument(
    call, exc, msg
):
    from ..splinekit import random_walk

    s = qs.Squad(random_walk(6, 1), np.arange(6.0))
    with pytest.raises(exc, match=msg):
        call(s)
    qs.set_num_threads(0)


@pytest.mark.parametrize("scale", [1e-170, 1e-200, 1e-300, 1e160, 1e300])
def test_log_of_a_tiny_or_huge_quaternion_is_finite(scale):
    # |q|² underflowed to 0 below ~1e-154 (and overflowed above ~1e154): log gave ∓inf
    q = np.array([0.6, 0.0, 0.8, 0.0]) * scale
    got = qs.log(q)
    assert np.isfinite(got).all(), got
    np.testing.assert_allclose(got[0], np.log(scale), rtol=1e-14)
    np.testing.assert_allclose(got[1:], [0.0, np.arctan2(0.8, 0.6), 0.0], atol=1e-15)
    with pytest.raises(ValueError, match="q: quaternion 0 has zero"):
        qs.log(np.zeros(4))  # the zero quaternion has no logarithm


def _rate_methods():
    """Every registry method with its key-based parameters (holds on where it is a choice)."""
    out = []
    for name, m in qs.registry.METHODS.items():
        params = {"holds": True} if "holds" in m.params else {}
        if name == "fit":  # a fixed λ: the default λ search on stationary data is fit's own test
            params = {"smoothing": "1e-3"}
        out.append(pytest.param(name, params, id=name))
        if name == "natural":
            for ends in ("clamped", "rest", "closed"):
                out.append(pytest.param(name, {"ends": ends}, id=f"natural-{ends}"))
    return out


@pytest.mark.parametrize("method, params", _rate_methods())
def test_constant_attitude_has_exactly_zero_rates_in_every_spline_family(method, params):
    # NaturalSpline(ends="clamped") through one attitude gave α = 3.3e-16 where scipy gives 0:
    # q* q had a vector part of ~1e-17, so the chord between equal keys was not the identity
    rng = np.random.default_rng(5)
    for base in qs.from_rotvec(rng.normal(size=(4, 3)) * 1.5):
        q = np.tile(base, (7, 1))
        t = np.cumsum(np.r_[0.0, rng.uniform(0.2, 2.0, 6)])
        s = qs.registry.spline(method, q, t, **params)
        tt = np.linspace(*s.domain, 61)
        for f in (s.angular_velocity, s.angular_acceleration, s.jerk):
            for frame in ("world", "body"):
                assert np.all(f(tt, frame) == 0.0), (method, f.__name__, frame)
        v = s(tt)
        assert np.all(np.minimum(np.abs(v - base), np.abs(v + base)) <= 2e-15), method


@pytest.mark.parametrize(
    "method, params",
    [
        p
        for p in _rate_methods()
        if qs.registry.METHODS[p.values[0]].interpolating or "holds" in p.values[1]
    ],
)
def test_hold_between_equal_keys_is_exactly_constant_in_every_family(method, params):
    # MinimumEnergySpline drifted 5.3° between two equal keys; the others held to rounding
    rng = np.random.default_rng(6)
    for _ in range(4):
        q = qs.from_rotvec(rng.normal(size=(7, 3)) * 0.6)
        q[3] = q[2]
        t = np.cumsum(np.r_[0.0, rng.uniform(0.3, 2.0, 6)])
        if params.get("ends") == "closed":
            t = np.r_[t, t[-1] + 1.0]
        s = qs.registry.spline(method, q, t, **params)
        if method == "bspline":  # approximating: its hold is the interval it reports
            lo, hi = s.hold_intervals[0]
        else:
            lo, hi = t[2], t[3]
        tt = np.linspace(lo, hi, 41)[1:-1]
        for f in (s.angular_velocity, s.angular_acceleration, s.jerk):
            assert np.all(f(tt) == 0.0), (method, f.__name__)
        ref = q[2] if method != "bspline" else s(tt[0])
        v = s(tt)
        assert np.all(np.minimum(np.abs(v - ref), np.abs(v + ref)) <= 2e-15), method


# ---- messages print huge and tiny numbers short ----------------------------------------------
_K2 = np.tile([1.0, 0.0, 0.0, 0.0], (2, 1))
_K3 = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0], [0, 0, 1.0, 0]])
_K4 = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0], [0, 0, 1.0, 0], [0, 0, 0, 1.0]])


@pytest.mark.parametrize(
    ("call", "shown"),
    [
        (lambda: qs.spline("slerp", _K2, [0, 1e300]), "1e300"),
        (lambda: qs.spline("slerp", _K2, [0, -1e300]), "-1e300"),
        (lambda: qs.spline("slerp", _K2, [0, 1])(np.array([1e300])), "1e300"),
        (lambda: design.evaluate("c3", _K3, [0, 1, 2], {"alpha": 1e308}), "1e308"),
        (lambda: design.evaluate("kochanek_bartels", _K3, [0, 1, 2], {"tension": 1e308}), "1e308"),
        (lambda: qs.spline("kochanek_bartels", _K3, [0, 1, 2], bias=-1e308), "-1e308"),
        (lambda: qs.spline("beta", _K4, None, beta1=1e-300), "1e-300"),
        (lambda: qs.spline("beta", _K4, None, beta2=-1e300), "-1e300"),
        (
            lambda: qs.CumulativeBSpline(_K4, knots=[0, 0, 0, 0, 1e300, 1e300, 1e300, 1e300]),
            "1e300",
        ),
        (lambda: qs.CumulativeBSpline(_K4, knots=[0, 0, 0, 1e29, -1e300, 1, 1, 1]), "-1e300"),
    ],
    ids=[
        "key-time",
        "decreasing-time",
        "outside-domain",
        "c3-alpha",
        "design-tension",
        "kb-bias",
        "beta1-tiny",
        "beta2",
        "knot-range",
        "knot-order",
    ],
)
def test_core_messages_print_huge_numbers_short(call, shown):
    with pytest.raises(ValueError) as e:
        call()
    msg = str(e.value)
    assert "\n" not in msg, msg
    assert max(len(run) for run in re.findall(r"\d+", msg)) <= 20, msg
    assert shown in msg, msg
