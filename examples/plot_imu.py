"""
A real IMU against motion capture
=================================

RepoIMU (bundled in the repository's ``data/`` folder, 30 s) records a handheld IMU at
100 Hz under a Vicon motion-capture system: the Vicon orientation of the rigid body, and the
IMU's own gyroscope and accelerometer. Here the Vicon orientation is smoothed by a fit, the
gyroscope is calibrated against it (sensor rotation, bias, scale, time offset), and the
accelerometer is compared with the gravity the fitted orientation predicts.

Frames: the body frame is the Vicon rigid body's, the sensor frame the IMU's;
``ω_meas(t) = K R_bsᵀ ω_body(t + δ) + b``.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import quatspline as qs
import quatspline.io as qio

# the repository's data folder, from the repository or from its examples/ folder
DATA = next(
    b / "data" for b in (Path.cwd(), *Path.cwd().parents) if (b / "data" / "repoimu").is_dir()
)
path = DATA / "repoimu" / "repoIMU_first30s.csv"

vicon = qio.read(path)  # the Vicon orientation (a Trajectory)
imu = qio.read_imu(path)  # the IMU's gyroscope and accelerometer (an ImuData)
assert imu.accel is not None  # RepoIMU records both
print(f"{len(vicon)} Vicon orientations, {len(imu.times)} IMU samples")

# %%
# Calibrate the gyroscope
# -----------------------
# :func:`quatspline.imu.calibrate` smooths the motion capture by a fit (GCV) and estimates the
# parameters of the model above, with standard errors from the residuals. Thirty seconds of
# hand-held motion hardly excite the gyroscope's scale (the calibration warns when it is
# asked for a parameter the motion does not determine), so the scale is held at 1 here.

cal = qs.imu.calibrate(vicon, imu, estimate=("rotation", "bias", "time_offset"))
se = cal.standard_errors
angle = np.degrees(np.linalg.norm(qs.as_rotvec(cal.rotation)))
print(
    f"sensor rotation  {angle:.2f}° from the body frame (± {np.degrees(se['rotation']).max():.2f}°)"
)
print(f"gyro bias        {np.degrees(cal.gyro_bias).round(3)} °/s")
print(f"time offset      {cal.time_offset * 1e3:.2f} ms (± {se['time_offset'] * 1e3:.2f} ms)")
print(f"RMS residual     {np.degrees(cal.rms).round(3)} °/s per axis")

fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7, 6))
for k, ax in enumerate(axes):
    ax.plot(cal.times, np.degrees(cal.measured[:, k]), lw=0.8, label="measured")
    ax.plot(cal.times, np.degrees(cal.predicted[:, k]), lw=0.8, label="predicted from Vicon")
    ax.set_ylabel(f"ω_{'xyz'[k]} (°/s)")
axes[0].legend(loc="upper right")
axes[-1].set_xlabel("time (s)")
fig.suptitle("gyroscope: measured and predicted by the calibrated model")
fig.tight_layout()

# %%
# The accelerometer sees gravity
# ------------------------------
# A hand-held device accelerates little, so its specific force ``Rᵀ(p̈ − g)`` is mostly
# ``−Rᵀ g``: gravity (here ``(0, 0, −9.80665)`` m/s² in the Vicon frame) seen from the
# sensor. The fitted orientation and the calibrated sensor rotation predict it from the
# motion capture alone.

fit = qs.fit(vicon.times, vicon.quats)
inside = (imu.times + cal.time_offset >= fit.knots[0]) & (
    imu.times + cal.time_offset <= fit.knots[-1]
)
t = imu.times[inside]
sensor = qs.multiply(fit(t + cal.time_offset), cal.rotation)  # world ← sensor
predicted = qs.rotate(qs.conjugate(sensor), np.array([0.0, 0.0, 9.80665]))
measured = imu.accel[inside]
err = np.degrees(
    np.arccos(
        np.clip(
            np.sum(
                predicted
                / np.linalg.norm(predicted, axis=1, keepdims=True)
                * measured
                / np.linalg.norm(measured, axis=1, keepdims=True),
                axis=1,
            ),
            -1,
            1,
        )
    )
)
print(
    f"direction of gravity: median {np.median(err):.2f}°, 95th percentile "
    f"{np.percentile(err, 95):.2f}° between accelerometer and prediction"
)

fig, ax = plt.subplots(figsize=(7, 3))
for k in range(3):
    ax.plot(t, measured[:, k], lw=0.8, color=f"C{k}", label=f"a_{'xyz'[k]} measured")
    ax.plot(t, predicted[:, k], lw=1.2, ls="--", color=f"C{k}")
ax.set_xlabel("time (s)")
ax.set_ylabel("m/s²")
ax.set_title("accelerometer (solid) and −Rᵀg from the fitted Vicon orientation (dashed)")
ax.legend(loc="upper right", fontsize="small")
fig.tight_layout()
plt.show()
