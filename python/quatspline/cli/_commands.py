"""The ``quatspline`` command line: sample, fit, compare, plot, export, imu, demo, batch, view.

Exit codes: 0 success, 1 bad data (a file or its content), 2 bad usage (unknown options,
methods or parameters). Outputs are written atomically and never over an input file unless
``--force``. Progress bars appear on a terminal only.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import shutil
import sys
import tempfile
import traceback
import warnings
from pathlib import Path

from .. import arguments as options
from .. import batch, demo, ops, plot, viewer
from .. import io as qio
from .._core import __version__
from .._util.atomic import atomic_write, resolve_output
from .._util.optional import need
from ..poses.pose_spline import PoseSpline
from ..registry import METHODS


class UsageError(Exception):
    """Bad usage: exit code 2."""


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (``quatspline sample: error: …; see --help``), exit 2."""

    def error(self, message: str):
        msg = " ".join(message.split())
        self.exit(2, f"{self.prog}: error: {msg} (see {self.prog} --help)\n")


# ---- shared helpers -------------------------------------------------------------------------
def _read(args) -> qio.Trajectory:
    return options.read_input(args.input, options.read_options(args))


def _check_output(args) -> None:
    """Refuses a bad output before any work: unknown extension, a device/FIFO/directory."""
    if args.output == "-":
        return
    if getattr(args, "format", None) is None:
        qio.detect_format_for_writing(args.output)
    resolve_output(args.output)


def _write_trajectory(args, traj: qio.Trajectory) -> None:
    """Writes to ``-o FILE`` atomically, or to standard output for ``-o -``."""
    if args.output != "-":
        qio.write(args.output, traj, format=args.format)
        return
    with tempfile.TemporaryDirectory(prefix="quatspline-") as d:
        tmp = Path(d) / "stdout"
        qio.write(tmp, traj, format=args.format or "csv")
        sys.stdout.flush()
        binary = getattr(sys.stdout, "buffer", None)
        if binary is not None:
            with open(tmp, "rb") as f:
                shutil.copyfileobj(f, binary)
            binary.flush()
        else:  # a text-only stream (an embedding, a test harness): text formats only
            try:
                text = tmp.read_text(encoding="utf-8")
            except UnicodeDecodeError:
                raise UsageError(
                    f"-o -: standard output takes text only here; {args.format} is binary"
                ) from None
            sys.stdout.write(text)
            sys.stdout.flush()


def _input_files(args) -> list[tuple[str, Path]]:
    """Every file the command reads, with the argument that names it: the input and the
    auxiliary files (a KITTI ``--times`` file, ``--at`` times, ``--knots`` FILE)."""
    files = [("the input file", Path(args.input))]
    if getattr(args, "imu", None) is not None:
        files.append(("the IMU file", Path(args.imu)))
    for opt in ("times", "at", "knots", "noise"):
        value = getattr(args, opt, None)
        if value is None or (opt == "knots" and _is_number(value)):
            continue
        files.append((f"the --{opt} file", Path(value)))
    return files


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _guard_output(out: Path, args) -> None:
    """Refuses an output that is one of the files the command reads (the same file by any
    name: a symbolic or a hard link), unless ``--force``."""
    if str(out) == "-" or args.force or not out.exists():
        return
    for what, path in _input_files(args):
        try:
            same = os.path.samefile(out, path)
        except OSError:  # the input does not exist (its reader says so)
            continue
        if same:
            raise UsageError(f"{out}: refusing to overwrite {what} {path} (use --force)")


# ---- sample ---------------------------------------------------------------------------------
def cmd_sample(args) -> int:
    _check_output(args)
    _guard_output(Path(args.output), args)
    traj = _read(args)
    out = ops.sample(traj, **options.method_options(args), **options.sampling_options(args))
    _write_trajectory(args, out)
    at = "" if args.at is None else f" at the times of {args.at}"
    print(
        f"wrote {'standard output' if args.output == '-' else args.output}: {len(out)} samples "
        f"of {args.method} through {len(traj)} keys{at}",
        file=sys.stderr if args.output == "-" else sys.stdout,
    )
    return 0


# ---- fit ------------------------------------------------------------------------------------
#: The output formats with columns for extra per-sample data.
EXTRA_COLUMN_FORMATS = ("csv", "json", "npz")


def _check_extra_columns(args, option: str) -> None:
    """Refuses, before any work, an output format that cannot hold extra columns."""
    fmt = args.format or (
        "csv" if args.output == "-" else qio.detect_format_for_writing(args.output)
    )
    if fmt not in EXTRA_COLUMN_FORMATS:
        raise UsageError(
            f"{option}: the {fmt} format has no columns for per-sample standard deviations; "
            f"write {', '.join(EXTRA_COLUMN_FORMATS)}"
        )


def cmd_fit(args) -> int:
    """``quatspline fit``: least-squares fitting spline through noisy measurements (thin: the
    work is :func:`quatspline.ops.fit_trajectory`)."""
    _check_output(args)
    _guard_output(Path(args.output), args)
    if args.uncertainty:
        _check_extra_columns(args, "--uncertainty")
    if args.figure:
        _check_side_output(args.figure, args, (".png", ".svg", ".pdf"), "--figure")
        need("matplotlib", extra="plot", what="fit --figure")  # before the fit, not after
    traj = _read(args)
    out, f = ops.fit_trajectory(
        traj,
        **options.sampling_options(args),
        **options.fit_options(args),
        progress=True if len(traj) >= 20_000 else None,
    )
    _write_trajectory(args, out)
    rms = ops.rms_residual_deg(f)
    rot = getattr(f, "rotation", f)  # the orientation part of a pose fit
    if rot.gyro is not None:
        print(ops.gyro_summary(rot.gyro), file=sys.stderr if args.output == "-" else sys.stdout)
    print(
        f"wrote {'standard output' if args.output == '-' else args.output}: {len(out)} samples "
        f"of a fit to {len(traj)} measurements (λ = {f.smoothing:.4g}, effective dof "
        f"{f.effective_dof:.1f}, RMS residual {rms:.3f}°, {f.iterations} iterations"
        + (f", noise σ̂ {math.degrees(f.noise_std):.3f}° per axis)" if args.uncertainty else ")"),
        file=sys.stderr if args.output == "-" else sys.stdout,
    )
    if args.figure:
        t0 = float(traj.times[0])
        fig = plot.fitted(
            f, traj.times - t0, traj.quats, traj.positions, t0=t0, name=Path(args.input).name
        )
        plot.save(fig, args.figure)
        print(f"wrote {args.figure}", file=sys.stderr if args.output == "-" else sys.stdout)
    return 0


# ---- compare --------------------------------------------------------------------------------
def cmd_compare(args) -> int:
    traj = _read(args)
    rows = ops.compare(traj, **options.compare_options(args), progress=True)
    if args.json:
        print(json.dumps(rows, indent=1))
    else:
        print(ops.format_table(rows))
    return 0


# ---- plot -----------------------------------------------------------------------------------
def _family(args, traj):
    name, vals, base = options.family_sweep(args)
    return {f"{name} = {v}": ops.build_spline(args.method, traj, {**base, name: v}) for v in vals}


def cmd_plot(args) -> int:
    if Path(args.output).suffix.lower() not in (".png", ".svg", ".pdf"):
        raise UsageError(f"{args.output}: expected a .png, .svg or .pdf output")
    resolve_output(args.output)
    _guard_output(Path(args.output), args)

    traj = _read(args)
    kt = traj.times - traj.times[0]
    marks = None if args.method == "fit" else kt  # a fit's samples are not keys
    name = Path(args.input).name + (f" {traj.name}" if traj.name else "")
    if args.kind == "family":
        fig = plot.family(
            _family(args, traj),
            title=f"{name}: {args.method}, {args.family or 'alpha sweep'}",
        )
    else:
        s = ops.build_spline(args.method, traj, options.checked_params(args.param, args.method))
        if args.kind == "sphere":
            fig = plot.sphere(s, key_times=marks, name=name)
        elif args.kind == "rates":
            show = options.rates_shown(args)
            try:
                fig = plot.rates(s, key_times=marks, name=name, show=show)
            except ValueError as e:
                raise UsageError(f"--{e}") from None
        else:
            pos = None
            if traj.positions is not None:
                pos = PoseSpline(traj.quats, kt, traj.positions, rotation="slerp").position
            fig = plot.body(s, positions=pos, name=name, t0=float(traj.times[0]))
    _guard_output(Path(args.output), args)
    plot.save(fig, args.output)
    print(f"wrote {args.output}")
    return 0


# ---- export ---------------------------------------------------------------------------------
def cmd_export(args) -> int:
    traj = _read(args)
    exported = options.export_options(args)
    method = options.method_options(args)
    out = Path(args.output)
    _guard_output(out, args)
    rep = ops.export(traj, out, method=method["method"], **exported, **method["params"])
    print(rep.summary() if isinstance(rep, ops.GltfReport) else f"wrote {rep.summary()}")
    return 0


# ---- imu ------------------------------------------------------------------------------------
def cmd_imu_simulate(args) -> int:
    """``quatspline imu simulate``: the IMU a recording's motion would produce (thin: the
    work is :func:`quatspline.ops.simulate_imu`, the file
    :func:`quatspline.ops.write_simulated`)."""
    ext = Path(args.output).suffix.lower()
    if ext not in qio.IMU_WRITE_EXTENSIONS:
        raise UsageError(
            f"{args.output}: expected an IMU output file: .csv (EuRoC imu0/data.csv), .bag or .mcap"
        )
    resolve_output(args.output)
    _guard_output(Path(args.output), args)
    traj = _read(args)
    data = ops.simulate_imu(traj, **options.imu_simulate_options(args))
    ops.write_simulated(args.output, data)
    what = "gyroscope and accelerometer" if data.accel is not None else "gyroscope only"
    motion = "a smoothing fit" if args.fit else f"{args.method} through the keys"
    print(
        f"wrote {args.output}: {len(data)} IMU samples at {args.rate:g} Hz ({what}) of "
        f"{motion} ({len(traj)} keys){', with noise' if args.noise else ', noise-free'}"
    )
    return 0


def _check_side_output(path, args, exts: tuple[str, ...], option: str) -> None:
    if Path(path).suffix.lower() not in exts:
        raise UsageError(f"{option} {path}: expected a {', '.join(exts)} file")
    resolve_output(path)
    _guard_output(Path(path), args)


def cmd_imu_calibrate(args) -> int:
    """``quatspline imu calibrate``: a gyroscope against the recording's motion (thin: the
    work is :func:`quatspline.ops.calibrate_imu`)."""
    if args.figure:
        _check_side_output(args.figure, args, (".png", ".svg", ".pdf"), "--figure")
    if args.json:
        _check_side_output(args.json, args, (".json",), "--json")
    traj = _read(args)
    cal = ops.calibrate_imu(traj, args.imu, **options.imu_calibrate_options(args))
    print(cal.table())
    if args.json:
        with atomic_write(args.json) as f:
            f.write(json.dumps(cal.to_dict(), indent=1) + "\n")
        print(f"wrote {args.json}")
    if args.figure:
        cal.plot_residuals(args.figure, name=Path(args.imu).name)
        print(f"wrote {args.figure}")
    return 0


# ---- demo -----------------------------------------------------------------------------------
def cmd_demo(args) -> int:
    return demo.run(Path(args.out), recording=Path(args.recording) if args.recording else None)


# ---- parser ---------------------------------------------------------------------------------
# ---- batch ----------------------------------------------------------------------------------
def cmd_batch(args) -> int:
    table = batch.run(
        args.operation,
        args.inputs,
        args.output,
        scheduler=args.scheduler,
        workers=args.workers,
        force=args.force,
        **batch.cli_options(args),
    )
    n_bad = int((table["status"] == "error").sum())
    n_skip = int((table["status"] == "skipped").sum())
    print(
        f"batch {args.operation}: {len(table)} files, {len(table) - n_bad - n_skip} done, "
        f"{n_skip} up to date, {n_bad} failed; summary in {Path(args.output) / 'summary.md'}"
    )
    return 1 if n_bad else 0


# ---- view -----------------------------------------------------------------------------------
def cmd_view(args) -> int:
    viewer.serve(args.input, port=args.port, open_browser=not args.no_browser)
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(
        prog="quatspline",
        description="Keyframe orientations and poses in, smooth rigid-body motion out.",
        epilog="methods: " + ", ".join(METHODS) + "\n\n" + options.examples("quatspline"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--version", action="version", version=f"quatspline {__version__}")
    p.add_argument("--debug", action="store_true", help="show the traceback of an error")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    s = sub.add_parser(
        "sample",
        help="sample a spline through a recording's keys",
        epilog=options.examples("sample"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    options.add_input_options(s)
    s.add_argument(
        "-o",
        "--output",
        required=True,
        help="output file (format from the extension: .csv .json .npz .txt/.tum .bvh), "
        "or - for standard output (csv unless --format)",
    )
    s.add_argument("--format", choices=sorted(qio.FORMATS), help="output format")
    options.add_method_options(s)
    options.add_sampling_options(s)
    s.add_argument("--force", action="store_true", help="allow overwriting the input file")
    s.set_defaults(func=cmd_sample)

    ft = sub.add_parser(
        "fit",
        help="fit a smooth spline to noisy measurements and sample it",
        epilog=options.examples("fit"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    options.add_input_options(ft)
    ft.add_argument("-o", "--output", required=True, help="output file, or - (as sample)")
    ft.add_argument("--format", choices=sorted(qio.FORMATS), help="output format")
    options.add_fit_options(ft)
    options.add_gyro_options(ft)
    options.add_sampling_options(ft, extrapolate=ops.FIT_EXTRAPOLATE)
    ft.add_argument(
        "--figure",
        metavar="FILE",
        help="the data against the fit and the residuals as a figure (.png, .svg, .pdf)",
    )
    ft.add_argument("--force", action="store_true", help="allow overwriting the input file")
    ft.set_defaults(func=cmd_fit)

    c = sub.add_parser(
        "compare",
        help="compare methods on a recording",
        epilog=options.examples("compare"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    options.add_input_options(c)
    options.add_compare_options(c)
    c.add_argument("--json", action="store_true", help="print JSON instead of a table")
    c.set_defaults(func=cmd_compare)

    pl = sub.add_parser(
        "plot",
        help="plot a spline through a recording's keys",
        epilog=options.examples("plot"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    options.add_input_options(pl)
    pl.add_argument("-o", "--output", required=True, help="figure file (.png, .svg, .pdf)")
    pl.add_argument("--kind", choices=("sphere", "body", "rates", "family"), default="sphere")
    options.add_method_options(pl)
    pl.add_argument("--family", metavar="PARAM=V1,V2,…", help="family: the parameter to sweep")
    pl.add_argument(
        "--show", metavar="LIST", help="rates: some of omega,alpha,jerk (default: omega,alpha)"
    )
    pl.add_argument("--force", action="store_true", help="allow overwriting the input file")
    pl.set_defaults(func=cmd_plot)

    e = sub.add_parser(
        "export",
        help="export a motion to glTF 2.0 (error-bounded) or BVH",
        epilog=options.examples("export"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    options.add_input_options(e)
    e.add_argument("-o", "--output", required=True, help="motion.glb, motion.gltf or motion.bvh")
    options.add_export_options(e)
    options.add_method_options(e, what="spline through the keys")
    e.add_argument("--force", action="store_true", help="allow overwriting the input file")
    e.set_defaults(func=cmd_export)

    d = sub.add_parser(
        "demo",
        help="the papers' examples and a real recording through every method",
        epilog=options.examples("demo"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    d.add_argument("-o", "--out", default="out", help="output directory (default: out)")
    d.add_argument("--recording", help="recording to use (default: bundled TUM RGB-D fr1/xyz)")
    d.set_defaults(func=cmd_demo)

    b = sub.add_parser(
        "batch",
        help="one operation over many files, distributed with Dask",
        epilog=options.examples("batch"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    batch.add_arguments(b, parser_class=_Parser)
    b.set_defaults(func=cmd_batch)

    im = sub.add_parser(
        "imu",
        help="simulate an IMU on a recording's motion, or calibrate one against it",
        description="Inertial measurements: simulate the IMU a recording's motion would "
        "produce, or calibrate a recorded gyroscope against the recording.",
        epilog=options.examples("imu"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    imu = im.add_subparsers(
        dest="imu_command", metavar="IMU_COMMAND", required=True, parser_class=_Parser
    )
    si = imu.add_parser(
        "simulate",
        help="the gyroscope (and accelerometer) samples a recording's motion would produce",
        description="The IMU samples of the motion through a recording's keys (the --method "
        "spline, a pose spline when the file has positions: then the accelerometer too; or a "
        "smoothing fit with --fit), exact or with Kalibr imu.yaml noise. Times on the "
        "recording's clock.",
        epilog=options.examples("imu simulate"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    options.add_input_options(si)
    si.add_argument(
        "-o", "--output", required=True, help="IMU file: .csv (EuRoC imu0/data.csv), .bag, .mcap"
    )
    options.add_imu_simulate_options(si)
    si.add_argument("--force", action="store_true", help="allow overwriting an input file")
    si.set_defaults(func=cmd_imu_simulate)

    ca = imu.add_parser(
        "calibrate",
        help="a gyroscope's mounting, bias, scale and time offset against a recording",
        description="Calibrates the IMU's gyroscope against the recording's orientations "
        "(smoothed by a fit): the model ω_meas(t) = K R_bsᵀ ω_body(t + δ) + b. Prints the "
        "estimates with their standard errors and the RMS residual per axis.",
        epilog=options.examples("imu calibrate"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    options.add_input_options(ca)
    ca.add_argument("imu", help="IMU file (EuRoC imu0/data.csv, RepoIMU, ROS bag)")
    options.add_imu_calibrate_options(ca)
    ca.add_argument("--figure", metavar="FILE", help="residual figure (.png, .svg, .pdf)")
    ca.add_argument("--json", metavar="FILE", help="the result as JSON (.json)")
    ca.add_argument("--force", action="store_true", help="allow overwriting an input file")
    ca.set_defaults(func=cmd_imu_calibrate)

    v = sub.add_parser(
        "view",
        help="design attitude motion in the browser (local web page)",
        epilog=options.examples("view"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    v.add_argument("input", nargs="?", help="keys file, recording or trajectory (default: example)")
    v.add_argument("--port", type=int, default=0, help="port (default: a free one)")
    v.add_argument("--no-browser", action="store_true", help="print the URL only")
    v.set_defaults(func=cmd_view)
    return p


_CLI_NAMES = {
    "method": "--method",
    "methods": "--methods",
    "rate": "--rate",
    "count": "--count",
    "times": "--at",
    "holdout": "--holdout",
    "max_samples": "--max-samples",
    "workers": "--workers",
    "fps": "--fps",
    "max_error": "--max-error",
    "max_position_error": "--max-position-error",
    "max_offset": "--max-offset",
    "estimate": "--estimate",
    "noise": "--noise",
}


_KEYWORDS = re.compile(r"\b(" + "|".join(k for k in _CLI_NAMES if "_" in k) + r")\b")


def _cli_message(e: BaseException) -> str:
    """The one-line message of an error, with library argument names as CLI options."""
    msg = " ".join(str(e).split()) or type(e).__name__
    name, sep, rest = msg.partition(":")
    if sep and name in _CLI_NAMES:
        msg = _CLI_NAMES[name] + sep + rest
    # a library keyword quoted inside the message ("… more than max_samples = 10") in the
    # option's spelling; only identifiers with an underscore, never ordinary words
    return _KEYWORDS.sub(lambda m: _CLI_NAMES[m.group(0)], msg)


def main(argv: list[str] | None = None) -> int:
    """Runs the command line; returns the exit code (0 success, 1 bad data or a failure,
    2 bad usage, 130 interrupted). Every error is one line on standard error; ``--debug``
    adds the traceback."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2

    def one_line(message, category, filename, lineno, file=None, line=None):
        # A warning from the library (e.g. a λ capped where double precision ends) is one
        # line too, like the errors; --debug keeps Python's form with the source line.
        print(f"quatspline: warning: {message}", file=sys.stderr)

    with warnings.catch_warnings():
        if not args.debug:
            warnings.showwarning = one_line
            # the command's own warnings are messages to its user, whatever -W says
            warnings.filterwarnings("default", category=RuntimeWarning, module="quatspline")
        return _run(args)


def _run(args) -> int:
    try:
        return int(args.func(args))
    except KeyboardInterrupt:
        if args.debug:
            raise
        print("quatspline: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader of standard output went away (``-o - | head``): quiet, like SIGPIPE
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
        return 128 + 13
    except Exception as e:
        if args.debug:
            traceback.print_exc()
        if isinstance(e, (UsageError, ops.ParameterError)):
            code = 2
        else:
            code = 1
        if isinstance(e, MemoryError):
            msg = f"out of memory ({_cli_message(e)}); use fewer samples"
        elif isinstance(e, (ValueError, OSError, ImportError, UsageError)):
            msg = _cli_message(e)
        else:  # an unexpected failure: still one line, with its kind
            msg = f"{type(e).__name__}: {_cli_message(e)} (run with --debug for the traceback)"
        print(f"quatspline: error: {msg}", file=sys.stderr)
        return code


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
