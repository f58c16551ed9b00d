"""A rotation spline has no positions, so no accelerometer: a sensor model that describes one
is refused with a message naming the missing positions (it was silently ignored)."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from quatspline.imu import SensorModel, simulate


@pytest.mark.parametrize(
    "sensor, name",
    [
        (SensorModel(lever_arm=[0.1, 0.0, 0.0]), "lever_arm"),
        (SensorModel(accel_bias=[0.0, 0.1, 0.0]), "accel_bias"),
        (SensorModel(accel_matrix=[1.01, 1.0, 1.0]), "accel_matrix"),
    ],
)
def test_accelerometer_terms_of_a_rotation_spline_name_the_missing_positions(sensor, name):
    t = np.linspace(0.0, 2.0, 5)
    rot = qs.spline("slerp", qs.from_rotvec(np.outer(t, [0.0, 0.0, 1.0])), t)
    with pytest.raises(ValueError, match=f"sensor: {name}.*needs positions"):
        simulate(rot, rate=50, sensor=sensor)
    # the gyroscope alone is still simulated, and a pose spline takes the same sensor
    assert simulate(rot, rate=50).accel is None
    pose = qs.PoseSpline(qs.from_rotvec(np.outer(t, [0.0, 0.0, 1.0])), t, np.zeros((5, 3)))
    assert simulate(pose, rate=50, sensor=sensor).accel is not None
