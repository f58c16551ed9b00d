"""BVH motion capture: one joint's rotation (local, or world through the chain of parents)
and position, as a trajectory. The rotation order of each joint is taken from its CHANNELS
line (e.g. ``Zrotation Xrotation Yrotation`` → R = Rz·Rx·Ry, intrinsic "ZXY", degrees).

Options: ``joint`` (default: the root; an unknown name lists the joints), ``world=False``
(local rotation relative to the parent) or ``True`` (rotation and position in the world
frame by forward kinematics), ``skip_frames=0`` (e.g. 1 to drop a T-pose reference frame).
Frame i is at time i × Frame Time.
"""

from __future__ import annotations

import numbers
from array import array
from dataclasses import dataclass, field

import numpy as np

from .._util.atomic import atomic_write
from ..core.algebra import multiply, rotate
from ..core.convert import as_euler, from_euler
from ._common import (
    bounded_lines,
    check_for_writing,
    open_regular,
    parse_float,
    plain_number,
    refuse_extra,
)
from .trajectory import Trajectory, TrajectoryError, finish

AXES = {"Xrotation": "X", "Yrotation": "Y", "Zrotation": "Z"}
POS = ("Xposition", "Yposition", "Zposition")


@dataclass
class Joint:
    name: str
    parent: int
    offset: np.ndarray
    channels: list[str] = field(default_factory=list)
    start: int = 0


def _parse_hierarchy(path, lines):
    """The joints, the channel count and the number of the MOTION line, from an iterator of
    lines (consumed up to MOTION: the file is never held as a list of lines)."""
    joints: list[Joint] = []
    stack: list[int] = []
    nchan = 0
    i = 0
    pending: Joint | None = None
    in_end_site = 0
    for text in lines:
        s = text.strip()
        i += 1
        if not s or s == "HIERARCHY":
            continue
        if s == "MOTION":
            return joints, nchan, i
        word = s.split()
        if word[0] in ("ROOT", "JOINT"):
            if len(word) < 2:
                raise TrajectoryError(f"{path}:{i}: {word[0]} without a name")
            pending = Joint(" ".join(word[1:]), stack[-1] if stack else -1, np.zeros(3))
            joints.append(pending)
        elif word[0] == "End":
            in_end_site += 1
            pending = None
        elif word[0] == "{":
            if in_end_site:
                in_end_site += 1
            else:
                stack.append(len(joints) - 1)
        elif word[0] == "}":
            if in_end_site:
                in_end_site -= 1
                if in_end_site == 1:
                    in_end_site = 0
            elif stack:
                stack.pop()
            else:
                raise TrajectoryError(f"{path}:{i}: unbalanced '}}'")
        elif word[0] == "OFFSET":
            if len(word) != 4:
                raise TrajectoryError(f"{path}:{i}: OFFSET needs 3 numbers")
            vals = [parse_float(path, i, k + 2, "OFFSET", v) for k, v in enumerate(word[1:])]
            if not in_end_site and joints:
                joints[-1].offset = np.array(vals)
        elif word[0] == "CHANNELS":
            if not joints or in_end_site:
                raise TrajectoryError(f"{path}:{i}: CHANNELS outside a joint")
            try:
                n = int(plain_number(word[1]))
            except (IndexError, ValueError):
                raise TrajectoryError(f"{path}:{i}: CHANNELS needs a count") from None
            chans = word[2:]
            if len(chans) != n or any(c not in AXES and c not in POS for c in chans):
                raise TrajectoryError(f"{path}:{i}: bad CHANNELS line {s!r}")
            joints[-1].channels = chans
            joints[-1].start = nchan
            nchan += n
        else:
            raise TrajectoryError(f"{path}:{i}: unexpected {word[0]!r} in HIERARCHY")
    raise TrajectoryError(f"{path}: no MOTION section")


def _rotation(joint: Joint, frames: np.ndarray) -> np.ndarray:
    rot = [(c, k) for k, c in enumerate(joint.channels) if c in AXES]
    if not rot:
        q = np.zeros((len(frames), 4))
        q[:, 0] = 1.0
        return q
    if len(rot) != 3:
        raise TrajectoryError(f"joint {joint.name!r}: expected 3 rotation channels, got {len(rot)}")
    seq = "".join(AXES[c] for c, _ in rot)
    if seq[0] == seq[1] or seq[1] == seq[2]:
        raise TrajectoryError(f"joint {joint.name!r}: rotation channels {seq} repeat an axis")
    angles = frames[:, [joint.start + k for _, k in rot]]
    return from_euler(seq, angles, degrees=True)


def _translation(joint: Joint, frames: np.ndarray) -> np.ndarray:
    t = np.tile(joint.offset, (len(frames), 1))
    for axis, name in enumerate(POS):
        if name in joint.channels:
            t[:, axis] += frames[:, joint.start + joint.channels.index(name)]
    return t


def joints_of(path) -> list[str]:
    with open_regular(path, encoding="utf-8-sig") as f:
        return [j.name for j in _parse_hierarchy(path, bounded_lines(f, path))[0]]


def read(
    path,
    joint: str | None = None,
    world: bool = False,
    skip_frames: int = 0,
    sort=False,
    dedupe=False,
) -> Trajectory:
    if isinstance(skip_frames, bool) or not isinstance(skip_frames, numbers.Integral):
        raise TypeError(f"skip_frames: expected an integer, got {type(skip_frames).__name__}")
    if skip_frames < 0:
        raise TrajectoryError(f"{path}: skip_frames must be ≥ 0, got {int(skip_frames)}")
    with open_regular(path, encoding="utf-8-sig") as f:
        lines = bounded_lines(f, path)  # read as parsed: a frame at a time
        joints, nchan, i = _parse_hierarchy(path, lines)
        if not joints:
            raise TrajectoryError(f"{path}: no joints in HIERARCHY")
        names = [j.name for j in joints]
        target = 0 if joint is None else (names.index(joint) if joint in names else None)
        if target is None:
            raise TrajectoryError(f"{path}: no joint {joint!r}; joints: {', '.join(names)}")
        if nchan == 0:
            raise TrajectoryError(f"{path}: no CHANNELS in HIERARCHY")
        try:
            nframes = int(plain_number(next(lines).split(":")[1]))
            dt = float(plain_number(next(lines).split(":")[1]))
        except (StopIteration, IndexError, ValueError):
            raise TrajectoryError(
                f"{path}:{i + 1}: expected 'Frames: N' and 'Frame Time: dt'"
            ) from None
        if nframes <= 0:
            raise TrajectoryError(f"{path}:{i + 1}: no frames (Frames: {nframes})")
        if not (dt > 0 and np.isfinite(dt)):
            raise TrajectoryError(f"{path}:{i + 2}: Frame Time must be positive, got {dt}")
        data = array("d")  # 8 bytes a value, not a Python float each
        for k in range(nframes):
            ln = i + 3 + k
            text = next(lines, None)
            if text is None:
                raise TrajectoryError(f"{path}: truncated: {k} of {nframes} frames")
            cells = text.split()
            if len(cells) != nchan:
                raise TrajectoryError(
                    f"{path}:{ln}: expected {nchan} channel values, got {len(cells)}"
                )
            data.extend([parse_float(path, ln, c + 1, "channel", v) for c, v in enumerate(cells)])
    frames = np.array(data, dtype=float).reshape(-1, nchan)[skip_frames:]
    if len(frames) == 0:
        raise TrajectoryError(f"{path}: no frames")
    chain = [target]
    while joints[chain[-1]].parent >= 0:
        chain.append(joints[chain[-1]].parent)
    chain.reverse()
    try:
        q, pos = _pose(joints, chain, target, frames, world)
    except TrajectoryError as e:
        raise TrajectoryError(f"{path}: {e}") from None
    times = (np.arange(len(frames)) + skip_frames) * dt
    lines_of = np.arange(len(frames)) + i + 3 + skip_frames
    return finish(path, times, q, pos, lines_of, sort, dedupe, name=names[target])


def _pose(joints, chain, target, frames, world):
    if world:
        q = None
        pos = None
        for j in chain:
            local_q = _rotation(joints[j], frames)
            local_t = _translation(joints[j], frames)
            if q is None:
                q, pos = local_q, local_t
            else:
                pos = pos + rotate(q, local_t)
                q = multiply(q, local_q)
    else:
        q = _rotation(joints[target], frames)
        has_pos = any(c in POS for c in joints[target].channels)
        pos = _translation(joints[target], frames) if has_pos else None
    return q, pos


def write(path, traj: Trajectory, joint: str = "Root") -> None:
    check_for_writing(path, traj)
    refuse_extra(path, traj, "BVH")
    name = traj.name or joint
    if not isinstance(name, str) or not name.strip() or name != " ".join(name.split()):
        raise ValueError(
            f"{path}: joint name {name!r} cannot be written to BVH (one line of words separated "
            "by single spaces)"
        )
    if name in ("{", "}") or not name.isprintable():
        raise ValueError(f"{path}: joint name {name!r} cannot be written to BVH")
    with np.errstate(over="ignore", invalid="ignore"):  # spans beyond 1.8e308 are refused
        dt = np.diff(traj.times)
        uneven = len(traj) < 2 or not np.all(np.isfinite(dt))
        # even up to the rounding of the times themselves (epoch seconds: 2.4e-7 at 1.7e9)
        slack = 1e-9 * max(1.0, abs(dt[0])) if len(dt) else 0.0
        slack += 4 * float(np.spacing(np.max(np.abs(traj.times)))) if len(dt) else 0.0
        uneven = uneven or bool(np.any(np.abs(dt - dt[0]) > slack))
    if len(traj) < 2:
        raise ValueError(f"{path}: BVH needs at least 2 frames (its frame time), got {len(traj)}")
    if uneven:
        raise ValueError(f"{path}: BVH needs uniformly spaced times (resample first)")
    angles = as_euler(traj.quats, "ZXY", degrees=True)
    pos = traj.positions
    with atomic_write(path) as f:
        f.write(f"HIERARCHY\nROOT {name}\n{{\n  OFFSET 0 0 0\n")
        if pos is None:  # no positions: rotation channels only (not zeros the reader would keep)
            f.write("  CHANNELS 3 Zrotation Xrotation Yrotation\n")
        else:
            f.write("  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n")
        f.write("  End Site\n  {\n    OFFSET 0 0 0\n  }\n}\n")
        frame_time = (float(traj.times[-1]) - float(traj.times[0])) / (len(traj) - 1)
        f.write(f"MOTION\nFrames: {len(traj)}\nFrame Time: {frame_time!r}\n")
        for k, a in enumerate(angles):
            vals = a if pos is None else (*pos[k], *a)
            f.write(" ".join(repr(float(v)) for v in vals) + "\n")
