"""
Keys in, smooth motion out
==========================

Four orientations given as Euler angles at uneven times, interpolated by the C³ spline, then
sampled with exact angular velocity in the world and the body frame.
"""

import matplotlib.pyplot as plt
import numpy as np
import quatspline as qs

keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [45, 0, 90], [45, 30, 120]], degrees=True)
times = [0.0, 1.0, 2.5, 3.0]

s = qs.C3Spline(keys, times, alpha=5 / 16, beta=0.0)
t, q = s.sample(rate=200)
print(s, "->", q.shape)
print("passes through the keys:", np.allclose(s(times), keys))

# %%
# Angular velocity in both frames
# -------------------------------
# The world-frame rate is what a fixed observer sees; the body-frame rate is what a gyroscope
# on the body measures (and what scipy's ``RotationSpline(t, 1)`` returns). Their norms agree.

w = s.angular_velocity(t)
wb = s.angular_velocity(t, frame="body")
fig, axes = plt.subplots(1, 2, figsize=(8, 3), sharey=True)
for ax, rate, title in zip(axes, (w, wb), ("world frame", "body frame")):
    for k, name in enumerate("xyz"):
        ax.plot(t, rate[:, k], label=f"ω{name}")
    ax.plot(t, np.linalg.norm(rate, axis=1), "k--", lw=1, label="|ω|")
    for tk in times:
        ax.axvline(tk, color="0.85", lw=0.8, zorder=0)
    ax.set_title(title)
    ax.set_xlabel("t (s)")
axes[0].set_ylabel("rad/s")
axes[0].legend(fontsize=8)
fig.tight_layout()

# %%
# Euler angles of the result
# --------------------------
# Converting back uses the same sequence convention as scipy.

angles = qs.as_euler(q, "xyz", degrees=True)
fig2, ax2 = plt.subplots(figsize=(8, 3))
ax2.plot(t, angles, label=["roll (x)", "pitch (y)", "yaw (z)"])
ax2.plot(times, qs.as_euler(keys, "xyz", degrees=True), "ko", ms=4)
ax2.set_xlabel("t (s)")
ax2.set_ylabel("degrees")
ax2.legend(fontsize=8)
fig2.tight_layout()
plt.show()
