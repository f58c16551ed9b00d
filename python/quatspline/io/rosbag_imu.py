"""``sensor_msgs/Imu`` messages in ROS 1 bags, ROS 2 bags (sqlite3) and MCAP files, read and
written with the ``rosbags`` library (``pip install 'quatspline[bag]'``); the bag rules
(which files are read, how an existing bag is replaced) are those of
:mod:`quatspline.io.rosbag`.

Reading: ``angular_velocity`` (rad/s) → ``gyro``, ``linear_acceleration`` (m/s²) →
``accel``; times are the header stamps (``stamp="header"``, default) or the bag's receive
times (``stamp="bag"``), in seconds, with the integer nanoseconds kept in ``stamps_ns``. By
the message's convention, element 0 of a covariance equal to −1 means the field holds no
estimate: a topic whose ``linear_acceleration_covariance[0]`` is −1 in every message gives a
gyroscope-only record (−1 in some messages only is an error); −1 in
``angular_velocity_covariance[0]`` is an error (no angular rate). The ``orientation`` is
kept in ``extra["orientation"]`` (w, x, y, z) when every message has one.

Writing: one message per sample on ``topic`` (``frame_id`` in each header, receive time =
stamp); the angular-velocity and acceleration covariances are written as unknown (all
zeros); without an orientation in ``extra["orientation"]`` the orientation is (0, 0, 0, 0)
with ``orientation_covariance[0] = -1`` (no estimate), and a gyroscope-only record has
``linear_acceleration`` zero with ``linear_acceleration_covariance[0] = -1``.
"""

from __future__ import annotations

import numpy as np

from ._imu_common import check_imu_for_writing, finish_imu, integer_stamps
from .inertial import ImuData
from .rosbag import (
    check_stamp,
    choose_topic,
    field,
    int64_stamps,
    messages,
    number,
    open_bag,
    stamp_of,
    write_bag,
)
from .trajectory import TrajectoryError

MSGTYPE = "sensor_msgs/msg/Imu"


def _no_estimate(where, msg, name: str) -> bool:
    """Whether the covariance ``name`` says "no estimate" (element 0 equal to −1)."""
    cov = field(where, msg, name)
    try:
        c0 = float(cov[0])
    except (TypeError, ValueError, IndexError, KeyError):
        raise TrajectoryError(f"{where}: field {name!r} is not an array of numbers") from None
    return c0 == -1.0


def read(
    path, topic: str | None = None, stamp: str = "header", sort: bool = False, dedupe: bool = False
) -> ImuData:
    """Reads the ``sensor_msgs/Imu`` messages on ``topic`` (may be left out when the bag has
    one such topic); see the module."""
    check_stamp(stamp)
    ns, gyro, accel, quats = [], [], [], []
    no_accel = no_orientation = None
    with open_bag(path) as reader:
        topic, chosen, _ = choose_topic(
            path, reader, topic, (MSGTYPE,), "carries no inertial measurements"
        )
        for where, bag_ns, msg in messages(path, reader, topic, chosen):
            if _no_estimate(where, msg, "angular_velocity_covariance"):
                raise TrajectoryError(
                    f"{where}: angular_velocity_covariance[0] is -1: the message holds no "
                    "angular rate"
                )
            missing = _no_estimate(where, msg, "linear_acceleration_covariance")
            if no_accel is None:
                no_accel = missing
            elif missing != no_accel:
                raise TrajectoryError(
                    f"{where}: linear_acceleration_covariance[0] is "
                    f"{'-1 (no acceleration)' if missing else 'not -1'}, unlike the earlier "
                    "messages of the topic"
                )
            no_orientation = no_orientation or _no_estimate(where, msg, "orientation_covariance")
            ns.append(stamp_of(where, msg, stamp, bag_ns))
            gyro.append([number(where, msg, f"angular_velocity.{c}") for c in "xyz"])
            accel.append([number(where, msg, f"linear_acceleration.{c}") for c in "xyz"])
            if not no_orientation:
                quats.append([number(where, msg, f"orientation.{c}") for c in "wxyz"])
    if not ns:
        raise TrajectoryError(f"{path}: no messages on topic {topic!r}")
    stamps = int64_stamps(path, topic, ns)
    extra = {} if no_orientation else {"orientation": np.array(quats)}
    return finish_imu(
        path,
        stamps * 1e-9,
        np.array(gyro),
        None if no_accel else np.array(accel),
        np.arange(1, len(ns) + 1),
        sort,
        dedupe,
        name=topic,
        stamps_ns=stamps,
        extra=extra,
    )


def write(
    path, data: ImuData, topic: str = "/imu", frame_id: str = "imu", ros: int | None = None
) -> None:
    """Writes ``sensor_msgs/Imu`` messages on ``topic``: ``.bag`` → ROS 1, ``.mcap`` → a
    ROS 2 MCAP file, any other path → a ROS 2 bag directory (sqlite3); see the module."""
    check_imu_for_writing(path, data, "ROS bag IMU", extra=("orientation",))
    n = len(data)
    stamps = integer_stamps(path, data, "ROS bag")
    if stamps[0] < 0:
        raise ValueError(f"{path}: times before 0 s cannot be written (ROS stamps are unsigned)")
    quats = data.extra.get("orientation")
    if quats is not None:
        quats = np.asarray(quats, dtype=float)
        if quats.shape != (n, 4):
            raise ValueError(
                f"{path}: extra 'orientation' has shape {quats.shape}, expected ({n}, 4)"
            )
    gyro, accel = data.gyro, data.accel
    unknown, absent = np.zeros(9), np.zeros(9)
    absent[0] = -1.0

    def make(types, k, header):
        vec, quat = types["geometry_msgs/msg/Vector3"], types["geometry_msgs/msg/Quaternion"]
        if quats is None:
            q, q_cov = quat(x=0.0, y=0.0, z=0.0, w=0.0), absent
        else:
            w, x, y, z = (float(v) for v in quats[k])
            q, q_cov = quat(x=x, y=y, z=z, w=w), unknown
        g = vec(x=float(gyro[k, 0]), y=float(gyro[k, 1]), z=float(gyro[k, 2]))
        if accel is None:
            a, a_cov = vec(x=0.0, y=0.0, z=0.0), absent
        else:
            a, a_cov = (
                vec(x=float(accel[k, 0]), y=float(accel[k, 1]), z=float(accel[k, 2])),
                unknown,
            )
        return types[MSGTYPE](
            header=header,
            orientation=q,
            orientation_covariance=q_cov.copy(),
            angular_velocity=g,
            angular_velocity_covariance=unknown.copy(),
            linear_acceleration=a,
            linear_acceleration_covariance=a_cov.copy(),
        )

    write_bag(path, ros, topic, MSGTYPE, stamps, frame_id, make)
