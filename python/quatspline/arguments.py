"""The command line's option groups, each defined once, and their translation to the library.

``quatspline sample|fit|compare|export FILE`` and ``quatspline batch sample|fit|compare|export
FILES…`` add the same groups (the same names, choices, defaults and help) and turn the parsed
arguments into the same keyword arguments of the same library operation, so a batch runs the
single-file command over many files. The groups, and what translates each:

- input: ``--in-format --euler --degrees --joint --world --skip-frames --topic --frame
  --node-in --times --sort --dedupe`` (:func:`read_options`, read by :func:`read_input`);
- method: ``--method --param`` (:func:`method_options`);
- sampling: ``--rate | --count | --at``, ``--derivatives --max-samples --extrapolate``
  (:func:`sampling_options`);
- fit: ``--smoothing --penalty --robust --knots --uncertainty`` (:func:`fit_options`);
- compare: ``--methods --holdout`` (:func:`compare_options`);
- export: ``--node --max-error --max-position-error --interpolation --empty --fps``
  (:func:`export_options`).

Every string → value conversion is one of :mod:`quatspline._util.options`; a bad value is a
:class:`~quatspline._util.errors.ParameterError` naming the option (exit code 2).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from . import io as qio
from . import ops
from ._util.errors import ParameterError
from ._util.options import (
    parse_angle,
    parse_length,
    parse_list,
    parse_pairs,
    parse_smoothing,
    parse_spacing_or_file,
)
from .io.kitti import read_times
from .registry import METHODS

__all__ = [
    "EXTRAPOLATE",
    "INTERPOLATIONS",
    "PENALTIES",
    "ROBUST_LOSSES",
    "add_compare_options",
    "add_export_options",
    "add_fit_options",
    "add_input_options",
    "add_method_options",
    "add_sampling_options",
    "at_times",
    "checked_params",
    "compare_options",
    "export_options",
    "fit_options",
    "knots_of",
    "method_options",
    "read_input",
    "read_options",
    "sampling_options",
]

#: ``--extrapolate`` choices: what sampling does at times outside the keys.
EXTRAPOLATE = ("raise", "clamp", "linear", "periodic")
#: ``--penalty`` choices of a fit.
PENALTIES = ("acceleration", "jerk", "auto")
#: ``--robust`` choices of a fit.
ROBUST_LOSSES = ("huber", "cauchy")
#: ``--interpolation`` choices of a glTF export.
INTERPOLATIONS = ("linear", "cubicspline")


# ---- the groups -------------------------------------------------------------------------------
def add_input_options(p, *, many: bool = False) -> None:
    """The input file (``many``: files, directories and patterns) and how to read it."""
    if many:
        p.add_argument("inputs", nargs="+", help="files, directories (recursive) or glob patterns")
    else:
        p.add_argument(
            "input", help="trajectory file (csv, json, npz, tum, euroc, repoimu, bvh, …)"
        )
    p.add_argument(
        "--in-format", choices=sorted(qio.FORMATS), help="input format (default: guessed)"
    )
    p.add_argument("--euler", metavar="SEQ", help="CSV with Euler angle columns in sequence SEQ")
    p.add_argument("--degrees", action="store_true", help="Euler angles in degrees")
    p.add_argument("--joint", help="BVH joint (default: the root)")
    p.add_argument("--world", action="store_true", help="BVH: world rotation instead of local")
    p.add_argument("--skip-frames", type=int, default=0, help="BVH: frames to drop at the start")
    p.add_argument("--topic", help="ROS bag / MCAP: the topic (listed when missing)")
    p.add_argument("--frame", help="ROS bag /tf topics: the child frame to follow")
    p.add_argument("--node-in", metavar="NODE", help="glTF input: the animated node")
    p.add_argument("--times", metavar="FILE", help="KITTI: the times file (one per line)")
    p.add_argument("--sort", action="store_true", help="sort rows by time instead of failing")
    p.add_argument("--dedupe", action="store_true", help="drop rows with a repeated time")


def add_method_options(p, *, what: str = "interpolation method") -> None:
    """``--method`` (default c3) and its ``--param NAME=VALUE`` pairs."""
    p.add_argument("--method", default="c3", help=f"{what} (default: c3)")
    p.add_argument("--param", action="append", metavar="NAME=VALUE", help="method parameter")


def add_sampling_options(p, *, extrapolate: tuple[str, ...] = EXTRAPOLATE) -> None:
    """Where to sample (exactly one of ``--rate``, ``--count``, ``--at``), the derivative
    columns, the bound on the number of samples and ``--extrapolate``, the times outside the
    keys (``extrapolate``: the modes the operation offers; a fit only raise and clamp)."""
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--rate", type=float, help="samples per time unit")
    g.add_argument("--count", type=int, help="number of samples")
    g.add_argument(
        "--at",
        metavar="FILE",
        help="sample at the times of a trajectory file (or a one-column file of times)",
    )
    p.add_argument("--derivatives", action="store_true", help="add ω, α and jerk columns")
    p.add_argument(
        "--max-samples",
        type=int,
        default=ops.DEFAULT_MAX_SAMPLES,
        metavar="N",
        help=f"refuse to write more than N samples (default: {ops.DEFAULT_MAX_SAMPLES:,}; "
        "about 300 bytes each at peak with positions and derivatives)",
    )
    words = {
        "raise": "raise (default)",
        "clamp": "clamp (hold the end pose)",
        "linear": "linear (constant angular and linear velocity)",
        "periodic": "periodic",
    }
    p.add_argument(
        "--extrapolate",
        choices=extrapolate,
        default="raise",
        help="times outside the keys (--at): " + ", ".join(words[m] for m in extrapolate),
    )


def add_fit_options(p) -> None:
    """λ, the penalty, a robust loss and the knots of a smoothing fit."""
    p.add_argument("--smoothing", default="auto", help="λ: auto (GCV, default) or a number ≥ 0")
    p.add_argument("--penalty", choices=PENALTIES, default="acceleration")
    p.add_argument("--robust", choices=ROBUST_LOSSES, help="robust loss against glitches")
    p.add_argument(
        "--knots",
        metavar="SPACING|FILE",
        help="knot spacing, or a file of knot times (one per line, the recording's clock, from "
        "its first to its last time; uneven spacing allowed); default: one per sample interval",
    )
    p.add_argument(
        "--uncertainty",
        action="store_true",
        help="add the fit's posterior standard deviations per sample: orientation_std (radians, "
        "body axes), position_std (with positions), omega_std (rad/s, world axes, with "
        "--derivatives); needs a format with extra columns (csv, json, npz)",
    )


def add_compare_options(p) -> None:
    """The methods to compare and the hold-out (default: none, as ``compare``)."""
    p.add_argument("--methods", help="comma-separated methods (default: all interpolating)")
    p.add_argument(
        "--holdout", type=int, metavar="K", help="keys = every K-th frame; score the rest"
    )


def add_export_options(p) -> None:
    """The glTF node, the error bounds, the interpolation and the BVH frame rate (the spline
    through the keys is the method group)."""
    p.add_argument("--node", default="body", help="glTF node name (default: body)")
    p.add_argument("--max-error", default="0.01deg", help="orientation bound (default: 0.01deg)")
    p.add_argument("--max-position-error", default="0.1mm", help="position bound (default: 0.1mm)")
    p.add_argument("--interpolation", choices=INTERPOLATIONS, default="linear")
    p.add_argument("--empty", action="store_true", help="an empty node instead of an axes mesh")
    p.add_argument("--fps", type=float, help="BVH: frame rate (default: from the key spacing)")


# ---- the translation: parsed arguments → the library's keyword arguments -----------------------
def read_options(args) -> dict:
    """The input group as a plain dict (the names :func:`read_input` takes)."""
    return {
        "format": args.in_format,
        "euler": args.euler,
        "degrees": bool(args.degrees),
        "joint": args.joint,
        "world": bool(args.world),
        "skip_frames": int(args.skip_frames or 0),
        "topic": args.topic,
        "frame": args.frame,
        "node_in": args.node_in,
        "times_file": args.times,
        "sort": bool(args.sort),
        "dedupe": bool(args.dedupe),
    }


def read_input(path, options: dict | None = None) -> qio.Trajectory:
    """Reads ``path`` with the options of :func:`read_options` that its format takes (the
    format given, else guessed from the file): Euler columns for CSV, the joint for BVH, the
    topic and frame for ROS bags, the node for glTF, the times file for KITTI."""
    o = options or {}
    opts = {"sort": bool(o.get("sort")), "dedupe": bool(o.get("dedupe"))}
    fmt = o.get("format") or qio.detect_format(path)
    if fmt == "csv" and o.get("euler"):
        opts.update(euler=o["euler"], degrees=bool(o.get("degrees")))
    if fmt == "bvh":
        opts.update(
            joint=o.get("joint"),
            world=bool(o.get("world")),
            skip_frames=int(o.get("skip_frames") or 0),
        )
    if fmt == "rosbag":
        opts.update(topic=o.get("topic"), frame=o.get("frame"))
    if fmt == "gltf" and o.get("node_in"):
        opts.update(node=o["node_in"])
    if fmt == "kitti" and o.get("times_file"):
        opts.update(times=o["times_file"])
    return qio.read(path, format=fmt, **opts)


def checked_params(pairs, method, option: str = "--param") -> dict:
    """``--param NAME=VALUE`` pairs as a dict; with a ``method`` of the registry, a name that
    is not one of its parameters is a :class:`ParameterError` naming the valid ones (never
    passed on as a keyword to whatever the command calls)."""
    out = parse_pairs(pairs, option)
    known = METHODS[method].params if isinstance(method, str) and method in METHODS else None
    if known is not None:
        for k in out:
            if k not in known:
                valid = ", ".join(known) or "none"
                raise ParameterError(f"{option} {k}: not a parameter of {method}; valid: {valid}")
    return out


def method_options(args) -> dict:
    """``method`` and its ``params`` (checked against the method's parameters)."""
    return {"method": args.method, "params": checked_params(args.param, args.method)}


def _times_file(path: Path, option: str, one: str = "time") -> np.ndarray:
    """One number per line (``#`` comments) from ``path``, read as the KITTI times reader
    reads (a regular file, bounded lines); an unreadable or empty file is a one-line error
    naming the option and the file."""
    try:
        t = read_times(path)
    except ValueError as e:
        raise ValueError(f"{option}: {e}") from None
    if t.size == 0:
        raise ValueError(f"{option} {path}: the file holds no {one}s")
    return t


def at_times(path) -> np.ndarray:
    """The times of ``--at FILE``: those of any trajectory file, or of a one-column file of
    times (:func:`quatspline.ops.times_from_file`, the one reader every command uses)."""
    return ops.times_from_file(path)


def knots_of(value):
    """``--knots``: a spacing, or the knot times of a file (one per line)."""
    knots = parse_spacing_or_file(value, "--knots")
    if isinstance(knots, str):
        return _times_file(Path(knots), "--knots", "knot time")
    return knots


def sampling_options(args) -> dict:
    """``rate``, ``count`` or ``times`` (the ``--at`` file read), ``derivatives``,
    ``max_samples`` and ``extrapolate``."""
    out = {
        "rate": args.rate,
        "count": args.count,
        "times": None if args.at is None else at_times(args.at),
        "derivatives": bool(args.derivatives),
        "max_samples": args.max_samples,
    }
    out["extrapolate"] = args.extrapolate
    return out


def fit_options(args) -> dict:
    """``smoothing`` ("auto" or λ), ``penalty``, ``robust``, ``knots`` (a spacing or the
    times of the ``--knots`` file) and ``uncertainty``."""
    return {
        "smoothing": parse_smoothing(args.smoothing, "--smoothing"),
        "penalty": args.penalty,
        "robust": args.robust,
        "knots": None if args.knots is None else knots_of(args.knots),
        "uncertainty": bool(args.uncertainty),
    }


def compare_options(args) -> dict:
    """``methods`` (None: the library's default, every interpolating method) and ``holdout``
    (default: none)."""
    # no --methods: None, the library's default list (every interpolating method)
    methods = parse_list(args.methods, "--methods") if args.methods else None
    return {"methods": methods, "holdout": args.holdout}


def export_options(args) -> dict:
    """The keyword arguments of :func:`quatspline.ops.to_gltf` (bounds checked here, kept as
    given: the exporter reads them) and ``fps`` for a BVH export."""
    parse_angle(args.max_error, "--max-error")
    parse_length(args.max_position_error, "--max-position-error")
    return {
        "max_error": args.max_error,
        "max_position_error": args.max_position_error,
        "interpolation": args.interpolation,
        "node": args.node,
        "mesh": None if args.empty else "axes",
        "fps": args.fps,
    }
