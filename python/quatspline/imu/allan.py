"""The overlapping Allan deviation of sensor samples: how noise averages out over time."""

from __future__ import annotations

import numpy as np

from .._util import checks
from .._util.arrays import as_real

__all__ = ["allan_deviation"]


def allan_deviation(samples, rate, taus=None) -> tuple[np.ndarray, np.ndarray]:
    r"""The overlapping Allan deviation of regularly spaced samples.

    With :math:`\tau_0 = 1/\text{rate}`, :math:`\theta_k = \tau_0 \sum_{i<k} y_i`
    (k = 0 … N) and :math:`\tau = m \tau_0`,

    .. math::

        \sigma^2(\tau) = \frac{1}{2 \tau^2 (N + 1 - 2m)}
            \sum_{k=0}^{N - 2m} (\theta_{k+2m} - 2\theta_{k+m} + \theta_k)^2

    (IEEE Std 952-1997, annex C; Riley, "Handbook of Frequency Stability Analysis", NIST
    SP 1065, 2008, eq. 14). White noise of density σ gives :math:`\sigma/\sqrt\tau`
    (slope −½ on a log-log plot), a random walk of density :math:`\sigma_b` gives
    :math:`\sigma_b \sqrt{\tau/3}` (slope +½): the Kalibr ``imu.yaml`` densities are read
    off these lines (at τ = 1 s and τ = 3 s).

    Parameters
    ----------
    samples : array_like, shape (N,) or (N, k)
        Samples at a constant rate (e.g. a gyroscope at rest), one column per axis.
    rate : float
        Sample rate, Hz.
    taus : array_like, optional
        Averaging times in seconds, each rounded to a whole number m of samples,
        1 ≤ m ≤ (N − 1)/2. Default: about ten per decade from τ₀ to the longest.

    Returns
    -------
    taus : numpy.ndarray, shape (T,)
        The averaging times used (m / rate, increasing, unique).
    deviation : numpy.ndarray, shape (T,) or (T, k)
        The Allan deviation at each τ (units of the samples).

    Raises
    ------
    ValueError
        Fewer than three samples, non-finite samples, a τ outside the range above, a bad rate.
    TypeError
        Values that are not numbers.

    Examples
    --------
    White noise of density 0.01 per √Hz sampled at 100 Hz: 0.01 at τ = 1 s.

    >>> import numpy as np
    >>> from quatspline.imu import allan_deviation
    >>> y = np.random.default_rng(0).standard_normal(200_000) * 0.01 * np.sqrt(100)
    >>> tau, adev = allan_deviation(y, 100, taus=[1.0])
    >>> tau, bool(abs(adev[0] - 0.01) < 0.0005)
    (array([1.]), True)
    """
    r = checks.real(rate, "rate", positive=True)
    y = as_real(samples, "samples")
    if y.ndim not in (1, 2):
        raise ValueError(f"samples: expected shape (N,) or (N, k), got {y.shape}")
    n = y.shape[0]
    if n < 3:
        raise ValueError(f"samples: expected at least 3 samples, got {n}")
    if not np.all(np.isfinite(y)):
        raise ValueError("samples: not finite")
    top = (n - 1) // 2
    if taus is None:
        m = np.unique(np.round(np.logspace(0, np.log10(top), int(10 * np.log10(top)) + 1)))
    else:
        tau = as_real(taus, "taus").reshape(-1)
        if not np.all(np.isfinite(tau)):
            raise ValueError("taus: not finite")
        m = np.round(tau * r)
        bad = (m < 1) | (m > top)
        if np.any(bad):
            k = int(np.flatnonzero(bad)[0])
            raise ValueError(
                f"taus: taus[{k}] = {tau[k]:g} s is outside [{1 / r:g}, {top / r:g}] s "
                f"(1 to (N − 1)/2 samples)"
            )
        m = np.unique(m)
    m = m.astype(np.int64)
    yy = y.reshape(n, -1)
    yy = yy - yy.mean(axis=0)  # a constant does not change σ(τ); removing it saves digits
    theta = np.zeros((n + 1, yy.shape[1]))
    np.cumsum(yy, axis=0, out=theta[1:])
    theta /= r
    out = np.empty((m.size, yy.shape[1]))
    for i, mi in enumerate(m):
        d = theta[2 * mi :] - 2.0 * theta[mi:-mi] + theta[: -2 * mi]
        tau_i = mi / r
        out[i] = np.sqrt(np.sum(d * d, axis=0) / (2.0 * tau_i * tau_i * d.shape[0]))
    taus_out = m / r
    return taus_out, (out[:, 0] if y.ndim == 1 else out)
