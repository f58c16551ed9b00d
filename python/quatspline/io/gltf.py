"""glTF 2.0 animations (``.gltf`` with embedded or external buffers, ``.glb``): the rotation
and translation channels of one node, parsed with ``pygltflib``
(``pip install 'quatspline[gltf]'``).

The trajectory's times are the rotation channel's key times (seconds) and its quaternions the
keys (glTF stores (x, y, z, w); CUBICSPLINE keys are the values between the tangents). A
translation channel with the same key times gives the positions; with other key times it is
played back (LINEAR, STEP or CUBICSPLINE as the file says) at the rotation's times. A node
with only a translation channel keeps its static rotation. Writing goes through
:func:`quatspline.export.to_gltf` (an error-bounded export of a spline through the keys).
"""

from __future__ import annotations

import base64
import warnings
from pathlib import Path

import numpy as np

from ._common import Trajectory, TrajectoryError, finish

HINT = "glTF files need pygltflib: pip install 'quatspline[gltf]'"
_COMP = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32}
_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
MAX_BYTES = 1 << 31


def _load(path):
    try:
        from pygltflib import GLTF2
    except ImportError as e:
        raise ImportError(HINT) from e
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # pygltflib warns about unknown chunks
            return GLTF2().load(str(path))
    except Exception as e:  # pygltflib raises assorted errors for damaged files
        raise TrajectoryError(
            f"{path}: not a readable glTF/GLB file ({type(e).__name__}: {e})"
        ) from None


def _buffer(path: Path, g, k: int, cache: dict) -> bytes:
    if k in cache:
        return cache[k]
    if not (0 <= k < len(g.buffers)):
        raise TrajectoryError(f"{path}: buffer {k} does not exist")
    buf = g.buffers[k]
    uri = buf.uri
    if uri is None:
        data = g.binary_blob()
        if data is None:
            raise TrajectoryError(f"{path}: buffer {k} has no data (no GLB BIN chunk)")
    elif uri.startswith("data:"):
        try:
            data = base64.b64decode(uri.split(",", 1)[1], validate=False)
        except (ValueError, IndexError):
            raise TrajectoryError(f"{path}: buffer {k}: bad data URI") from None
    else:
        ext = (path.parent / uri).resolve()
        if path.parent.resolve() not in ext.parents or not ext.is_file():
            raise TrajectoryError(f"{path}: buffer {k}: {uri!r} is not a file beside the glTF file")
        if ext.stat().st_size > MAX_BYTES:
            raise TrajectoryError(f"{path}: buffer {k}: {uri!r} larger than {MAX_BYTES} bytes")
        data = ext.read_bytes()
    if len(data) < (buf.byteLength or 0):
        raise TrajectoryError(
            f"{path}: buffer {k} has {len(data)} bytes, fewer than its byteLength {buf.byteLength}"
        )
    cache[k] = data
    return data


def _accessor(path: Path, g, k: int, cache: dict) -> np.ndarray:
    """Accessor k as a float64 array (count, width), normalised integers scaled as the
    specification says (§3.11)."""
    if not (isinstance(k, int) and 0 <= k < len(g.accessors)):
        raise TrajectoryError(f"{path}: accessor {k} does not exist")
    acc = g.accessors[k]
    where = f"{path}: accessor {k}"
    if acc.sparse is not None:
        raise TrajectoryError(f"{where}: sparse accessors are not supported")
    if acc.type not in _WIDTH:
        raise TrajectoryError(f"{where}: type {acc.type!r} is not an animation type")
    width, count = _WIDTH[acc.type], int(acc.count or 0)
    dtype = np.dtype(np.float32) if acc.componentType == 5126 else None
    if dtype is None:
        if acc.componentType not in _COMP:
            raise TrajectoryError(f"{where}: component type {acc.componentType} unknown")
        dtype = np.dtype(_COMP[acc.componentType])
    if acc.bufferView is None:
        return np.zeros((count, width))
    if not (0 <= acc.bufferView < len(g.bufferViews)):
        raise TrajectoryError(f"{where}: bufferView {acc.bufferView} does not exist")
    view = g.bufferViews[acc.bufferView]
    data = _buffer(path, g, view.buffer, cache)
    start = (view.byteOffset or 0) + (acc.byteOffset or 0)
    elem = dtype.itemsize * width
    stride = view.byteStride or elem
    need = start + (stride * (count - 1) + elem if count else 0)
    end = (view.byteOffset or 0) + view.byteLength
    if count < 0 or need > end or end > len(data):
        raise TrajectoryError(
            f"{where}: {count} elements do not fit in bufferView {acc.bufferView}"
        )
    raw = np.ndarray(
        shape=(count, width),
        dtype=dtype,
        buffer=data,
        offset=start,
        strides=(stride, dtype.itemsize),
    )
    with np.errstate(invalid="ignore", over="ignore"):
        out = raw.astype(np.float64)  # NaN / inf rows are refused by finish(), naming the key
    if acc.componentType != 5126 and acc.normalized:
        info = np.iinfo(dtype)
        out = np.maximum(out / info.max, -1.0) if info.min < 0 else out / info.max
    return out


def _play_channel(kind: str, kt, kv, t, rot: bool) -> np.ndarray:
    """glTF playback of one sampler at times t (clamped to its keys)."""
    if kind == "CUBICSPLINE":
        a, v, b = kv[0::3], kv[1::3], kv[2::3]
    else:
        v = kv
    if len(kt) == 1:
        return np.repeat(v[:1], len(t), axis=0)
    k = np.clip(np.searchsorted(kt, t, side="right") - 1, 0, len(kt) - 2)
    td = kt[k + 1] - kt[k]
    u = np.clip((t - kt[k]) / td, 0, 1)[:, None]
    if kind == "STEP":
        return np.where(u < 1, v[k], v[k + 1])
    if kind == "CUBICSPLINE":
        u2, u3 = u * u, u * u * u
        out = (
            (2 * u3 - 3 * u2 + 1) * v[k]
            + td[:, None] * (u3 - 2 * u2 + u) * b[k]
            + (-2 * u3 + 3 * u2) * v[k + 1]
            + td[:, None] * (u3 - u2) * a[k + 1]
        )
        return out / np.linalg.norm(out, axis=1)[:, None] if rot else out
    if rot:
        from ..interpolate import slerp

        return slerp(v[k], v[k + 1], u[:, 0])
    return v[k] + u * (v[k + 1] - v[k])


def read(
    path,
    node: str | None = None,
    animation: int | str | None = None,
    sort: bool = False,
    dedupe: bool = False,
) -> Trajectory:
    """Reads the animation of one node.

    Parameters
    ----------
    path : path-like
        A ``.gltf`` or ``.glb`` file.
    node : str, optional
        The node's name (or its index as a string); may be left out when exactly one node
        is animated. A missing node raises ``ValueError`` listing the animated nodes.
    animation : int or str, optional
        Which animation (index or name); default: the first that animates the node.

    Returns
    -------
    Trajectory
        Rotation keys (w, x, y, z) at their times, positions when the node is translated.
    """
    try:
        return _read(path, node, animation, sort, dedupe)
    except TrajectoryError:
        raise
    except (TypeError, AttributeError, IndexError, KeyError, ValueError, OverflowError) as e:
        # a document whose fields have the wrong types or point nowhere
        raise TrajectoryError(
            f"{path}: malformed glTF document ({type(e).__name__}: {e})"
        ) from None


def _read(path, node, animation, sort, dedupe) -> Trajectory:
    path = Path(path)
    path = Path(path)
    g = _load(path)
    anims = g.animations or []
    if not anims:
        raise TrajectoryError(f"{path}: no animations in this file")
    nodes = g.nodes or []

    def nname(i):
        return nodes[i].name if 0 <= i < len(nodes) and nodes[i].name else f"#{i}"

    if animation is not None:
        idx = [
            i
            for i, a in enumerate(anims)
            if (isinstance(animation, int) and i == animation) or a.name == animation
        ]
        if not idx:
            names = ", ".join(a.name or f"#{i}" for i, a in enumerate(anims))
            raise TrajectoryError(f"{path}: no animation {animation!r}; animations: {names}")
        anims_sel = [(idx[0], anims[idx[0]])]
    else:
        anims_sel = list(enumerate(anims))
    animated = {}
    for ai, a in anims_sel:
        for ch in a.channels or []:
            tgt = ch.target
            if tgt is not None and tgt.node is not None and tgt.path in ("rotation", "translation"):
                animated.setdefault(tgt.node, {}).setdefault(ai, {})[tgt.path] = ch.sampler
    if node is None:
        if len(animated) != 1:
            raise TrajectoryError(
                f"{path}: {len(animated)} animated nodes; choose one with node= (--node): "
                + ", ".join(nname(i) for i in sorted(animated))
            )
        ni = next(iter(animated))
    else:
        match = [i for i in range(len(nodes)) if nodes[i].name == node or str(i) == str(node)]
        if not match:
            raise TrajectoryError(
                f"{path}: no node {node!r}; animated nodes: "
                + (", ".join(nname(i) for i in sorted(animated)) or "none")
            )
        ni = match[0]
        if ni not in animated:
            raise TrajectoryError(
                f"{path}: node {node!r} has no rotation or translation animation; animated "
                "nodes: " + (", ".join(nname(i) for i in sorted(animated)) or "none")
            )
    ai, chans = next(iter(animated[ni].items()))
    samplers = anims[ai].samplers or []
    cache: dict = {}

    def sampler(k):
        if not (isinstance(k, int) and 0 <= k < len(samplers)):
            raise TrajectoryError(f"{path}: animation {ai}: sampler {k} does not exist")
        s = samplers[k]
        kind = s.interpolation or "LINEAR"
        if kind not in ("LINEAR", "STEP", "CUBICSPLINE"):
            raise TrajectoryError(f"{path}: sampler {k}: unknown interpolation {kind!r}")
        kt = _accessor(path, g, s.input, cache)[:, 0]
        kv = _accessor(path, g, s.output, cache)
        bad = ~np.isfinite(kt)
        with np.errstate(invalid="ignore"):
            bad[1:] |= ~(np.diff(kt) > 0)
        if np.any(bad):
            i = int(np.argmax(bad))
            raise TrajectoryError(
                f"{path}: sampler {k}: key times must be finite and strictly increasing "
                f"(key {i}: {float(kt[i])!r})"
            )
        if len(kv) != len(kt) * (3 if kind == "CUBICSPLINE" else 1) or len(kt) == 0:
            raise TrajectoryError(
                f"{path}: sampler {k}: {len(kt)} key times but {len(kv)} output values for {kind}"
            )
        return kind, kt, kv

    pos = None
    if "rotation" in chans:
        kind, kt, kv = sampler(chans["rotation"])
        if kv.shape[1] != 4:
            raise TrajectoryError(f"{path}: rotation output is not VEC4")
        times = kt
        quats = (kv[1::3] if kind == "CUBICSPLINE" else kv)[:, [3, 0, 1, 2]]
        if "translation" in chans:
            pk, pt, pv = sampler(chans["translation"])
            if pv.shape[1] != 3:
                raise TrajectoryError(f"{path}: translation output is not VEC3")
            if len(pt) == len(kt) and np.array_equal(pt, kt):
                pos = pv[1::3] if pk == "CUBICSPLINE" else pv
            else:
                pos = _play_channel(pk, pt, pv, kt, rot=False)
    else:
        pk, times, pv = sampler(chans["translation"])
        pos = pv[1::3] if pk == "CUBICSPLINE" else pv
        r = nodes[ni].rotation or [0.0, 0.0, 0.0, 1.0]
        quats = np.tile(np.array(r, dtype=float)[[3, 0, 1, 2]], (len(times), 1))
    return finish(
        path, times, quats, pos, np.arange(1, len(times) + 1), sort, dedupe, name=nname(ni)
    )


def write(path, traj: Trajectory, **options) -> None:
    """An error-bounded export of the trajectory (see :func:`quatspline.export.to_gltf`)."""
    from ..export import to_gltf

    options.setdefault("progress", False)
    to_gltf(traj, path, **options)
