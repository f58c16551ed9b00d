"""
Shaping a curve: the Beta spline's tension
==========================================

The Beta quaternion spline through the five vertices of the paper's Example 2, with the
tension β₂ at vertex 1 swept over 0.5, 2 and 4 (the paper's figure 4). Shown: where the body's
x axis points along the curve, as azimuth and elevation.
"""

import matplotlib.pyplot as plt
import numpy as np
import quatspline as qs

vertices = qs.examples.BETA_EXAMPLE2_VERTICES
fig, ax = plt.subplots(figsize=(7, 4))
for b12 in (0.5, 2.0, 4.0):
    beta2 = np.full(len(vertices), 0.5)
    beta2[1] = b12
    s = qs.BetaSpline(vertices, beta1=1.0, beta2=beta2, canonicalize=False)
    _, q = s.sample(n=400)
    x_axis = qs.rotate(q, [1.0, 0.0, 0.0])
    az = np.degrees(np.arctan2(x_axis[:, 1], x_axis[:, 0]))
    el = np.degrees(np.arcsin(np.clip(x_axis[:, 2], -1, 1)))
    ax.plot(az, el, label=f"β₂ at vertex 1 = {b12}")
ax.set_xlabel("azimuth of the body x axis (deg)")
ax.set_ylabel("elevation (deg)")
ax.legend(fontsize=8)
fig.tight_layout()

# %%
# The certificate says G¹ exactly, not G²: the Beta spline paper's G² claim does not hold on
# this data.

s = qs.BetaSpline(vertices, beta1=1.0, beta2=0.5, canonicalize=False)
for j in qs.continuity(s):
    print(f"joint {j.index}: G¹ residual {j.beta_g1_residual:.1e}, G² {j.beta_g2_residual:.3f}")
plt.show()
