"""The evaluation engine's switches: which kernels evaluate splines.

Splines of the cumulative family (``CumulativeBSpline``, ``BetaSpline``, ``C3Spline``,
``CumulativeBezier``), the slerp family (``PiecewiseSlerp``, ``Squad``, ``CatmullRom``,
``KochanekBartels``, ``SphericalBezier``) and ``NaturalSpline`` are evaluated by batch
kernels: AVX-512 F + DQ, eight samples per vector, where the CPU has them, else AVX2 + FMA,
four samples per vector (both detected at run time), else a portable scalar kernel. The
per-sample jet path remains as the reference every kernel is tested against. The environment
variable ``QUATSPLINE_SIMD`` (``auto``, ``avx512``, ``avx2``, ``scalar``/``off``,
``reference``) sets the mode at start-up; :func:`set_simd` changes it at run time.
"""

from __future__ import annotations

from .. import _core

__all__ = ["set_simd", "simd_status"]


def set_simd(mode: str) -> None:
    """Chooses the evaluation kernels for the whole process.

    Parameters
    ----------
    mode : str
        ``"auto"`` (the widest instruction set available: AVX-512, else AVX2),
        ``"avx512"`` or ``"avx2"`` (at most that instruction set: a CPU without it runs the
        best one below), ``"scalar"`` (portable batch kernels) or ``"reference"`` (the
        per-sample jet path).

    Raises
    ------
    ValueError
        For any other mode.

    Examples
    --------
    >>> import quatspline as qs
    >>> qs.set_simd("scalar")
    >>> qs.simd_status()
    ('scalar', 'scalar')
    >>> qs.set_simd("auto")
    """
    if not isinstance(mode, str):
        raise TypeError(f"mode: expected a str, got {type(mode).__name__}")
    _core.set_simd(mode)


def simd_status() -> tuple[str, str]:
    """The engine mode and the instruction set batch kernels run on now.

    Returns
    -------
    tuple of str
        ``(mode, kernel)``: mode ``"auto"``, ``"avx512"``, ``"avx2"``, ``"scalar"`` or
        ``"reference"``; kernel ``"avx512"``, ``"avx2"``, ``"scalar"`` or ``"reference"``.

    Examples
    --------
    >>> import quatspline as qs
    >>> qs.simd_status()[1] in ("avx512", "avx2", "scalar", "reference")
    True
    """
    return _core.simd_status()
