"""
Working with scipy
==================

scipy ``Rotation`` objects go straight in; with clamped ends the natural spline *is* scipy's
``RotationSpline``, and its body-frame rates are what ``RotationSpline(t, 1)`` returns.
"""

import matplotlib.pyplot as plt
import numpy as np
import quatspline as qs
from scipy.spatial.transform import Rotation, RotationSpline

keys = Rotation.random(7, random_state=2)
times = np.array([0.0, 0.5, 1.3, 2.0, 2.2, 3.1, 4.0])

ours = qs.NaturalSpline(keys, times, ends="clamped")
theirs = RotationSpline(times, keys)
t = np.linspace(0, 4, 801)

# values: compare as rotations (q and -q are the same)
gap = qs.angle_between(ours(t), qs.from_scipy(theirs(t)), degrees=True)
print(f"largest angle between the two: {gap.max():.2e} degrees")

# %%
# Rates: scipy's ``order=1`` is the body frame
# --------------------------------------------

wb = ours.angular_velocity(t, frame="body")
fig, ax = plt.subplots(figsize=(8, 3))
ax.plot(t, wb, lw=2, alpha=0.5, label=["quatspline ωx", "ωy", "ωz"])
ax.plot(t, theirs(t, 1), "k:", lw=1, label=["scipy", "", ""])
ax.set_xlabel("t (s)")
ax.set_ylabel("body rate (rad/s)")
ax.legend(fontsize=8, ncol=2)
fig.tight_layout()
print("largest rate difference:", np.abs(wb - theirs(t, 1)).max())

# %%
# And back
# --------
# Results are arrays; :func:`quatspline.to_scipy` turns them into a ``Rotation``.

r = qs.to_scipy(ours([0.25, 0.75]))
print(r.as_euler("xyz", degrees=True))
plt.show()
