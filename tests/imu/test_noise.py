"""The IMU noise model (Kalibr ``imu.yaml`` convention): discretisation and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from quatspline.io import ImuNoise

KEYS = (
    "gyroscope_noise_density",
    "gyroscope_random_walk",
    "accelerometer_noise_density",
    "accelerometer_random_walk",
)


def test_discretisation_follows_kalibr():
    # Kalibr wiki "IMU Noise Model": sigma_d = sigma / sqrt(dt), sigma_bd = sigma_b * sqrt(dt)
    n = ImuNoise(1e-3, 2e-5, 3e-2, 4e-4)
    dt = 1 / 400
    g, a = n.white_std(400)
    assert g == pytest.approx(1e-3 / math.sqrt(dt), rel=1e-15)
    assert a == pytest.approx(3e-2 / math.sqrt(dt), rel=1e-15)
    gb, ab = n.walk_std(dt)
    assert gb == pytest.approx(2e-5 * math.sqrt(dt), rel=1e-15)
    assert ab == pytest.approx(4e-4 * math.sqrt(dt), rel=1e-15)


def test_defaults_are_noiseless_and_kalibr_keys_round_trip():
    assert ImuNoise().white_std(100.0) == (0.0, 0.0)
    n = ImuNoise(gyroscope_noise_density=np.float32(0.5), accelerometer_random_walk=2)
    d = n.as_dict()
    assert tuple(d) == KEYS
    assert all(type(v) is float for v in d.values())
    extra = dict(d, rostopic="/imu0", update_rate=200.0)
    assert ImuNoise.from_dict(extra) == n


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        (dict(gyroscope_noise_density=-1e-3), ValueError, "gyroscope_noise_density"),
        (dict(accelerometer_random_walk=float("nan")), ValueError, "accelerometer_random_walk"),
        (dict(gyroscope_random_walk=float("inf")), ValueError, "gyroscope_random_walk"),
        (dict(accelerometer_noise_density="0.1"), TypeError, "accelerometer_noise_density"),
        (dict(gyroscope_noise_density=True), TypeError, "gyroscope_noise_density"),
    ],
)
def test_bad_densities(kwargs, exc, match):
    with pytest.raises(exc, match=match):
        ImuNoise(**kwargs)


def test_missing_keys_are_named():
    d = dict.fromkeys(KEYS, 0.1)
    del d["gyroscope_random_walk"], d["accelerometer_noise_density"]
    with pytest.raises(ValueError, match="gyroscope_random_walk, accelerometer_noise_density"):
        ImuNoise.from_dict(d)
    with pytest.raises(TypeError, match="mapping"):
        ImuNoise.from_dict([0.1] * 4)


@pytest.mark.parametrize(("method", "arg"), [("white_std", 0.0), ("walk_std", -0.01)])
def test_bad_rate_or_step(method, arg):
    with pytest.raises(ValueError, match="rate|dt"):
        getattr(ImuNoise(1.0), method)(arg)


def test_numbers_in_strings_as_yaml_gives_them():
    d = dict.fromkeys(KEYS, "1e-3")
    assert ImuNoise.from_dict(d) == ImuNoise(1e-3, 1e-3, 1e-3, 1e-3)
    d["gyroscope_random_walk"] = "small"
    with pytest.raises(ValueError, match="gyroscope_random_walk"):
        ImuNoise.from_dict(d)
