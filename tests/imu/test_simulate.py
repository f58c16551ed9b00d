"""quatspline.imu.simulate: exact rates and specific force, the sensor model, the noise model.

Oracles: finite differences of the spline's own orientation and position (and of the
sensor's world position p + R r), and every rotation computed with scipy's ``Rotation``
(no quatspline code on the expected side).
"""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from quatspline.imu import ImuNoise, SensorModel, allan_deviation, simulate, simulation
from scipy.spatial.transform import Rotation

G = np.array([0.0, 0.0, -9.80665])


def _rot(q) -> Rotation:
    q = np.asarray(q, dtype=float)
    return Rotation.from_quat(np.concatenate([q[..., 1:], q[..., :1]], axis=-1))


def _smooth(rng, t, amp, n=4, fmax=0.4):
    out = np.zeros((t.size, 3))
    for _ in range(n):
        f, ph = rng.uniform(0.05, fmax, 3), rng.uniform(0, 2 * np.pi, 3)
        out += rng.normal(0, amp, 3) * np.sin(2 * np.pi * f * t[:, None] + ph)
    return out


@pytest.fixture(scope="module")
def pose():
    rng = np.random.default_rng(7)
    tk = np.arange(0.0, 11.0, 0.5)
    keys = qs.from_rotvec(_smooth(rng, tk, 0.6))
    return qs.PoseSpline(keys, tk, _smooth(rng, tk, 1.5), rotation="c3")


def _away_from(joints, t, gap):
    """The times of ``t`` farther than ``gap`` from every joint (where derivatives jump)."""
    joints = np.asarray(joints)
    return t[np.min(np.abs(t[:, None] - joints[None, :]), axis=1) > gap]


def _second_derivative(f, t, h=2.5e-3):
    """Fourth-order central difference of f'' (error h⁴ f⁽⁶⁾ / 90)."""
    return (-f(t + 2 * h) + 16 * f(t + h) - 30 * f(t) + 16 * f(t - h) - f(t - 2 * h)) / (12 * h**2)


def _fd_body_rate(orientation, t, h=1e-4):
    """ω_body ≈ Log(R(t − h)ᵀ R(t + h)) / 2h, from scipy rotations."""
    r0, r1 = _rot(orientation(t - h)), _rot(orientation(t + h))
    return (r0.inv() * r1).as_rotvec() / (2 * h)


def test_gyro_is_the_body_rate(pose):
    t = np.linspace(0.3, 9.7, 157)
    d = simulate(pose, times=t)
    np.testing.assert_allclose(d.gyro, _fd_body_rate(pose.orientation, t), atol=2e-6)
    # and exactly the spline's own body-frame rate
    np.testing.assert_array_equal(d.gyro, pose.angular_velocity(t, frame="body"))


def test_accel_is_the_specific_force(pose):
    t = _away_from(pose.rotation.joints, np.linspace(0.3, 9.7, 157), 0.006)
    pdd = _second_derivative(pose.position, t)
    expected = _rot(pose.orientation(t)).apply(pdd - G, inverse=True)
    d = simulate(pose, times=t)
    np.testing.assert_allclose(d.accel, expected, atol=1e-8)
    np.testing.assert_array_equal(d.gyro_bias, 0.0)
    np.testing.assert_array_equal(d.accel_bias, 0.0)


def test_at_rest_the_accelerometer_reads_up():
    keys = qs.from_euler("xyz", [[30, 0, 0], [30, 0, 0]], degrees=True)
    rest = qs.PoseSpline(keys, [0.0, 1.0], np.zeros((2, 3)), rotation="c3")
    d = simulate(rest, rate=10)
    up_in_body = _rot(keys[0]).apply([0.0, 0.0, 9.80665], inverse=True)
    np.testing.assert_allclose(d.accel, np.tile(up_in_body, (11, 1)), atol=1e-12)
    np.testing.assert_allclose(d.gyro, 0.0, atol=1e-12)


def test_rotation_spline_gives_gyroscope_only():
    keys = qs.from_rotvec([[0, 0, 0], [0.3, 0.1, 0], [0.5, 0.4, 0.2]])
    s = qs.C3Spline(keys, [0.0, 1.0, 2.0])
    d = simulate(s, rate=50, noise=ImuNoise(1e-3, 1e-4, 1e-2, 1e-3), seed=1)
    assert d.accel is None and d.accel_bias is None
    assert len(d) == 101 and d.times[-1] == 2.0
    t = np.linspace(0.1, 1.9, 19)
    np.testing.assert_allclose(simulate(s, times=t).gyro, _fd_body_rate(s, t), atol=2e-6)


def test_fitted_pose_is_a_motion():
    t = np.linspace(0.0, 4.0, 81)
    q = qs.from_rotvec(np.column_stack([np.sin(t), 0.3 * t, 0 * t]))
    f = qs.fit(t, q, positions=np.column_stack([t, t**2, np.cos(t)]), smoothing=1e-6)
    j = f.rotation.joints
    ts = ((j[:-1] + j[1:]) / 2)[1:-1:3]  # between joints, where the derivatives are smooth
    d = simulate(f, times=ts)
    np.testing.assert_allclose(d.gyro, _fd_body_rate(f.orientation, ts), atol=1e-6)
    pdd = _second_derivative(f.position, ts)
    expected = _rot(f.orientation(ts)).apply(pdd - G, inverse=True)
    np.testing.assert_allclose(d.accel, expected, atol=1e-6)


def test_lever_arm_and_mounting_against_the_sensors_own_motion(pose):
    mount = Rotation.from_euler("zyx", [50, -20, 110], degrees=True)
    r = np.array([0.3, -0.2, 0.15])
    sensor = SensorModel(rotation=mount, lever_arm=r)
    t = _away_from(pose.rotation.joints, np.linspace(0.3, 9.7, 157), 0.006)
    d = simulate(pose, times=t, sensor=sensor)

    def sensor_position(tt):
        return pose.position(tt) + _rot(pose.orientation(tt)).apply(r)

    pdd = _second_derivative(sensor_position, t)
    r_ws = _rot(pose.orientation(t)) * mount
    np.testing.assert_allclose(d.accel, r_ws.apply(pdd - G, inverse=True), atol=2e-7)

    def sensor_orientation(tt):
        r = _rot(pose.orientation(tt)) * mount
        xyzw = r.as_quat()
        return np.concatenate([xyzw[..., 3:], xyzw[..., :3]], axis=-1)

    np.testing.assert_allclose(d.gyro, _fd_body_rate(sensor_orientation, t), atol=2e-6)
    # the lever arm matters here (the test would pass without it otherwise)
    plain = simulate(pose, times=t, sensor=SensorModel(rotation=mount))
    assert np.abs(plain.accel - d.accel).max() > 1e-2


def test_time_offset_sign():
    keys = qs.from_rotvec([[0, 0, 0], [0.3, 0.1, 0], [0.5, 0.4, 0.2], [0.1, 0.9, 0.3]])
    pose = qs.PoseSpline(
        keys, [0.0, 1.0, 2.0, 3.0], np.arange(12.0).reshape(4, 3) ** 1.5, rotation="c3"
    )
    t = np.linspace(0.5, 2.0, 16)
    shifted = simulate(pose, times=t, sensor=SensorModel(time_offset=0.25))
    direct = simulate(pose, times=t + 0.25)
    np.testing.assert_array_equal(shifted.times, t)
    np.testing.assert_allclose(shifted.gyro, direct.gyro, rtol=0, atol=1e-14)
    np.testing.assert_allclose(shifted.accel, direct.accel, rtol=0, atol=1e-12)
    # with rate=, the samples are placed so that the motion's domain is covered
    d = simulate(pose, rate=10, sensor=SensorModel(time_offset=0.25))
    assert d.times[0] == pytest.approx(-0.25) and d.times[-1] == pytest.approx(2.75)


def test_scale_misalignment_and_initial_bias_come_before_noise(pose):
    mg = np.array([[1.01, 0.002, -0.003], [0.0, 0.98, 0.004], [0.001, 0.0, 1.02]])
    sensor = SensorModel(
        gyro_matrix=mg,
        accel_matrix=[1.1, 0.9, 1.0],
        gyro_bias=[0.01, -0.02, 0.03],
        accel_bias=[0.1, 0.2, -0.3],
    )
    t = np.linspace(0.5, 9.5, 50)
    ideal = simulate(pose, times=t)
    d = simulate(pose, times=t, sensor=sensor, noise=ImuNoise(0, 1e-3, 0, 1e-2), seed=3)
    np.testing.assert_allclose(d.gyro - d.gyro_bias, ideal.gyro @ mg.T, atol=1e-14)
    np.testing.assert_allclose(d.accel - d.accel_bias, ideal.accel * [1.1, 0.9, 1.0], atol=1e-13)
    np.testing.assert_array_equal(d.gyro_bias[0], [0.01, -0.02, 0.03])
    np.testing.assert_array_equal(d.accel_bias[0], [0.1, 0.2, -0.3])
    assert np.all(np.abs(np.diff(d.gyro_bias, axis=0)) > 0)


def test_reproducible_by_seed_and_streams_are_independent(pose):
    n = ImuNoise(1e-3, 1e-4, 1e-2, 1e-3)
    a = simulate(pose, rate=50, noise=n, seed=11)
    b = simulate(pose, rate=50, noise=n, seed=11)
    c = simulate(pose, rate=50, noise=n, seed=12)
    np.testing.assert_array_equal(a.gyro, b.gyro)
    np.testing.assert_array_equal(a.accel, b.accel)
    assert np.abs(a.gyro - c.gyro).min() > 0
    gyro_only = simulate(pose, rate=50, noise=ImuNoise(1e-3, 1e-4), seed=11)
    np.testing.assert_array_equal(gyro_only.gyro, a.gyro)
    assert simulate(pose, rate=50, noise=n, seed=np.random.default_rng(11)).gyro.shape == (
        len(a),
        3,
    )


# ---- the noise model against its Allan deviation --------------------------------------------


def _rest(duration):
    keys = np.tile([1.0, 0.0, 0.0, 0.0], (2, 1))
    return qs.PoseSpline(keys, [0.0, duration], np.zeros((2, 3)), rotation="slerp")


def test_white_noise_density_is_the_allan_deviation_at_one_second():
    # Kalibr: sigma_d = sigma * sqrt(rate); ADEV(tau) = sigma / sqrt(tau)
    noise = ImuNoise(gyroscope_noise_density=2e-3, accelerometer_noise_density=3e-2)
    d = simulate(_rest(4000.0), rate=100, noise=noise, seed=5)
    y = np.hstack([d.gyro, d.accel])
    taus, adev = allan_deviation(y, 100, taus=[0.1, 1.0, 10.0])
    density = np.array([2e-3] * 3 + [3e-2] * 3)
    assert np.all(np.abs(adev[1] / density - 1) < 0.1)
    slope = np.polyfit(np.log(taus), np.log(adev), 1)[0]
    assert np.all(np.abs(slope + 0.5) < 0.05)


def test_bias_random_walk_gives_the_plus_half_slope():
    # a random walk of density sigma_b: ADEV(tau) = sigma_b sqrt(tau / 3)
    noise = ImuNoise(gyroscope_random_walk=1e-4, accelerometer_random_walk=3e-3)
    duration = 20000.0
    d = simulate(_rest(duration), rate=10, noise=noise, seed=6)
    y = np.hstack([d.gyro, d.accel])
    taus, adev = allan_deviation(y, 10, taus=np.logspace(1, np.log10(duration / 30), 8))
    slope = np.polyfit(np.log(taus), np.log(adev), 1)[0]
    assert np.all(np.abs(slope - 0.5) < 0.15)
    assert abs(slope.mean() - 0.5) < 0.05
    level = adev[3] / (np.array([1e-4] * 3 + [3e-3] * 3) * np.sqrt(taus[3] / 3))
    assert np.all(np.abs(level - 1) < 0.15)


# ---- bad input --------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        (dict(), ValueError, "exactly one"),
        (dict(rate=10, times=[1.0]), ValueError, "exactly one"),
        (dict(rate=0), ValueError, "rate"),
        (dict(rate="fast"), TypeError, "rate"),
        (dict(times=[1.0, 2.0, 11.0]), ValueError, r"times\[2\] = 11.0 is outside the motion"),
        (dict(times=[-0.5]), ValueError, "outside the motion's domain"),
        (dict(times=[1.0, 1.0]), ValueError, "not strictly increasing"),
        (dict(times=[1.0, np.nan]), ValueError, "not finite"),
        (dict(times=[]), ValueError, "non-empty"),
        (dict(times=[[1.0, 2.0]]), ValueError, "1-D"),
        (dict(rate=10, noise="loud"), TypeError, "noise"),
        (dict(rate=10, noise={"gyroscope_noise_density": 1e-3}), ValueError, "missing keys"),
        (dict(rate=10, sensor="imu"), TypeError, "sensor"),
        (dict(rate=10, seed="abc"), TypeError, "seed"),
        (dict(rate=10, seed=-1), ValueError, "seed"),
        (dict(rate=10, gravity=[0, 9.8]), ValueError, "gravity"),
        (dict(rate=10, gravity=[0, 0, np.inf]), ValueError, "gravity"),
        (dict(times=[10.4], sensor=SensorModel(time_offset=0.2)), ValueError, "time_offset"),
        (dict(times=[5.0], noise=ImuNoise(1e-3)), ValueError, "sample rate"),
    ],
)
def test_bad_input(pose, kwargs, exc, match):
    with pytest.raises(exc, match=match):
        simulate(pose, **kwargs)


def test_bad_motion_and_bad_sensor_values():
    with pytest.raises(TypeError, match="motion"):
        simulate(np.zeros((3, 4)), rate=10)
    with pytest.raises(ValueError, match="gyroscope_noise_density"):
        ImuNoise(gyroscope_noise_density=-1.0)
    for kwargs, match in [
        (dict(rotation=[0, 0, 0, 0]), "rotation"),
        (dict(rotation=[1, 0, 0]), "rotation"),
        (dict(lever_arm=[0, np.nan, 0]), "lever_arm"),
        (dict(gyro_matrix=np.eye(2)), "gyro_matrix"),
        (dict(time_offset=np.inf), "time_offset"),
    ]:
        with pytest.raises(ValueError, match=match):
            SensorModel(**kwargs)


def test_extrapolating_motion_accepts_times_outside():
    keys = qs.from_rotvec([[0, 0, 0], [0, 0, 1.0]])
    pose = qs.PoseSpline(
        keys, [0.0, 1.0], [[0, 0, 0], [1, 0, 0]], rotation="slerp", extrapolate="linear"
    )
    d = simulate(pose, times=[-1.0, 0.5, 2.0])
    np.testing.assert_allclose(d.gyro, [[0, 0, 1.0]] * 3, atol=1e-12)


def test_blocks_do_not_change_the_result(pose, monkeypatch):
    sensor = SensorModel(rotation=[0.9, 0.1, -0.3, 0.2], lever_arm=[0.1, 0.2, 0.3])
    noise = ImuNoise(1e-3, 1e-4, 1e-2, 1e-3)
    whole = simulate(pose, rate=20, sensor=sensor, noise=noise, seed=4)
    monkeypatch.setattr(simulation, "_BLOCK", 7)
    blocks = simulate(pose, rate=20, sensor=sensor, noise=noise, seed=4)
    np.testing.assert_array_equal(blocks.gyro, whole.gyro)
    np.testing.assert_array_equal(blocks.accel, whole.accel)


def _motions():
    rng = np.random.default_rng(8)
    q = qs.from_rotvec(_smooth(rng, np.arange(8.0), 0.5))
    p = _smooth(rng, np.arange(8.0), 1.0)
    return {
        "ScrewSpline": qs.ScrewSpline(q, np.arange(8.0), p, smooth=True),
        "PoseBSpline se3": qs.PoseBSpline(q, p, dt=1.0, order=5),
        "PoseBSpline split": qs.PoseBSpline(q, p, dt=1.0, order=4, formulation="split"),
        "PoseSpline squad": qs.PoseSpline(q, np.arange(8.0), p, rotation="squad"),
    }


@pytest.mark.parametrize("name", list(_motions()))
def test_every_pose_kind_with_a_lever_arm(name):
    m = _motions()[name]
    r = np.array([0.2, -0.1, 0.25])
    mount = Rotation.from_rotvec([0.3, -0.5, 1.1])
    joints = m.joints if hasattr(m, "joints") else m.rotation.joints
    a, b = m.domain
    t = _away_from(joints, np.linspace(a + 0.05, b - 0.05, 60), 0.006)
    d = simulate(m, times=t, sensor=SensorModel(rotation=mount, lever_arm=r))

    def sensor_position(tt):
        return m.position(tt) + _rot(m.orientation(tt)).apply(r)

    pdd = _second_derivative(sensor_position, t)
    r_ws = _rot(m.orientation(t)) * mount
    np.testing.assert_allclose(d.accel, r_ws.apply(pdd - G, inverse=True), atol=1e-6)

    def sensor_orientation(tt):
        xyzw = (_rot(m.orientation(tt)) * mount).as_quat()
        return np.concatenate([xyzw[..., 3:], xyzw[..., :3]], axis=-1)

    np.testing.assert_allclose(d.gyro, _fd_body_rate(sensor_orientation, t), atol=1e-5)


def test_bias_steps_follow_the_actual_intervals():
    # irregular stamps: the random walk steps by sigma_b * sqrt(dt_k) over each interval
    dt = np.tile([0.01, 0.04], 100_000)
    t = np.concatenate([[0.0], np.cumsum(dt)])
    d = simulate(_rest(t[-1]), times=t, noise=ImuNoise(gyroscope_random_walk=0.5), seed=9)
    steps = np.diff(d.gyro_bias, axis=0)
    short, long = steps[0::2], steps[1::2]
    np.testing.assert_allclose(np.std(short, axis=0), 0.5 * np.sqrt(0.01), rtol=0.02)
    np.testing.assert_allclose(np.std(long, axis=0), 0.5 * np.sqrt(0.04), rtol=0.02)
    np.testing.assert_allclose(d.gyro, d.gyro_bias, atol=1e-12)  # no white noise asked for
