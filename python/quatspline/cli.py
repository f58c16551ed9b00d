"""The ``quatspline`` command line: sample, compare, plot, demo.

Exit codes: 0 success, 1 bad data (a file or its content), 2 bad usage (unknown options,
methods or parameters). Outputs are written atomically and never over an input file unless
``--force``. Progress bars appear on a terminal only.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from . import __version__
from . import io as qio
from .continuity import continuity
from .registry import METHODS, interpolating_methods
from .registry import spline as make_spline
from .spline import path_length


class UsageError(Exception):
    """Bad usage: exit code 2."""


# ---- shared helpers -------------------------------------------------------------------------
def _params(pairs: list[str] | None) -> dict:
    out = {}
    for p in pairs or []:
        if "=" not in p:
            raise UsageError(f"--param: expected name=value, got {p!r}")
        k, v = p.split("=", 1)
        out[k.strip()] = v.strip()
    return out


def _read(args) -> qio.Trajectory:
    opts = {"sort": args.sort, "dedupe": args.dedupe}
    fmt = args.in_format or qio.detect_format(args.input)
    if fmt == "csv" and args.euler:
        opts.update(euler=args.euler, degrees=args.degrees)
    if fmt == "bvh":
        opts.update(joint=args.joint, world=args.world, skip_frames=args.skip_frames)
    return qio.read(args.input, format=fmt, **opts)


def _build(method: str, traj: qio.Trajectory, times, params: dict):
    if method not in METHODS:
        raise UsageError(f"--method: unknown method {method!r}; valid: {', '.join(METHODS)}")
    try:
        return make_spline(method, traj.quats, times, **params)
    except ValueError as e:
        msg = str(e)
        if "unknown parameter" in msg or msg.startswith(tuple(METHODS[method].params)):
            raise UsageError(msg) from None
        raise


def _guard_output(out: Path, inputs: list[Path], force: bool) -> None:
    for i in inputs:
        if out.exists() and i.exists() and out.resolve() == i.resolve() and not force:
            raise UsageError(f"{out}: refusing to overwrite the input file (use --force)")


def _progress(iterable, desc: str, total: int | None = None):
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover
        return iterable
    return tqdm(iterable, desc=desc, total=total, disable=None, leave=False, file=sys.stderr)


# ---- sample ---------------------------------------------------------------------------------
def cmd_sample(args) -> int:
    traj = _read(args)
    t0 = traj.times[0]
    s = _build(args.method, traj, traj.times - t0, _params(args.param))
    a, b = s.domain
    if args.rate is not None:
        if not (args.rate > 0 and np.isfinite(args.rate)):
            raise UsageError(f"--rate: expected a positive rate, got {args.rate}")
        t = a + np.arange(int(np.floor((b - a) * args.rate + 1e-9)) + 1) / args.rate
    elif args.count is not None:
        if args.count < 1:
            raise UsageError(f"--count: expected at least 1, got {args.count}")
        t = np.linspace(a, b, args.count)
    else:
        at = Path(args.at)
        try:
            t = np.loadtxt(at, ndmin=1, comments="#") - t0
        except (OSError, ValueError) as e:
            raise ValueError(f"{at}: cannot read times ({e})") from None
    q = s(t)
    extra = {}
    if args.derivatives:
        extra = {
            "omega": s.angular_velocity(t),
            "alpha": s.angular_acceleration(t),
            "jerk": s.jerk(t),
        }
    pos = None
    if traj.positions is not None and METHODS[args.method].interpolating:
        from .pose import PoseSpline

        ps = PoseSpline(traj.quats, traj.times - t0, traj.positions, rotation="slerp")
        pos = ps.position(np.clip(t, *ps.domain))
    out = qio.Trajectory(t + t0, q, pos, extra=extra)
    _guard_output(Path(args.output), [Path(args.input)], args.force)
    qio.write(args.output, out, format=args.format)
    print(f"wrote {args.output}: {len(t)} samples of {args.method} through {len(traj)} keys")
    return 0


# ---- compare --------------------------------------------------------------------------------
def angle_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Rotation angle between unit quaternions, degrees, exact for small and large angles:
    2·atan2(|a − s b|, |a + s b|) with s the sign of a·b (q and −q are the same rotation)."""
    s = np.where(np.sum(a * b, axis=-1) < 0, -1.0, 1.0)[..., None]
    return np.degrees(
        2 * np.arctan2(np.linalg.norm(a - s * b, axis=-1), np.linalg.norm(a + s * b, axis=-1))
    )


def compare(
    traj: qio.Trajectory, methods: list[str], holdout: int | None = None, samples_per_key: int = 8
) -> list[dict]:
    t_all = traj.times - traj.times[0]
    if holdout:
        if holdout < 2:
            raise UsageError(f"--holdout: expected K ≥ 2, got {holdout}")
        idx = np.arange(0, len(t_all), holdout)
        if len(idx) < 2:
            raise ValueError(f"--holdout {holdout}: fewer than 2 keys in {len(t_all)} frames")
        rest = np.setdiff1d(np.arange(idx[0], idx[-1] + 1), idx)
    else:
        idx = np.arange(len(t_all))
    keys, kt = traj.quats[idx], t_all[idx]
    rows = []
    for m in _progress(methods, "methods"):
        s = _build(m, qio.Trajectory(kt, keys), kt, {})
        a, b = s.domain
        n = int(min(max(samples_per_key * len(kt), 1000), 400_000))
        t = np.linspace(a, b, n)
        w = np.linalg.norm(s.angular_velocity(t), axis=1)
        acc = np.linalg.norm(s.angular_acceleration(t), axis=1)
        jerk = np.linalg.norm(s.jerk(t), axis=1)
        orders = [j.order for j in continuity(s)] or [s.continuity]
        row = {
            "method": m,
            "max_speed": float(w.max()),
            "rms_speed": float(np.sqrt(np.mean(w**2))),
            "rms_acceleration": float(np.sqrt(np.mean(acc**2))),
            "rms_jerk": float(np.sqrt(np.mean(jerk**2))),
            "path_length": float(path_length(s, per_segment=2)),
            "continuity_order": int(min(orders)),
        }
        if holdout:
            err = angle_deg(s(t_all[rest]), traj.quats[rest])
            row.update(
                holdout_median_deg=float(np.median(err)),
                holdout_p95_deg=float(np.percentile(err, 95)),
                holdout_max_deg=float(err.max()),
            )
        rows.append(row)
    return rows


def format_table(rows: list[dict]) -> str:
    cols = [
        ("method", "method", "{}"),
        ("max_speed", "max |ω|", "{:.3g}"),
        ("rms_speed", "rms |ω|", "{:.3g}"),
        ("rms_acceleration", "rms |α|", "{:.3g}"),
        ("rms_jerk", "rms jerk", "{:.3g}"),
        ("path_length", "path (rad)", "{:.4g}"),
        ("continuity_order", "C^k", "{}"),
        ("holdout_median_deg", "median err (°)", "{:.4f}"),
        ("holdout_p95_deg", "p95 err (°)", "{:.4f}"),
        ("holdout_max_deg", "max err (°)", "{:.4f}"),
    ]
    cols = [c for c in cols if c[0] in rows[0]]
    head = "| " + " | ".join(c[1] for c in cols) + " |"
    sep = "|" + "|".join("---" if c[0] == "method" else "---:" for c in cols) + "|"
    body = ["| " + " | ".join(f.format(r[k]) for k, _, f in cols) + " |" for r in rows]
    return "\n".join([head, sep, *body])


def cmd_compare(args) -> int:
    traj = _read(args)
    methods = args.methods.split(",") if args.methods else interpolating_methods()
    for m in methods:
        if m not in METHODS:
            raise UsageError(f"--methods: unknown method {m!r}; valid: {', '.join(METHODS)}")
    rows = compare(traj, methods, args.holdout)
    if args.json:
        print(json.dumps(rows, indent=1))
    else:
        print(format_table(rows))
    return 0


# ---- plot -----------------------------------------------------------------------------------
def _family(args, traj):
    name, _, values = (args.family or "alpha=0,0.3125,0.6").partition("=")
    vals = [v for v in values.split(",") if v]
    if not vals:
        raise UsageError("--family: expected PARAM=v1,v2,…")
    kt = traj.times - traj.times[0]
    base = _params(args.param)
    out = {}
    for v in vals:
        out[f"{name} = {v}"] = _build(args.method, traj, kt, {**base, name: v})
    return out


def cmd_plot(args) -> int:
    from . import plot

    traj = _read(args)
    kt = traj.times - traj.times[0]
    if args.kind == "family":
        fig = plot.family(
            _family(args, traj), title=f"{args.method}: {args.family or 'alpha sweep'}"
        )
    else:
        s = _build(args.method, traj, kt, _params(args.param))
        if args.kind == "sphere":
            fig = plot.sphere(s, key_times=kt)
        elif args.kind == "rates":
            fig = plot.rates(s, key_times=kt)
        else:
            pos = None
            if traj.positions is not None:
                from .pose import PoseSpline

                pos = PoseSpline(traj.quats, kt, traj.positions, rotation="slerp").position
            fig = plot.body(s, positions=pos)
    _guard_output(Path(args.output), [Path(args.input)], args.force)
    plot.save(fig, args.output)
    print(f"wrote {args.output}")
    return 0


# ---- demo -----------------------------------------------------------------------------------
def cmd_demo(args) -> int:
    from . import demo

    return demo.run(Path(args.out), recording=Path(args.recording) if args.recording else None)


# ---- parser ---------------------------------------------------------------------------------
def _input_options(p):
    p.add_argument("input", help="trajectory file (csv, json, npz, tum, euroc, repoimu, bvh)")
    p.add_argument(
        "--in-format", choices=sorted(qio.FORMATS), help="input format (default: guessed)"
    )
    p.add_argument("--euler", metavar="SEQ", help="CSV with Euler angle columns in sequence SEQ")
    p.add_argument("--degrees", action="store_true", help="Euler angles in degrees")
    p.add_argument("--joint", help="BVH joint (default: the root)")
    p.add_argument("--world", action="store_true", help="BVH: world rotation instead of local")
    p.add_argument("--skip-frames", type=int, default=0, help="BVH: frames to drop at the start")
    p.add_argument("--sort", action="store_true", help="sort rows by time instead of failing")
    p.add_argument("--dedupe", action="store_true", help="drop rows with a repeated time")


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="quatspline",
        description="Keyframe orientations and poses in, smooth rigid-body motion out.",
        epilog="methods: " + ", ".join(METHODS),
    )
    p.add_argument("--version", action="version", version=f"quatspline {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")

    s = sub.add_parser("sample", help="sample a spline through a recording's keys")
    _input_options(s)
    s.add_argument("-o", "--output", required=True, help="output file (format from extension)")
    s.add_argument("--format", choices=sorted(qio.FORMATS), help="output format")
    s.add_argument("--method", default="c3", help="interpolation method (default: c3)")
    s.add_argument("--param", action="append", metavar="NAME=VALUE", help="method parameter")
    g = s.add_mutually_exclusive_group(required=True)
    g.add_argument("--rate", type=float, help="samples per time unit")
    g.add_argument("--count", type=int, help="number of samples")
    g.add_argument("--at", metavar="TIMES_FILE", help="file of times to sample at")
    s.add_argument("--derivatives", action="store_true", help="add ω, α and jerk columns")
    s.add_argument("--force", action="store_true", help="allow overwriting the input file")
    s.set_defaults(func=cmd_sample)

    c = sub.add_parser("compare", help="compare methods on a recording")
    _input_options(c)
    c.add_argument("--methods", help="comma-separated methods (default: all interpolating)")
    c.add_argument(
        "--holdout", type=int, metavar="K", help="keys = every K-th frame; score the rest"
    )
    c.add_argument("--json", action="store_true", help="print JSON instead of a table")
    c.set_defaults(func=cmd_compare)

    pl = sub.add_parser("plot", help="plot a spline through a recording's keys")
    _input_options(pl)
    pl.add_argument("-o", "--output", required=True, help="figure file (.png, .svg, .pdf)")
    pl.add_argument("--kind", choices=("sphere", "body", "rates", "family"), default="sphere")
    pl.add_argument("--method", default="c3", help="interpolation method (default: c3)")
    pl.add_argument("--param", action="append", metavar="NAME=VALUE", help="method parameter")
    pl.add_argument("--family", metavar="PARAM=V1,V2,…", help="family: the parameter to sweep")
    pl.add_argument("--force", action="store_true", help="allow overwriting the input file")
    pl.set_defaults(func=cmd_plot)

    d = sub.add_parser(
        "demo", help="the papers' examples and a real recording through every method"
    )
    d.add_argument("-o", "--out", default="out", help="output directory (default: out)")
    d.add_argument("--recording", help="recording to use (default: bundled TUM RGB-D fr1/xyz)")
    d.set_defaults(func=cmd_demo)
    return p


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args))
    except UsageError as e:
        print(f"quatspline: error: {e}", file=sys.stderr)
        return 2
    except (ValueError, OSError, ImportError) as e:
        print(f"quatspline: error: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:  # pragma: no cover
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
