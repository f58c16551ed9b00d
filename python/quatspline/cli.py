"""The ``quatspline`` command line.

Exit codes: 0 success, 1 bad data, 2 bad usage (argparse's own convention).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from . import __version__
from ._atomic import atomic_write
from .algebra import normalize
from .examples import BETA_EXAMPLE1_VERTICES
from .interpolate import slerp


def _write_csv(path: Path, t: np.ndarray, q: np.ndarray) -> None:
    with atomic_write(path, newline="") as f:
        f.write("t,qw,qx,qy,qz\n")
        for ti, qi in zip(t, q):
            f.write(f"{ti:.9g},{qi[0]:.17g},{qi[1]:.17g},{qi[2]:.17g},{qi[3]:.17g}\n")


def cmd_demo(args: argparse.Namespace) -> int:
    out = Path(args.out)
    keys = normalize(BETA_EXAMPLE1_VERTICES)
    per_segment = 50
    ts, qs = [], []
    for i in range(len(keys) - 1):
        u = np.linspace(0.0, 1.0, per_segment, endpoint=False)
        ts.append(i + u)
        qs.append(slerp(keys[i], keys[i + 1], u))
    ts.append(np.array([len(keys) - 1.0]))
    qs.append(keys[-1:])
    path = out / "beta_example1_slerp.csv"
    _write_csv(path, np.concatenate(ts), np.concatenate(qs))
    print(f"wrote {path} ({sum(len(t) for t in ts)} samples, piecewise slerp of Beta Example 1)")
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="quatspline",
        description="Keyframe orientations and poses in, smooth rigid-body motion out.",
    )
    p.add_argument("--version", action="version", version=f"quatspline {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    d = sub.add_parser("demo", help="run the papers' examples and write results to out/")
    d.add_argument("--out", default="out", help="output directory (default: out)")
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
    except (ValueError, OSError) as e:
        print(f"quatspline: error: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
