"""
How smooth is each method?
==========================

The same six keys at uneven times through five methods. The angular acceleration shows which
methods are C² (continuous acceleration), and :func:`quatspline.continuity` certifies the
order reached at every joint.
"""

import matplotlib.pyplot as plt
import numpy as np
import quatspline as qs

rng = np.random.default_rng(4)
keys = qs.from_rotvec(np.cumsum(rng.normal(scale=0.6, size=(6, 3)), axis=0))
times = np.array([0.0, 0.7, 1.9, 2.4, 3.6, 4.0])
t = np.linspace(times[0], times[-1], 2001)

methods = ["slerp", "squad", "catmull_rom", "natural", "c3"]
fig, ax = plt.subplots(figsize=(8, 3.5))
for name in methods:
    s = qs.spline(name, keys, times)
    ax.plot(t, np.linalg.norm(s.angular_acceleration(t), axis=1), label=name, lw=1.2)
for tk in times:
    ax.axvline(tk, color="0.85", lw=0.8, zorder=0)
ax.set_yscale("log")
ax.set_xlabel("t (s)")
ax.set_ylabel("|dω/dt| (rad/s²)")
ax.legend(fontsize=8)
fig.tight_layout()

# %%
# The certificate
# ---------------
# For each joint, the largest derivative order whose jump is below the tolerance, and the
# relative jump of the next order.

for name in methods:
    s = qs.spline(name, keys, times)
    joints = qs.continuity(s)
    orders = [j.order for j in joints]
    print(f"{name:12s} claimed C{s.continuity}  measured {orders}")
plt.show()
