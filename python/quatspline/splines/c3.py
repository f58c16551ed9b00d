"""The interpolating C³ spline with shape parameters α and β (Rust ``spline/c3.rs``; Wang &
Zhou 2023, patent).

The patent's formulas were published as images and are lost; this is a reconstruction with
every stated property (documented in the mathematics pages).
"""

from __future__ import annotations

from .. import _core
from .base import Spline
from .keys import _keys, _per, _times

__all__ = ["C3Spline"]


C3_AUTO = (0.5, -3.0)


def c3_shape(alpha, beta):
    """Per-key (or per-segment) α, β arrays for the C³ spline; ``alpha="auto"`` is
    (1/2, −3) (see :class:`C3Spline`), ``beta=None`` is 0, or −3 with auto."""
    if isinstance(alpha, str):
        if alpha != "auto":
            raise ValueError(f"alpha: expected a number, numbers or 'auto', got {alpha!r}")
        alpha = C3_AUTO[0]
        if beta is None:
            beta = C3_AUTO[1]
    if beta is None:
        beta = 0.0
    return _per(alpha, "alpha"), _per(beta, "beta")


class C3Spline(Spline):
    """The interpolating C³ spline with shape parameters α and β (Wang & Zhou 2023).

    The patent's formulas were published as images and are lost; this is a reconstruction
    with every stated property (documented in the mathematics pages). (α, β) = (5/16, 0) is
    the quintic C³ scheme (speed at a key 5/8 of the chord speed); α = β = 0 is slerp timed
    by the degree-7 smoothstep (zero velocity at the keys).

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z), or a scipy ``Rotation`` holding N rotations; normalised.
    times : array_like, shape (N,), optional
        Strictly increasing key times (any unit; rates are per that unit); pandas
        ``DatetimeIndex`` and ``datetime64``/``timedelta64`` arrays become seconds. Default
        0, 1, …, N−1.
    alpha : float, array_like or "auto", default 5/16
        α: scales the key velocities and changes the first three derivatives at the keys.
        One value, or one per key (``"knot"``, N values) or per segment (``"patent"``, N−1).
        ``"auto"``: (α, β) = (1/2, −3), the only pair under which a constant-speed great
        circle is reproduced exactly (key velocity = chord rate, α(ω_k/h_l + ω_{k+1}/h_r) =
        2α·c; key jerk 0, 36α + 6β = 0; the degree-7 blend is then linear in time): speed
        ripple (max/min over the interior) 1.000 against 2.125 for (5/16, 0), whose key speed
        is 5/8 of the chord speed. Held-out accuracy in ``benchmarks/c3_auto.py``; a per-key
        rule (``quatspline.splines.c3_speed_matched_alpha``, key speed = mean chord speed)
        was measured there too and is less accurate on every bundled recording.
    beta : float or array_like, optional
        β: changes only the third derivative at the keys; same sizes as ``alpha``. Default
        0, or −3 with ``alpha="auto"``.
    variant : {"knot", "patent"}, default "knot"
        ``"knot"``: parameters belong to keys and the curve is C³ in time for any key
        spacing. ``"patent"``: the patent's blending functions exactly, C³ in the local
        parameter (in time only for uniform times and shared parameters; G³ otherwise).
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        Times outside the domain: an error, the end orientation held (zero derivatives),
        constant angular velocity from the end, or the domain repeated.
    ends : {"open", "rest", "closed"}, default "open"
        ``"rest"``: zero angular velocity, acceleration and jerk at the end keys (the
        rest-to-rest manoeuvre), still C³ — by α = β = 0 there (knot variant) or by the end
        segments' blending functions flattened at the end keys (patent variant). ``"closed"``
        (both variants): a periodic loop, C³ across the seam (see ``quatspline.splines.keys``).
    holds : bool, default True
        Consecutive equal keys (q or −q) hold exactly still, with zero angular velocity,
        acceleration and jerk at both ends of the hold. Knot variant: α = β = 0 at the keys
        bounding the hold, C³. Patent variant: the blending functions next to those keys
        are flattened there (first three derivatives zero, the other end the patent's), so
        the joint is C³ in time from both sides.

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    NaturalSpline : global C², closest to the data.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> angles = [[0, 0, 0], [0, 0, 90], [45, 0, 90], [45, 30, 120]]
    >>> keys = qs.from_euler("xyz", angles, degrees=True)
    >>> s = qs.C3Spline(keys, [0.0, 1.0, 2.5, 3.0], alpha=5 / 16, beta=0.0)
    >>> bool(np.allclose(s([0.0, 1.0, 2.5, 3.0]), keys))
    True
    >>> [j.order for j in qs.continuity(s)]
    [3, 3]
    """

    def __init__(
        self,
        quats,
        times=None,
        alpha=5 / 16,
        beta=None,
        variant: str = "knot",
        canonicalize: bool = True,
        extrapolate: str = "raise",
        ends: str = "open",
        holds: bool = True,
    ):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        use_holds = bool(holds)
        a, b = c3_shape(alpha, beta)
        super().__init__(
            _core.c3_spline(
                q,
                t,
                a,
                b,
                str(variant),
                bool(canonicalize),
                str(ends),
                use_holds,
            ),
            extrapolate,
            quats=q,
            times=t,
            alpha=alpha,
            beta=beta,
            variant=variant,
            canonicalize=canonicalize,
            ends=ends,
            holds=holds,
        )
