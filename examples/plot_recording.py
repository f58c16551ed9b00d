"""
A real recording: held-out accuracy and a pose spline
=====================================================

The recording that ships with the package (TUM RGB-D fr1/xyz: a handheld camera under motion
capture at 100 Hz). Every 10th frame is kept as a key; the nine frames between are predicted
by each method and compared with the measurement.
"""

import matplotlib.pyplot as plt
import numpy as np
import quatspline as qs

rec = qs.examples.load_recording()
t = rec.times - rec.times[0]
idx = np.arange(0, len(t), 10)
rest = np.setdiff1d(np.arange(idx[-1] + 1), idx)

for name in ["slerp", "squad", "natural", "c3"]:
    s = qs.spline(name, rec.quats[idx], t[idx])
    err = qs.angle_between(s(t[rest]), rec.quats[rest], degrees=True)
    print(f"{name:8s} median {np.median(err):.4f}°  p95 {np.percentile(err, 95):.4f}°")

# %%
# Orientation and position together
# ---------------------------------
# :class:`quatspline.PoseSpline` takes ``(quats, times, positions)``, like the spline classes.

assert rec.positions is not None
pose = qs.PoseSpline(rec.quats[idx], t[idx], rec.positions[idx], rotation="c3")
ts = np.linspace(0, 8, 800)
x = pose.position(ts)
nose = pose.transform_points(ts[::40], [[0.0, 0.0, 0.1]])[:, 0]
fig = plt.figure(figsize=(6, 5))
ax = fig.add_subplot(projection="3d")
ax.plot(x[:, 0], x[:, 1], x[:, 2], lw=1)
for a, b in zip(x[::40], nose):
    ax.plot([a[0], b[0]], [a[1], b[1]], [a[2], b[2]], "r-", lw=1)
ax.set_xlabel("x (m)")
ax.set_ylabel("y (m)")
ax.set_zlabel("z (m)")
ax.set_title("camera path, first 8 s, with its viewing direction")
fig.tight_layout()
plt.show()
