"""Where the IMU sits on the body and how it distorts what it measures."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._util import checks
from .._util.arrays import as_real, is_scipy_rotation, rotation_to_wxyz
from ..core.algebra import multiply, rotate
from ..core.convert import as_matrix

__all__ = ["SensorModel"]


def _vector(value, name: str) -> np.ndarray:
    v = as_real(value, name)
    if v.shape != (3,):
        raise ValueError(f"{name}: expected 3 numbers, got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name}: not finite")
    return v.copy()


def _matrix(value, name: str) -> np.ndarray | None:
    if value is None:
        return None
    m = as_real(value, name)
    if m.shape == (3,):
        m = np.diag(m)
    if m.shape != (3, 3):
        raise ValueError(f"{name}: expected 3 scale factors or a 3×3 matrix, got shape {m.shape}")
    if not np.all(np.isfinite(m)):
        raise ValueError(f"{name}: not finite")
    return m.copy()


def _rotation(value) -> np.ndarray:
    q = rotation_to_wxyz(value) if is_scipy_rotation(value) else as_real(value, "rotation")
    if q.shape != (4,):
        raise ValueError(f"rotation: expected one quaternion (w, x, y, z), got shape {q.shape}")
    n = float(np.linalg.norm(q))
    if not np.isfinite(n) or n == 0.0:
        raise ValueError("rotation: expected a finite, non-zero quaternion")
    return q / n


@dataclass(frozen=True, eq=False)
class SensorModel:
    r"""How an IMU is mounted on a moving body and how it distorts its readings.

    Frames: the motion's orientation :math:`R(t)` maps body coordinates to world
    coordinates and :math:`p(t)` is the body origin in the world
    (:math:`x_w = R x_b + p`). The sensor frame is fixed to the body: its axes in body
    coordinates are the columns of :math:`R_{bs}` (``rotation``) and its origin is the body
    point :math:`r` (``lever_arm``), so the sensor's pose in the world is
    :math:`(R R_{bs},\ p + R r)`. With :math:`\omega, \dot\omega` the body-frame angular
    velocity and acceleration, :math:`g` the gravity vector and :math:`\ddot p` the world
    acceleration of the body origin, the ideal sensor reads

    .. math::

        \omega_s = R_{bs}^T \omega, \qquad
        f_s = R_{bs}^T \left( R^T (\ddot p - g) + \dot\omega \times r
              + \omega \times (\omega \times r) \right),

    the specific force of the sensor's own origin (at rest on a table it reads
    :math:`-g`, i.e. +9.81 m/s² upwards). The measured values are then

    .. math::

        \tilde\omega = M_g \omega_s + b_g + n_g, \qquad
        \tilde f = M_a f_s + b_a + n_a,

    with the scale-and-misalignment matrices :math:`M` (identity by default) applied before
    the biases :math:`b` and the noise :math:`n` (:class:`quatspline.io.ImuNoise`).

    Time offset: a sample stamped :math:`t` on the sensor's clock measures the motion at
    :math:`t + \delta` (``time_offset`` = δ). A positive δ means the sensor's stamps run
    behind the motion's clock.

    Parameters
    ----------
    rotation : array_like, shape (4,), or scipy Rotation, default identity
        :math:`R_{bs}` as a quaternion (w, x, y, z), body from sensor (normalised here).
    lever_arm : array_like, shape (3,), default (0, 0, 0)
        The sensor's origin in body coordinates, in the motion's length unit.
    time_offset : float, default 0
        δ in seconds (see above).
    gyro_matrix, accel_matrix : array_like, shape (3, 3) or (3,), optional
        Scale and misalignment :math:`M_g`, :math:`M_a`; three numbers are a diagonal
        (pure scale factors). None is the identity.
    gyro_bias, accel_bias : array_like, shape (3,), default (0, 0, 0)
        The biases at the first sample (rad/s, m/s²); the noise model's random walks start
        from them.

    Raises
    ------
    ValueError
        A value of the wrong shape, not finite, or a zero quaternion.
    TypeError
        Values that are not numbers.

    Examples
    --------
    A sensor turned 90° about the body's z axis reads the body's x rate on its −y axis:

    >>> import numpy as np
    >>> import quatspline as qs
    >>> from quatspline.imu import SensorModel
    >>> s = SensorModel(rotation=qs.from_axis_angle([0, 0, 1], np.pi / 2))
    >>> s.to_sensor([1.0, 0.0, 0.0]).round(12)
    array([ 0., -1.,  0.])
    """

    rotation: np.ndarray = (1.0, 0.0, 0.0, 0.0)
    lever_arm: np.ndarray = (0.0, 0.0, 0.0)
    time_offset: float = 0.0
    gyro_matrix: np.ndarray | None = None
    accel_matrix: np.ndarray | None = None
    gyro_bias: np.ndarray = (0.0, 0.0, 0.0)
    accel_bias: np.ndarray = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        put = object.__setattr__
        put(self, "rotation", _rotation(self.rotation))
        put(self, "lever_arm", _vector(self.lever_arm, "lever_arm"))
        put(self, "time_offset", checks.real(self.time_offset, "time_offset"))
        put(self, "gyro_matrix", _matrix(self.gyro_matrix, "gyro_matrix"))
        put(self, "accel_matrix", _matrix(self.accel_matrix, "accel_matrix"))
        put(self, "gyro_bias", _vector(self.gyro_bias, "gyro_bias"))
        put(self, "accel_bias", _vector(self.accel_bias, "accel_bias"))

    def __repr__(self) -> str:
        parts = [f"rotation={np.round(self.rotation, 6).tolist()}"]
        if np.any(self.lever_arm):
            parts.append(f"lever_arm={self.lever_arm.tolist()}")
        if self.time_offset:
            parts.append(f"time_offset={self.time_offset:g}")
        for name in ("gyro_matrix", "accel_matrix"):
            if getattr(self, name) is not None:
                parts.append(f"{name}=...")
        for name in ("gyro_bias", "accel_bias"):
            if np.any(getattr(self, name)):
                parts.append(f"{name}={getattr(self, name).tolist()}")
        return f"SensorModel({', '.join(parts)})"

    @property
    def matrix(self) -> np.ndarray:
        """:math:`R_{bs}` as a 3×3 matrix (body from sensor)."""
        return as_matrix(self.rotation)

    def to_sensor(self, vectors) -> np.ndarray:
        """Body-frame vectors (..., 3) in sensor coordinates, :math:`R_{bs}^T v`."""
        v = as_real(vectors, "vectors")
        if v.shape[-1:] != (3,):
            raise ValueError(f"vectors: expected shape (..., 3), got {v.shape}")
        return v @ self.matrix

    def sensor_pose(self, quats, positions=None):
        """The sensor's pose in the world from the body's: :math:`(R R_{bs},\\ p + R r)`.

        Parameters
        ----------
        quats : array_like, shape (..., 4)
            Body orientations (world from body).
        positions : array_like, shape (..., 3), optional
            Body origins in the world.

        Returns
        -------
        numpy.ndarray or (numpy.ndarray, numpy.ndarray)
            The sensor's orientations (world from sensor), and its origins when ``positions``
            is given.
        """
        q = multiply(quats, self.rotation)
        if positions is None:
            return q
        p = as_real(positions, "positions")
        return q, p + rotate(quats, self.lever_arm)
