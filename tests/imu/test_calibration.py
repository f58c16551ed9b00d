"""quatspline.imu.calibrate: recovery of planted parameters (exact and with noise, where the
stated standard errors must be honest), the analytic Jacobian against finite differences,
Kabsch against scipy, the bundled RepoIMU recording within physical bounds, and refusals."""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
import quatspline as qs
from quatspline.imu import Calibration, SensorModel, calibrate, simulate
from quatspline.imu.calibration import COMPONENTS, _kabsch, _Problem
from quatspline.io import ImuData, ImuNoise, Trajectory
from scipy.spatial.transform import Rotation

DATA = Path(__file__).resolve().parents[2] / "data"

ROT = qs.from_rotvec([0.1, -0.2, 0.3])  # R_bs
BIAS = np.array([0.01, 0.0, -0.02])
SCALE = np.array([1.01, 0.98, 1.003])
OFFSET = 0.0123


def _motion(duration=20.0, seed=0):
    """A C³ spline exciting all three axes with varying rates."""
    tk = np.linspace(0.0, duration, int(4 * duration) + 1)
    rv = np.c_[np.sin(tk), np.cos(0.7 * tk), np.sin(1.3 * tk + seed)]
    return qs.spline("c3", qs.from_rotvec(rv), tk)


K_TRUE = np.diag(SCALE)


def _gyro(motion, t, rot=ROT, bias=BIAS, k=K_TRUE, offset=OFFSET):
    """The model written out independently: ω_meas(t) = K R_bsᵀ ω_body(t + δ) + b."""
    r = qs.as_matrix(rot)
    w = motion.angular_velocity(t + offset, frame="body")
    return np.einsum("ij,jk,nk->ni", k, r.T, w) + bias


def _angle(q1, q2) -> float:
    d = abs(float(np.dot(q1, q2)))
    return 2.0 * math.acos(min(1.0, d))


def test_noise_free_recovery_to_1e6():
    m = _motion()
    t = np.arange(0.5, 19.5, 0.005)
    cal = calibrate(m, ImuData(t, _gyro(m, t)))
    assert isinstance(cal, Calibration)
    assert _angle(cal.rotation, ROT) <= 1e-6
    np.testing.assert_allclose(cal.gyro_bias, BIAS, atol=1e-6)
    np.testing.assert_allclose(cal.scale, SCALE, atol=1e-6)
    assert abs(cal.time_offset - OFFSET) <= 1e-6
    assert np.all(cal.rms < 1e-9) and cal.unobservable == ()
    np.testing.assert_allclose(cal.residuals, cal.measured - cal.predicted)


def test_noise_free_misalignment_and_negative_offset():
    m = _motion()
    t = np.arange(0.5, 19.5, 0.01)
    k = np.array([[1.02, 0.004, -0.003], [0.0, 0.99, 0.006], [0.0, 0.0, 1.01]])
    g = _gyro(m, t, k=k, offset=-0.0371)
    est = ("rotation", "bias", "scale", "misalignment", "time_offset")
    cal = calibrate(m, ImuData(t, g), estimate=est)
    np.testing.assert_allclose(cal.scale_matrix, k, atol=1e-6)
    assert abs(cal.time_offset + 0.0371) <= 1e-6
    assert _angle(cal.rotation, ROT) <= 1e-6


def test_offset_found_beyond_the_margin_by_correlation():
    """A large offset (0.4 s, 80 samples) is found by the |ω| correlation, then refined."""
    m = _motion()
    t = np.arange(1.0, 19.0, 0.005)
    cal = calibrate(m, ImuData(t, _gyro(m, t, offset=0.4)), max_offset=0.6)
    assert abs(cal.time_offset - 0.4) <= 1e-6


@pytest.mark.parametrize("robust", [None, "huber"])
def test_standard_errors_are_honest_over_seeds(robust):
    """White noise of 0.005 rad/s: the z-scores (error / stated standard error) of 10
    components over 8 seeds have an RMS near 1 (standard errors neither too small nor too
    large), at least 97 % of them lie within 3 standard errors (99.7 % expected) and none
    beyond 4 (probability 0.5 % for 80 honest draws)."""
    m = _motion()
    t = np.arange(0.5, 19.5, 0.01)
    clean = _gyro(m, t)
    truth_rot = qs.as_matrix(ROT)
    z = []
    for seed in range(8):
        g = clean + np.random.default_rng(seed).normal(0.0, 0.005, clean.shape)
        cal = calibrate(m, ImuData(t, g), robust=robust)
        se = cal.standard_errors
        # rotation error as the right perturbation: R_true = R_est Exp(e)
        e = qs.as_rotvec(qs.from_matrix(cal.rotation_matrix.T @ truth_rot))
        z += list(e / se["rotation"])
        z += list((BIAS - cal.gyro_bias) / se["gyro_bias"])
        z += list((SCALE - cal.scale) / se["scale"])
        z.append((OFFSET - cal.time_offset) / se["time_offset"])
        assert 0.0045 < cal.sigma < 0.0055
    z = np.array(z)
    assert np.all(np.abs(z) < 4.0), np.abs(z).max()
    assert np.mean(np.abs(z) < 3.0) >= 0.97
    assert 0.75 < np.sqrt(np.mean(z**2)) < 1.25


def test_jacobian_matches_finite_differences():
    m = _motion()
    t = np.arange(1.0, 19.0, 0.05)
    r0 = qs.as_matrix(qs.from_rotvec([0.3, 0.1, -0.4]))
    p = _Problem(m, t, np.zeros((t.size, 3)), r0)
    x = np.array([0.05, -0.02, 0.03, 0.1, 0.2, 0.3, 1.1, 0.9, 1.05, 0.01, -0.02, 0.03, 0.013])
    _, jac = p.evaluate(x)
    h = 1e-6
    for i in range(13):
        dx = np.zeros(13)
        dx[i] = h
        fd = (p.evaluate(x + dx, False)[0] - p.evaluate(x - dx, False)[0]).ravel() / (2 * h)
        np.testing.assert_allclose(jac[:, i], fd, atol=1e-7, err_msg=COMPONENTS[i])


def test_kabsch_matches_scipy_align_vectors():
    rng = np.random.default_rng(3)
    body = rng.normal(size=(50, 3))
    r = qs.as_matrix(qs.from_rotvec([0.7, -1.1, 0.4]))
    sensor = body @ r + rng.normal(0, 0.01, body.shape)  # rows rᵀ b
    ours = _kabsch(body, sensor)
    theirs = Rotation.align_vectors(body, sensor)[0].as_matrix()
    np.testing.assert_allclose(ours, theirs, atol=1e-12)


def test_trajectory_reference_is_smoothed_and_used():
    """A Trajectory of mocap orientations (noise 0.05°) at 100 Hz: the fit route gives the
    planted offset to a fraction of the sample interval."""
    m = _motion()
    tk = np.arange(0.0, 20.0, 0.01)
    rng = np.random.default_rng(5)
    noise = qs.from_rotvec(rng.normal(0, math.radians(0.05), (tk.size, 3)))
    keys = qs.multiply(m(tk), noise)
    t = np.arange(0.5, 19.5, 0.005)
    cal = calibrate(Trajectory(tk, keys), ImuData(t, _gyro(m, t)))
    assert abs(cal.time_offset - OFFSET) < 1e-3
    assert _angle(cal.rotation, ROT) < math.radians(0.2)


def _repoimu():
    """The bundled RepoIMU file read independently: time, Vicon wxyz, acc, gyro (rad/s)."""
    a = np.loadtxt(DATA / "repoimu" / "repoIMU_first30s.csv", delimiter=";", skiprows=2)
    return a[:, 0], a[:, 1:5], a[:, 8:11]


def test_repoimu_calibrates_within_physical_bounds():
    t, q, g = _repoimu()
    # The raw gyro axes and the reference body axes already agree (a precondition from the
    # data, before any calibration): each axis correlates above 0.8 with the Vicon rate.
    w = qs.fit(t, q).angular_velocity(t, frame="body")
    for j in range(3):
        assert np.corrcoef(w[:, j], g[:, j])[0, 1] > 0.8
    # the y and z rates stay within ±10 °/s: their scales (and the rotation about x, which
    # trades against them) are weakly determined, and said to be; the bias and the offset,
    # determined by any motion with varying rates, are not among them
    with pytest.warns(RuntimeWarning, match="weakly") as record:
        cal = calibrate(Trajectory(t, q), ImuData(t, g))
    assert np.all(np.abs(g[:, 1:]) < math.radians(10.0))
    assert "scale[y]" in cal.weak and "scale[z]" in cal.weak
    assert not any(w.startswith(("bias", "time_offset")) for w in cal.weak)
    assert all(w in str(record[0].message) for w in cal.weak)
    # the mounting: the axes already agree, so R_bs is a small correction (< 10°)
    assert math.degrees(_angle(cal.rotation, [1, 0, 0, 0])) < 10.0
    # the time offset: inside the search window, resolved to better than a sample interval
    assert abs(cal.time_offset) < 1.0 and cal.standard_errors["time_offset"] < 0.01
    # a consumer MEMS gyroscope: zero-rate offset within ±5 °/s
    assert np.all(np.abs(np.degrees(cal.gyro_bias)) < 5.0)
    # the calibrated model explains most of the measured rate: residual power below a
    # quarter of the signal's (mean-removed) power; a wrong mounting or offset does not
    signal = np.sum(np.var(cal.measured, axis=0))
    assert np.sum(cal.rms**2) < 0.25 * signal
    # where the Vicon shows the device at rest (its first 3 s: |ω| below 1 °/s) the residual
    # is the gyro's own noise there: its spread within 1.5 × the raw gyro's spread
    rest = (cal.times < t[0] + 3.0) & (
        np.linalg.norm(cal.predicted - cal.gyro_bias, axis=1) < math.radians(1.0)
    )
    assert np.count_nonzero(rest) > 100
    raw = np.std(g[: np.count_nonzero(t < t[0] + 3.0)], axis=0)
    assert np.all(np.std(cal.residuals[rest], axis=0) < 1.5 * raw)
    assert cal.unobservable == () and cal.converged


def test_at_rest_bias_estimated_rest_flagged():
    """A device at rest: only the bias is observable; the rest is held and named."""
    tk = np.linspace(0.0, 10.0, 11)
    m = qs.spline("c3", np.tile(qs.from_rotvec([0.2, 0.1, 0.0]), (11, 1)), tk)
    t = np.arange(0.0, 10.0, 0.01)
    g = np.tile(BIAS, (t.size, 1)) + np.random.default_rng(0).normal(0, 1e-3, (t.size, 3))
    with pytest.warns(RuntimeWarning, match="does not excite rotation"):
        cal = calibrate(m, ImuData(t, g))
    assert set(cal.unobservable) == {
        *(f"rotation[{a}]" for a in "xyz"),
        *(f"scale[{a}]" for a in "xyz"),
        "time_offset",
    }
    np.testing.assert_allclose(cal.gyro_bias, cal.measured.mean(0), atol=1e-12)
    assert np.all(np.isinf(cal.standard_errors["rotation"]))
    assert np.all(np.isfinite(cal.standard_errors["gyro_bias"]))
    np.testing.assert_allclose(cal.rotation, [1, 0, 0, 0])
    assert json.dumps(cal.to_dict())  # inf is written as null


def test_single_axis_motion_flags_rotation_about_it():
    tk = np.linspace(0.0, 10.0, 41)
    m = qs.spline("c3", qs.from_rotvec(np.c_[0 * tk, 0 * tk, np.sin(tk) + 0.3 * tk]), tk)
    t = np.arange(0.5, 9.5, 0.01)
    g = _gyro(m, t, rot=[1, 0, 0, 0])
    with pytest.warns(RuntimeWarning, match="rotation\\[z\\]"):
        cal = calibrate(m, ImuData(t, g))
    assert set(cal.unobservable) == {"rotation[z]", "scale[x]", "scale[y]"}
    assert abs(cal.time_offset - OFFSET) < 1e-6
    np.testing.assert_allclose(cal.gyro_bias, BIAS, atol=1e-9)


def test_disjoint_times_refused():
    m = _motion()
    t = np.arange(100.0, 110.0, 0.01)
    with pytest.raises(ValueError, match="do not overlap the motion's domain"):
        calibrate(m, ImuData(t, np.zeros((t.size, 3))))


def test_too_few_samples_refused():
    m = _motion()
    t = np.array([5.0, 5.1, 5.2])
    with pytest.raises(ValueError, match="3 IMU samples inside"):
        calibrate(m, ImuData(t, np.zeros((3, 3))), estimate=("bias",))


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"estimate": ("rotation", "offset")}, ValueError, "estimate"),
        ({"max_offset": -1.0}, ValueError, "max_offset"),
        ({"max_offset": float("nan")}, ValueError, "max_offset"),
        ({"max_offset": "1"}, TypeError, "max_offset"),
        ({"robust": "l1"}, ValueError, "robust"),
    ],
)
def test_bad_options(kwargs, exc, match):
    m = _motion()
    t = np.arange(1.0, 5.0, 0.01)
    with pytest.raises(exc, match=match):
        calibrate(m, ImuData(t, _gyro(m, t)), **kwargs)


def test_wrong_kinds():
    m = _motion()
    with pytest.raises(TypeError, match="motion"):
        calibrate("not a spline", ImuData([0.0, 1.0], np.zeros((2, 3))))
    with pytest.raises(TypeError, match="data"):
        calibrate(m, np.zeros((5, 3)))


def test_robust_loss_resists_glitches():
    m = _motion()
    t = np.arange(0.5, 19.5, 0.005)
    g = _gyro(m, t) + np.random.default_rng(1).normal(0, 0.005, (t.size, 3))
    g[::97] += 2.0  # spikes of 2 rad/s on 1 % of the samples
    with warnings.catch_warnings():  # the spikes swamp an axis of the plain solve: warned
        warnings.simplefilter("ignore", RuntimeWarning)
        plain = calibrate(m, ImuData(t, g))
    robust = calibrate(m, ImuData(t, g), robust="huber")  # no warning: turned to an error
    assert robust.weak == ()
    assert abs(robust.time_offset - OFFSET) < abs(plain.time_offset - OFFSET)
    assert np.linalg.norm(robust.gyro_bias - BIAS) < 0.2 * np.linalg.norm(plain.gyro_bias - BIAS)


def test_figure_and_table(tmp_path):
    m = _motion()
    t = np.arange(0.5, 19.5, 0.01)
    cal = calibrate(m, ImuData(t, _gyro(m, t)))
    fig = cal.plot_residuals(tmp_path / "cal.png", name="synthetic")
    assert (tmp_path / "cal.png").stat().st_size > 0 and len(fig.axes) == 4
    text = cal.table()
    assert "time offset (ms)" in text and "12.3" in text
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        json.dumps(cal.to_dict())


def test_correct_inverts_the_model():
    m = _motion()
    t = np.arange(0.5, 19.5, 0.01)
    g = _gyro(m, t)
    cal = calibrate(m, ImuData(t, g))
    np.testing.assert_allclose(
        cal.correct(g), m.angular_velocity(t + cal.time_offset, frame="body"), atol=1e-9
    )


def test_recovers_what_simulate_planted_through_a_sensor_model():
    """The conventions agree with quatspline.imu.simulate's SensorModel: its rotation (body
    from sensor), time offset (sample stamped t measures the motion at t + δ), gyro matrix
    and bias come back from calibrate, noise-free to 1e-6."""
    m = _motion()
    k = np.array([[1.02, 0.004, -0.003], [0.0, 0.99, 0.006], [0.0, 0.0, 1.01]])
    sensor = SensorModel(rotation=ROT, time_offset=-0.021, gyro_matrix=k, gyro_bias=BIAS)
    data = simulate(m, times=np.arange(0.5, 19.5, 0.005), sensor=sensor)
    est = ("rotation", "bias", "scale", "misalignment", "time_offset")
    cal = calibrate(m, data, estimate=est)
    assert _angle(cal.rotation, ROT) <= 1e-6
    assert abs(cal.time_offset + 0.021) <= 1e-6
    np.testing.assert_allclose(cal.scale_matrix, k, atol=1e-6)
    np.testing.assert_allclose(cal.gyro_bias, BIAS, atol=1e-6)


def test_recovers_simulated_noise_within_its_standard_errors():
    """A consumer MEMS noise model (white only: the model has a constant bias) through
    simulate: rotation, bias and offset within 3 standard errors."""
    m = _motion()
    noise = ImuNoise(gyroscope_noise_density=0.0003)
    sensor = SensorModel(rotation=ROT, time_offset=0.0077, gyro_bias=BIAS)
    data = simulate(m, rate=200.0, sensor=sensor, noise=noise, seed=4)
    cal = calibrate(m, data)
    se = cal.standard_errors
    e = qs.as_rotvec(qs.from_matrix(cal.rotation_matrix.T @ qs.as_matrix(ROT)))
    assert np.all(np.abs(e) < 3 * se["rotation"])
    assert np.all(np.abs(cal.gyro_bias - BIAS) < 3 * se["gyro_bias"])
    assert abs(cal.time_offset - 0.0077) < 3 * se["time_offset"]


def test_single_axis_motion_from_noisy_mocap_is_warned_as_weak():
    """Rotation about one axis seen through noisy motion capture: nothing is exactly
    unobservable, but the other axes' scales and the rotation about the axis are determined
    to no use — named in a warning, never a silent guess."""
    tk = np.linspace(0.0, 10.0, 41)
    m = qs.spline("c3", qs.from_rotvec(np.c_[0 * tk, 0 * tk, np.sin(tk) + 0.3 * tk]), tk)
    rng = np.random.default_rng(0)
    t = np.arange(0.5, 9.5, 0.005)
    g = _gyro(m, t, rot=[1, 0, 0, 0]) + rng.normal(0, 0.003, (t.size, 3))
    tt = np.arange(0.0, 10.0, 0.01)
    noise = qs.from_rotvec(rng.normal(0, math.radians(0.1) / math.sqrt(3), (tt.size, 3)))
    with pytest.warns(RuntimeWarning, match="weakly") as record:
        cal = calibrate(Trajectory(tt, qs.multiply(m(tt), noise)), ImuData(t, g))
    assert {"rotation[z]", "scale[x]", "scale[y]"} <= set(cal.weak)
    assert "scale[z]" not in cal.weak and abs(cal.scale[2] - SCALE[2]) < 0.02
    assert "time_offset" not in cal.weak and abs(cal.time_offset - OFFSET) < 1e-3
    assert "scale[x]" in str(record[0].message)
