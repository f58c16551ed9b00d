"""Catmull–Rom and Kochanek–Bartels on the rotation group (Rust ``spline/catmull_rom.rs``,
``spline/kochanek_bartels.rs``): interpolating, cubic spherical Bézier segments.

Catmull–Rom (Gortler 2012, ch. 9) is C¹ in time; it is Kochanek–Bartels at
tension = continuity = bias = 0. Kochanek–Bartels (Kochanek & Bartels 1984) is C¹ in time at
keys with ``continuity = 0`` and has a corner (C⁰) where it is not.
"""

from __future__ import annotations

from .. import _core
from .._util.arrays import as_real
from .base import Spline
from .keys import _keys, _per, _times

__all__ = ["CatmullRom", "KochanekBartels"]


def _alpha(alpha):
    if alpha is None:
        return None
    a = as_real(alpha, "alpha")
    if a.ndim != 0:
        raise ValueError(f"alpha: expected a scalar in [0, 1], got shape {a.shape}")
    a = float(a)
    if not (0.0 <= a <= 1.0):
        raise ValueError(f"alpha: expected a value in [0, 1], got {a}")
    return a


class CatmullRom(Spline):
    """Catmull–Rom through the keys with spherical Bézier segments: C¹ in time.

    Gortler (2012, ch. 9): segment i has inner control points ``exp(hᵢ Wᵢ/3) cᵢ`` and
    ``exp(−hᵢ Wᵢ₊₁/3) cᵢ₊₁`` with the key tangent ``Wᵢ = log(cᵢ₊₁ cᵢ₋₁⁻¹)/(hᵢ₋₁ + hᵢ)``;
    for uniform times this is exactly Gortler's construction.

    ``ends="reflect"`` (default) mirrors the missing end neighbours (two keys give slerp);
    ``ends="duplicate"`` repeats the end keys; ``ends="rest"`` stops at both ends;
    ``ends="closed"`` makes a periodic loop (see ``quatspline.splines.keys``). Without
    ``times``, ``alpha`` (0 uniform, 0.5 centripetal, 1 chordal) spaces the keys by their angles
    as the ``splines`` package does. ``holds`` (default True): consecutive equal keys hold exactly
    still. This is ``KochanekBartels`` at tension = continuity = bias = 0.

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z), or a scipy ``Rotation`` holding N rotations; normalised.
    times : array_like, shape (N,), optional
        Strictly increasing key times (any unit; rates are per that unit); pandas
        ``DatetimeIndex`` and ``datetime64``/``timedelta64`` arrays become seconds. Default
        0, 1, …, N−1.
    ends : {"reflect", "duplicate", "rest", "closed"}, default "reflect"
        How the missing neighbours of the end keys are made: mirrored (two keys then give
        slerp), the end keys repeated, zero rate at both ends, or a closed loop.
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        Times outside the domain raise ``ValueError``, are clamped to it (the end
        orientation held, zero derivatives), continue at the end's angular velocity, or
        repeat the domain.
    alpha : float in [0, 1], optional
        Without ``times``: key spacing by angle to the power ``alpha`` (0 uniform, 0.5
        centripetal, 1 chordal). With ``times``, the times rule.
    holds : bool, default True
        Consecutive equal keys (q and −q count as equal) hold the orientation exactly.

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    Squad

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [90, 0, 0], [90, 45, 0], [0, 45, 30]], degrees=True)
    >>> s = qs.CatmullRom(keys, [0.0, 1.0, 3.0, 3.5])
    >>> [j.order for j in qs.continuity(s)]
    [1, 1]
    """

    def __init__(
        self,
        quats,
        times=None,
        ends: str = "reflect",
        canonicalize: bool = True,
        extrapolate: str = "raise",
        alpha=None,
        holds: bool = True,
    ):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(
            _core.catmull_rom(q, t, str(ends), bool(canonicalize), _alpha(alpha), bool(holds)),
            extrapolate,
            quats=q,
            times=t,
            ends=ends,
            canonicalize=canonicalize,
            alpha=alpha,
            holds=holds,
        )


class KochanekBartels(Spline):
    """Kochanek–Bartels (tension, continuity, bias) on the rotation group.

    Cubic spherical Bézier segments whose key rates are the KB tangents lifted to the group
    (see ``kochanek_bartels.rs``): at (0, 0, 0) exactly ``CatmullRom``; equal to the
    ``splines`` package's ``KochanekBartels`` wherever the two neighbouring logs of each key
    share an axis. C¹ in time at keys with ``continuity = 0``; a corner (C⁰) where it is not.

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Key orientations (w, x, y, z).
    times : array_like, shape (N,) or (N + 1,), optional
        Key times; a closed curve takes one more, closing the loop. Times take precedence
        over ``alpha``.
    tension, continuity, bias : float or array_like of shape (N,)
        One value or one per key (as given; a dropped closing key's value must equal the
        first). Finite, ``|value| ≤ 1e6``.
    alpha : float in [0, 1], optional
        Parametrisation when ``times`` is None: key spacing θ^α (θ the angle between keys):
        0 uniform, 0.5 centripetal, 1 chordal — as ``splines.quaternion.KochanekBartels``.
    ends : {"reflect", "duplicate", "rest", "closed"}
        Open ends by a mirrored (default) or repeated phantom key, zero rates at both ends
        (``"rest"``), or a closed loop.
    holds : bool
        Consecutive equal keys (q or −q) hold exactly still, with zero rates at both ends
        (default True).
    canonicalize : bool
        Flip keys so consecutive ones are in the same hemisphere.
    extrapolate : {"raise", "clamp", "linear", "periodic"}
        Rule outside the domain.

    Raises
    ------
    ValueError
        Non-finite or wrongly sized tension/continuity/bias (named with the index), ``alpha``
        outside [0, 1], too few keys for a closed curve, an unsupported ``ends``.

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> q = qs.from_rotvec([[0, 0, 0], [0.4, 0, 0], [0.4, 0.5, 0], [0, 0.5, 0.3]])
    >>> kb = qs.KochanekBartels(q, tension=0.0, continuity=0.0, bias=0.0)
    >>> bool(np.allclose(kb(np.linspace(0, 3, 7)), qs.CatmullRom(q)(np.linspace(0, 3, 7))))
    True
    >>> qs.KochanekBartels(q, continuity=0.5).continuity
    0
    """

    def __init__(
        self,
        quats,
        times=None,
        tension=0.0,
        continuity=0.0,
        bias=0.0,
        alpha=None,
        ends: str = "reflect",
        holds: bool = True,
        canonicalize: bool = True,
        extrapolate: str = "raise",
    ):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        a = _alpha(alpha)
        core = _core.kochanek_bartels(
            q,
            t,
            a,
            _per(tension, "tension"),
            _per(continuity, "continuity"),
            _per(bias, "bias"),
            str(ends),
            bool(holds),
            bool(canonicalize),
        )
        super().__init__(
            core,
            extrapolate,
            quats=q,
            times=t,
            tension=tension,
            continuity=continuity,
            bias=bias,
            alpha=alpha,
            ends=ends,
            holds=holds,
            canonicalize=canonicalize,
        )
