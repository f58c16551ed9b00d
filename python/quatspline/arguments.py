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
- fit: ``--smoothing --penalty --robust --knots --uncertainty`` (:func:`fit_options`), and
  for ``quatspline fit`` a gyroscope: ``--gyro --gyro-noise --estimate`` (:func:`gyro_options`);
- compare: ``--methods --holdout`` (:func:`compare_options`);
- export: ``--node --max-error --max-position-error --interpolation --empty --fps``
  (:func:`export_options`);
- IMU simulation: ``--rate --noise --seed --fit`` with the method and fit groups
  (:func:`imu_simulate_options`);
- IMU calibration: ``--estimate --max-offset --robust --smoothing --imu-format``
  (:func:`imu_calibrate_options`).

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
    DEFAULT_METHOD,
    parse_angle,
    parse_choice,
    parse_length,
    parse_list,
    parse_pairs,
    parse_smoothing,
    parse_spacing_or_file,
    parse_sweep,
)
from .fitting import GYRO_ESTIMATES
from .imu.calibration import DEFAULT_ESTIMATE, ESTIMATES
from .io.kitti import read_times
from .registry import METHODS

__all__ = [
    "EXAMPLES",
    "EXTRAPOLATE",
    "INTERPOLATIONS",
    "PENALTIES",
    "ROBUST_LOSSES",
    "add_compare_options",
    "add_export_options",
    "add_fit_options",
    "add_gyro_options",
    "add_imu_calibrate_options",
    "add_imu_simulate_options",
    "add_input_options",
    "add_method_options",
    "add_sampling_options",
    "at_times",
    "checked_params",
    "compare_options",
    "examples",
    "family_sweep",
    "export_options",
    "fit_options",
    "gyro_options",
    "imu_calibrate_options",
    "imu_simulate_options",
    "knots_of",
    "method_options",
    "read_input",
    "rates_shown",
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

#: Two or three examples per command, shown at the end of its ``--help`` (bundled data paths
#: work from a source checkout).
EXAMPLES = {
    "quatspline": [
        "quatspline fit recording.tum -o smooth.csv --rate 200 --derivatives",
        "quatspline sample keys.csv -o motion.csv --method c3 --rate 100",
        "quatspline export smooth.csv -o motion.glb --max-error 0.05deg",
    ],
    "sample": [
        "quatspline sample keys.csv -o motion.csv --method c3 --rate 100",
        "quatspline sample gt.tum -o est_on_gt.tum --at est.tum --method natural",
        "quatspline sample keys.json -o - --count 5 --method kochanek_bartels "
        "--param tension=0.3 --derivatives",
    ],
    "fit": [
        "quatspline fit recording.tum -o smooth.csv --rate 200",
        "quatspline fit recording.tum -o smooth.csv --rate 200 --figure fit.png",
        "quatspline fit mocap.bvh --joint LeftElbow -o elbow.csv --rate 120 --penalty jerk",
        "quatspline fit glitchy.csv -o clean.csv --count 1000 --robust huber --smoothing 1e-4",
        "quatspline fit vicon.csv --gyro imu0.csv --gyro-noise imu.yaml -o fused.csv --rate 200",
    ],
    "compare": [
        "quatspline compare recording.tum --holdout 10",
        "quatspline compare keys.csv --methods slerp,natural,c3 --json",
    ],
    "plot": [
        "quatspline plot keys.csv -o sphere.png --kind sphere --method c3",
        "quatspline plot recording.tum -o rates.pdf --kind rates --show omega,alpha,jerk",
        "quatspline plot keys.csv -o family.png --kind family --method c3 --family alpha=0,0.3,0.5",
    ],
    "export": [
        "quatspline export smooth.csv -o motion.glb --max-error 0.05deg",
        "quatspline export run.bag --topic /pose -o motion.gltf --interpolation cubicspline",
        "quatspline export mocap.bvh --joint Hips -o hips.bvh --fps 60",
    ],
    "demo": ["quatspline demo", "quatspline demo -o /tmp/demo --recording recording.tum"],
    "batch": [
        "quatspline batch sample 'mocap/**/*.bvh' -o out/resampled --method natural --rate 120",
        "quatspline batch fit recordings/ -o out/fit --rate 200 --scheduler tcp://10.0.0.5:8786",
    ],
    "batch sample": [
        "quatspline batch sample 'mocap/**/*.bvh' -o out/resampled --method natural --rate 120",
        "quatspline batch sample data/ -o out/c3 --rate 100 --to tum --workers 2",
    ],
    "batch fit": [
        "quatspline batch fit recordings/ -o out/fit --rate 200",
        "quatspline batch fit recordings/ -o out/fit --rate 200 --scheduler scheduler.json",
    ],
    "batch compare": [
        "quatspline batch compare data/ -o out/cmp --methods slerp,natural,c3 --holdout 10",
    ],
    "batch export": [
        "quatspline batch export takes/ -o out/glb --max-error 0.05deg",
        "quatspline batch export takes/ -o out/glb --interpolation cubicspline --workers 2",
    ],
    "batch imu-simulate": [
        "quatspline batch imu-simulate recordings/ -o imu/ --rate 200",
        "quatspline batch imu-simulate 'mocap/**/*.csv' -o imu/ --rate 200 --fit --noise imu.yaml",
    ],
    "imu": [
        "quatspline imu simulate poses.csv -o imu.csv --rate 200",
        "quatspline imu calibrate vicon.csv imu0/data.csv --figure residuals.png",
    ],
    "imu simulate": [
        "quatspline imu simulate poses.csv -o imu.csv --rate 200",
        "quatspline imu simulate mocap.csv -o imu.csv --rate 200 --fit --noise imu.yaml --seed 1",
        "quatspline imu simulate keys.json -o imu.mcap --rate 100 --method squad",
    ],
    "imu calibrate": [
        "quatspline imu calibrate vicon.csv imu0/data.csv",
        "quatspline imu calibrate data/repoimu/repoIMU_first30s.csv "
        "data/repoimu/repoIMU_first30s.csv --figure residuals.png --json cal.json",
        "quatspline imu calibrate mocap.csv imu.bag --estimate rotation,bias,time_offset "
        "--robust huber",
    ],
    "view": ["quatspline view", "quatspline view keys.json --no-browser --port 8765"],
}


def examples(command: str) -> str:
    """The ``--help`` epilog of ``command`` (a key of :data:`EXAMPLES`): its examples, one
    per line."""
    return "examples:\n" + "\n".join("  " + line for line in EXAMPLES[command])


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
    """``--method`` (default :data:`~quatspline._util.options.DEFAULT_METHOD`) and its
    ``--param NAME=VALUE`` pairs."""
    p.add_argument("--method", default=DEFAULT_METHOD, help=f"{what} (default: {DEFAULT_METHOD})")
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


def add_fit_options(p, *, uncertainty: bool = True) -> None:
    """λ, the penalty, a robust loss and the knots of a smoothing fit (and ``--uncertainty``
    where the output can hold the standard deviations)."""
    p.add_argument(
        "--smoothing",
        default="auto",
        help="λ: auto (from the data, locally adaptive where it helps; default), gcv (one "
        "global λ by GCV), adaptive, or a number ≥ 0",
    )
    p.add_argument("--penalty", choices=PENALTIES, default="acceleration")
    p.add_argument("--robust", choices=ROBUST_LOSSES, help="robust loss against glitches")
    p.add_argument(
        "--knots",
        metavar="SPACING|FILE",
        help="knot spacing, or a file of knot times (one per line, the recording's clock, from "
        "its first to its last time; uneven spacing allowed); default: one per sample interval",
    )
    if not uncertainty:
        return
    p.add_argument(
        "--uncertainty",
        action="store_true",
        help="add the fit's posterior standard deviations per sample: orientation_std (radians, "
        "body axes), position_std (with positions), omega_std (rad/s, world axes, with "
        "--derivatives); needs a format with extra columns (csv, json, npz)",
    )


def add_gyro_options(p) -> None:
    """A gyroscope fitted with the orientations (``quatspline fit``): the record, its noise
    and the sensor parameters to estimate."""
    p.add_argument(
        "--gyro",
        metavar="IMU",
        help="an IMU file (EuRoC csv, RepoIMU csv, bag, …) whose gyroscope is fitted with the "
        "orientations, on the recording's clock up to an estimated offset",
    )
    p.add_argument(
        "--gyro-noise",
        metavar="IMU.YAML",
        help="Kalibr imu.yaml of the gyroscope's noise (default: estimated from the record)",
    )
    p.add_argument(
        "--estimate",
        default="bias,time_offset,rotation",
        help="with --gyro: comma-separated sensor parameters to estimate, of "
        + ", ".join(GYRO_ESTIMATES)
        + " (default: bias,time_offset,rotation; 'none' holds them all)",
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


def add_imu_simulate_options(p) -> None:
    """The IMU's rate, noise and seed, and the motion: the method group (the spline through
    the keys) or ``--fit`` with the fit group."""
    p.add_argument("--rate", type=float, required=True, help="IMU sample rate, Hz")
    p.add_argument(
        "--noise",
        metavar="IMU.YAML",
        help="Kalibr imu.yaml noise densities (default: noise-free, exact rates)",
    )
    p.add_argument("--seed", type=int, help="random seed of the noise (default: fresh)")
    p.add_argument(
        "--max-samples",
        type=int,
        default=ops.DEFAULT_MAX_SAMPLES,
        metavar="N",
        help=f"refuse to simulate more than N samples (default: {ops.DEFAULT_MAX_SAMPLES:,})",
    )
    p.add_argument(
        "--fit",
        action="store_true",
        help="the motion is a smoothing fit of the keys (--smoothing, --penalty, …) instead "
        "of the --method spline through them (for noisy motion capture)",
    )
    add_method_options(p, what="spline through the keys, the motion")
    add_fit_options(p, uncertainty=False)


def add_imu_calibrate_options(p) -> None:
    """What to estimate, the offset searched, a robust loss, the reference's smoothing and
    the IMU file's format."""
    p.add_argument(
        "--estimate",
        default=",".join(DEFAULT_ESTIMATE),
        metavar="LIST",
        help=f"comma-separated, some of {', '.join(ESTIMATES)} (default: "
        f"{','.join(DEFAULT_ESTIMATE)})",
    )
    p.add_argument(
        "--max-offset",
        default="1",
        metavar="SECONDS",
        help="largest time offset searched (default: 1)",
    )
    p.add_argument("--robust", choices=ROBUST_LOSSES, help="robust loss against glitches")
    p.add_argument(
        "--smoothing", default="auto", help="λ of the reference's fit: auto (GCV) or a number ≥ 0"
    )
    p.add_argument(
        "--imu-format", choices=sorted(qio.IMU_FORMATS), help="IMU file format (default: guessed)"
    )


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
            # the row's own converter (idempotent on converted values), so that a bad value is
            # named as the user spelled it: "--param alpha: expected a number or 'auto', …"
            out[k] = known[k].convert(f"{option} {k}", out[k])
            if known[k].check is None:  # choices only; a check may read other parameters
                known[k].validate(f"{option} {k}", method, out[k], out)
    return out


def family_sweep(args) -> tuple[str, list[str], dict]:
    """``plot --kind family``: the swept parameter, its value texts and the other ``--param``
    values. Without ``--family`` the method's α is swept over 0, 0.3125 and 0.6."""
    row = METHODS.get(args.method)
    if args.family is None and row is not None and "alpha" not in row.params:
        raise ParameterError(
            f"--kind family: {args.method} has no alpha to sweep by default; give "
            "--family PARAM=V1,V2,… or a method with shape parameters (--method c3)"
        )
    name, values = parse_sweep(args.family or "alpha=0,0.3125,0.6")
    return name, values, checked_params(args.param, args.method)


def rates_shown(args) -> tuple[str, ...]:
    """``plot --kind rates --show``: the derivatives to draw (default ω and α)."""
    return tuple(parse_list(args.show or "omega,alpha", "--show"))


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
    times of the ``--knots`` file) and ``uncertainty`` (where the command has it)."""
    out = {
        "smoothing": parse_smoothing(args.smoothing, "--smoothing"),
        "penalty": args.penalty,
        "robust": args.robust,
        "knots": None if args.knots is None else knots_of(args.knots),
    }
    if hasattr(args, "uncertainty"):
        out["uncertainty"] = bool(args.uncertainty)
    if getattr(args, "gyro", None) is not None:
        out.update(gyro_options(args))
    elif getattr(args, "gyro_noise", None) is not None:
        raise ParameterError("--gyro-noise: only with --gyro")
    return out


def gyro_options(args) -> dict:
    """``gyro`` (the IMU file), ``gyro_noise`` (an imu.yaml path or None) and ``estimate``
    (each one of :data:`quatspline.fitting.GYRO_ESTIMATES`; "none" for none)."""
    names = parse_list(args.estimate, "--estimate")
    if names == ["none"]:
        estimate = ()
    else:
        estimate = tuple(parse_choice(e, "--estimate", GYRO_ESTIMATES) for e in names)
    return {"gyro": args.gyro, "gyro_noise": args.gyro_noise, "estimate": estimate}


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


def imu_simulate_options(args) -> dict:
    """The keyword arguments of :func:`quatspline.ops.simulate_imu`: ``rate``, ``method``,
    ``params``, ``fit`` (the fit group's options with ``--fit``, else None), ``noise`` (the
    imu.yaml path), ``seed`` and ``max_samples``."""
    out = {
        "rate": args.rate,
        **method_options(args),
        "fit": fit_options(args) if args.fit else None,
        "noise": args.noise,
        "seed": args.seed,
        "max_samples": args.max_samples,
    }
    return out


def imu_calibrate_options(args) -> dict:
    """The keyword arguments of :func:`quatspline.ops.calibrate_imu`: ``estimate`` (each one
    of :data:`quatspline.imu.calibration.ESTIMATES`), ``max_offset`` (seconds ≥ 0),
    ``robust``, ``smoothing`` and ``imu_format``."""
    estimate = tuple(
        parse_choice(e, "--estimate", ESTIMATES) for e in parse_list(args.estimate, "--estimate")
    )
    try:
        max_offset = float(str(args.max_offset).strip())
    except ValueError:
        raise ParameterError(
            f"--max-offset: expected a number of seconds ≥ 0, got {args.max_offset!r}"
        ) from None
    if not (np.isfinite(max_offset) and max_offset >= 0):
        raise ParameterError(f"--max-offset: expected a finite number ≥ 0, got {max_offset:g}")
    return {
        "estimate": estimate,
        "max_offset": max_offset,
        "robust": args.robust,
        "smoothing": parse_smoothing(args.smoothing, "--smoothing"),
        "imu_format": args.imu_format,
    }
