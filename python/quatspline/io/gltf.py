"""glTF 2.0 animations (``.gltf`` with embedded or external buffers, ``.glb``): the rotation
and translation channels of one node.

The trajectory's times are the rotation channel's key times (seconds) and its quaternions the
keys (glTF stores (x, y, z, w); CUBICSPLINE keys are the values between the tangents). A
translation channel with the same key times gives the positions; with other key times it is
played back (LINEAR, STEP or CUBICSPLINE as the file says) at the rotation's times. A node
with only a translation channel keeps its static rotation.

Writing: :func:`write_animation` builds the document (one buffer, a bufferView and accessor
per array, one sampler and channel per path of one node, an optional axes mesh) from key
times and values and writes it atomically as ``.glb`` or ``.gltf``. :func:`write` (as
``io.write``) gives it a trajectory's own samples as LINEAR keys, exact at every sample;
:func:`quatspline.ops.to_gltf` gives it the keys of an error-bounded export of a spline.

The reader checks every field it uses against the glTF 2.0 specification and refuses a file
that breaks it with one ``ValueError`` naming the file and the field
(``accessors[3].byteOffset``). Nothing is allocated from what a file declares before the
declaration is checked against the bytes the file actually holds, and only the byte ranges
the animation uses are read (from the GLB binary chunk or an external buffer, by seeking).
A ``bufferView.byteStride`` (4 to 252, a multiple of 4, at least the element size) is
honoured on animation data too, and sparse accessors are applied.
"""

from __future__ import annotations

import base64
import binascii
import json
import math
import os
import re
import struct
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import unquote

import numpy as np

from .._util import checks as _checks
from .._util.atomic import atomic_write
from ..core.interpolate import slerp
from ._common import check_for_writing, check_regular_input, refuse_extra
from .trajectory import Trajectory, TrajectoryError, finish, quat_norms

#: component type → numpy dtype (little-endian, as the specification stores them)
_COMP = {
    5120: np.dtype("<i1"),
    5121: np.dtype("<u1"),
    5122: np.dtype("<i2"),
    5123: np.dtype("<u2"),
    5125: np.dtype("<u4"),
    5126: np.dtype("<f4"),
}
_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
_GLB_MAGIC, _JSON_CHUNK, _BIN_CHUNK = 0x46546C67, 0x4E4F534A, 0x004E4942
_DATA_URI = re.compile(r"data:[^,]*;base64,", re.IGNORECASE)
#: output component types allowed per path (glTF 2.0 §3.11; KHR_mesh_quantization widens
#: translation); values: (component type, normalized)
_ROTATION_TYPES = {(5126, False), (5120, True), (5121, True), (5122, True), (5123, True)}
_QUANTIZED_TRANSLATION = {(c, n) for c in (5120, 5121, 5122, 5123) for n in (False, True)}


class _Doc:
    """The JSON document and where its bytes come from, with the checks that name the file
    and the field."""

    def __init__(self, path: Path):
        self.path = path
        self.size = os.stat(path).st_size
        self.bin = None  # (offset, length) of the GLB BIN chunk
        #: buffer index → (byteLength, ("file", Path, offset) or ("mem", bytes))
        self.buffers: dict[int, tuple] = {}
        with open(path, "rb") as f:
            head = f.read(12)
            if len(head) == 12 and struct.unpack("<I", head[:4])[0] == _GLB_MAGIC:
                self.json = self._glb(f, head)
            else:
                f.seek(0)
                self.json = self._parse(f.read(), "the file")

    def bad(self, why: str):
        raise TrajectoryError(f"{self.path}: not a readable glTF/GLB file ({why})")

    def fail(self, where: str, what: str):
        raise TrajectoryError(f"{self.path}: {where}: {what}" if where else f"{self.path}: {what}")

    def _parse(self, raw: bytes, what: str):
        try:
            doc = json.loads(raw.decode("utf-8-sig"))
        except UnicodeDecodeError as e:
            self.bad(f"{what} is not UTF-8 JSON (byte {e.start}) nor GLB")
        except (ValueError, RecursionError) as e:
            detail = e.msg if isinstance(e, json.JSONDecodeError) else type(e).__name__
            self.bad(f"{what} is not valid JSON: {detail}")
        if not isinstance(doc, dict):
            self.bad("the glTF JSON is not an object")
        return doc

    def _glb(self, f, head: bytes):
        _, version, length = struct.unpack("<III", head)
        if version != 2:
            self.bad(f"GLB version {version}; only glTF 2 is read")
        if length > self.size or length < 20:
            self.bad(f"the GLB header declares {length} bytes; the file has {self.size}")
        chunk = f.read(8)
        if len(chunk) < 8:
            self.bad("GLB without a JSON chunk")
        n, kind = struct.unpack("<II", chunk)
        if kind != _JSON_CHUNK:
            self.bad("the first GLB chunk is not JSON")
        if 20 + n > length:
            self.bad(f"the GLB JSON chunk's {n} bytes do not fit in the file's {length}")
        doc = self._parse(f.read(n), "the JSON chunk")
        pos = 20 + n + (-n % 4)
        if pos + 8 <= length:
            f.seek(pos)
            m, kind = struct.unpack("<II", f.read(8))
            if kind == _BIN_CHUNK:
                if pos + 8 + m > length:
                    self.bad(f"the GLB BIN chunk's {m} bytes do not fit in the file's {length}")
                self.bin = (pos + 8, m)
        return doc

    # ---- typed fields ----------------------------------------------------------------------
    def array(self, obj: dict, key: str, where: str, required=False) -> list:
        v = obj.get(key)
        if v is None:
            if required:
                self.fail(f"{where}.{key}" if where else key, "missing")
            return []
        if not isinstance(v, list):
            self.fail(f"{where}.{key}" if where else key, "must be an array")
        return v

    def item(self, top: str, k) -> dict:
        """The object ``top[k]``, k checked as an index."""
        arr = self.array(self.json, top, "")
        if not isinstance(arr[k] if 0 <= k < len(arr) else None, dict):
            self.fail(f"{top}[{k}]", "is not an object")
        return arr[k]

    def index(self, obj: dict, key: str, where: str, top: str, required=True) -> int | None:
        v = obj.get(key)
        if v is None and not required:
            return None
        n = len(self.array(self.json, top, ""))
        if not _is_int(v) or not 0 <= v < n:
            valid = f"0..{n - 1}" if n else f"the file has no {top}"
            self.fail(f"{where}.{key}", f"{_show(v)} is not an index into {top} ({valid})")
        return v

    def integer(self, obj: dict, key: str, where: str, lo: int, default=None) -> int:
        v = obj.get(key, default)
        if v is None:
            self.fail(f"{where}.{key}", "missing")
        if not _is_int(v) or v < lo:
            self.fail(f"{where}.{key}", f"{_show(v)} is not an integer ≥ {lo}")
        return v

    def string(self, obj: dict, key: str, where: str, default=None) -> str | None:
        v = obj.get(key, default)
        if v is not None and not isinstance(v, str):
            self.fail(f"{where}.{key}", f"{_show(v)} is not a string")
        return v

    # ---- bytes -----------------------------------------------------------------------------
    def buffer(self, k: int) -> tuple[int, tuple]:
        """(byteLength, source) of buffer k, the declared length checked against the bytes
        its source holds; external files are opened later, only for the ranges used."""
        if k in self.buffers:
            return self.buffers[k]
        where = f"buffers[{k}]"
        buf = self.item("buffers", k)
        length = self.integer(buf, "byteLength", where, 1)
        uri = self.string(buf, "uri", where)
        if uri is None:
            if k != 0 or self.bin is None:
                self.fail(where, "has no uri and is not the GLB binary chunk")
            have, source = self.bin[1], ("file", self.path, self.bin[0])
        elif uri[:5].lower() == "data:":
            m = _DATA_URI.match(uri)
            if not m:
                self.fail(f"{where}.uri", "a data URI that is not base64")
            body = uri[m.end() :]
            if len(body) // 4 * 3 < length - 2:  # cheap bound before decoding
                self.fail(f"{where}.uri", f"holds fewer than byteLength {length} bytes")
            try:
                data = base64.b64decode(body, validate=True)
            except (binascii.Error, ValueError):
                self.fail(f"{where}.uri", "invalid base64 data")
            have, source = len(data), ("mem", data)
        else:
            file = self._external(uri, f"{where}.uri")
            have, source = os.stat(file).st_size, ("file", file, 0)
        if have < length:
            self.fail(where, f"byteLength {length} but the data holds {have} bytes")
        self.buffers[k] = (length, source)
        return self.buffers[k]

    def _external(self, uri: str, where: str) -> Path:
        rel = unquote(uri)
        if "\0" in rel:
            self.fail(where, "a file name with a NUL byte")
        if re.match(r"^[A-Za-z][A-Za-z0-9+.-]*:", rel) or rel.startswith(("/", "\\")) or not rel:
            self.fail(where, f"{uri!r} is not a relative file name")
        base = self.path.parent.resolve()
        file = (base / rel).resolve()
        if base not in file.parents:
            self.fail(where, f"{uri!r} is not a file beside the glTF file")
        try:
            check_regular_input(file)
        except ValueError as e:
            self.fail(where, f"{uri!r}: {str(e).split(': ', 1)[-1]}")
        return file

    def read(self, source: tuple, start: int, n: int, where: str) -> bytes:
        if source[0] == "mem":
            return source[1][start : start + n]
        _, file, base = source
        with open(file, "rb") as f:
            f.seek(base + start)
            data = f.read(n)
        if len(data) != n:
            self.fail(where, f"{file.name} ended early (it changed while being read?)")
        return data


def _is_int(v) -> bool:
    return isinstance(v, int) and not isinstance(v, bool)


def _show(v) -> str:
    s = json.dumps(v) if isinstance(v, (int, float, str, bool, type(None))) else type(v).__name__
    return s if len(s) <= 40 else s[:37] + "..."


def _view_data(d: _Doc, vi: int, start: int, count: int, elem: int, comp: int, where: str):
    """``count`` elements of ``elem`` bytes at ``start`` in bufferView ``vi``: (bytes, stride),
    every bound checked before anything is read."""
    vw = f"bufferViews[{vi}]"
    view = d.item("bufferViews", vi)
    bi = d.index(view, "buffer", vw, "buffers")
    voff = d.integer(view, "byteOffset", vw, 0, default=0)
    vlen = d.integer(view, "byteLength", vw, 1)
    stride = view.get("byteStride")
    if stride is not None and not (_is_int(stride) and 4 <= stride <= 252 and stride % 4 == 0):
        d.fail(f"{vw}.byteStride", f"{_show(stride)} is not a multiple of 4 in [4, 252]")
    if stride is not None and stride < elem:
        d.fail(f"{vw}.byteStride", f"{stride} is less than the element size {elem} ({where})")
    exts = view.get("extensions")
    if isinstance(exts, dict) and any("meshopt" in k for k in exts):
        d.fail(vw, "compressed (meshopt), which this reader does not decode")
    blen, source = d.buffer(bi)
    if voff + vlen > blen:
        d.fail(vw, f"byteOffset {voff} + byteLength {vlen} exceed buffers[{bi}].byteLength {blen}")
    if (voff + start) % comp:
        d.fail(where, f"data at byte {voff + start} of the buffer is not aligned to {comp} bytes")
    step = stride or elem
    need = start + step * (count - 1) + elem
    if need > vlen:
        d.fail(where, f"{count} elements need {need} bytes of {vw}, which has {vlen}")
    return d.read(source, voff + start, need - start if count else 0, where), step


def _elements(raw: bytes, dtype, count: int, width: int, step: int) -> np.ndarray:
    return np.ndarray(
        shape=(count, width), dtype=dtype, buffer=raw, offset=0, strides=(step, dtype.itemsize)
    )


def _accessor(d: _Doc, k: int, expect: str, types: set, what: str, times=False) -> np.ndarray:
    """Accessor k as float64 (count, width), after checking it against the specification:
    its type is ``expect`` and (componentType, normalized) one of ``types``."""
    where = f"accessors[{k}]"
    acc = d.item("accessors", k)
    comp = acc.get("componentType")
    if not _is_int(comp) or comp not in _COMP:
        d.fail(f"{where}.componentType", f"{_show(comp)} is not a glTF component type")
    norm = acc.get("normalized", False)
    if not isinstance(norm, bool):
        d.fail(f"{where}.normalized", f"{_show(norm)} is not a boolean")
    if norm and comp in (5125, 5126):
        d.fail(f"{where}.normalized", "only byte and short components can be normalized")
    kind = acc.get("type")
    if not isinstance(kind, str) or kind not in _WIDTH:
        d.fail(f"{where}.type", f"{_show(kind)} is not an accessor type")
    if kind != expect or (comp, norm) not in types:
        names = {5120: "BYTE", 5121: "UNSIGNED_BYTE", 5122: "SHORT", 5123: "UNSIGNED_SHORT"}
        names.update({5125: "UNSIGNED_INT", 5126: "FLOAT"})
        got = f"{kind} {'normalized ' if norm else ''}{names[comp]}"
        d.fail(where, f"{got} cannot hold {what}")
    count = d.integer(acc, "count", where, 1)
    offset = d.integer(acc, "byteOffset", where, 0, default=0)
    dtype, width = _COMP[comp], _WIDTH[kind]
    elem = dtype.itemsize * width
    if offset % dtype.itemsize:
        d.fail(f"{where}.byteOffset", f"{offset} is not a multiple of {dtype.itemsize}")
    vi = d.index(acc, "bufferView", where, "bufferViews", required=False)
    sparse = acc.get("sparse")
    if vi is None:
        if offset:
            d.fail(f"{where}.byteOffset", "given without a bufferView")
        # Without data the values are zeros (with the sparse values on top). Increasing key
        # times allow one zero besides the sparse values; an output accessor's count was
        # checked against its key times before this point.
        n = sparse.get("count") if isinstance(sparse, dict) else 0
        if times and count > 1 + (n if _is_int(n) else 0):
            d.fail(where, f"{count} key times without data (zeros, not increasing)")
        out = np.zeros((count, width))
    else:
        raw, step = _view_data(d, vi, offset, count, elem, dtype.itemsize, where)
        with np.errstate(invalid="ignore", over="ignore"):  # NaN rows: refused later
            out = _elements(raw, dtype, count, width, step).astype(np.float64)
    if sparse is not None:
        _sparse(d, where, sparse, out, count, dtype, width)
    if norm:
        info = np.iinfo(dtype)
        out = np.maximum(out / info.max, -1.0) if info.min < 0 else out / info.max
    return out


def _sparse(d: _Doc, where: str, sparse, out: np.ndarray, count: int, dtype, width: int):
    sw = f"{where}.sparse"
    if not isinstance(sparse, dict):
        d.fail(sw, "is not an object")
    n = d.integer(sparse, "count", sw, 1)
    if n > count:
        d.fail(f"{sw}.count", f"{n} exceeds the accessor's count {count}")
    parts = {}
    for key in ("indices", "values"):
        part = sparse.get(key)
        pw = f"{sw}.{key}"
        if not isinstance(part, dict):
            d.fail(pw, "missing or not an object")
        vi = d.index(part, "bufferView", pw, "bufferViews")
        off = d.integer(part, "byteOffset", pw, 0, default=0)
        if key == "indices":
            ct = part.get("componentType")
            if ct not in (5121, 5123, 5125) or not _is_int(ct):
                d.fail(f"{pw}.componentType", f"{_show(ct)} is not an unsigned integer type")
            dt, w = _COMP[ct], 1
        else:
            dt, w = dtype, width
        raw, step = _view_data(d, vi, off, n, dt.itemsize * w, dt.itemsize, pw)
        parts[key] = _elements(raw, dt, n, w, step)
    idx = parts["indices"][:, 0].astype(np.int64)
    if np.any(idx >= count) or np.any(np.diff(idx) <= 0):
        d.fail(f"{sw}.indices", f"must be strictly increasing and below the count {count}")
    out[idx] = parts["values"].astype(np.float64)


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

    Raises
    ------
    ValueError
        A file that breaks the glTF 2.0 specification in a field the reader uses (the
        message names the file and the field, e.g. ``accessors[3].byteOffset``), a missing
        node or animation, key times that are not increasing.
    """
    path = Path(path)
    check_regular_input(path)
    d = _Doc(path)
    asset = d.json.get("asset")
    version = asset.get("version") if isinstance(asset, dict) else None
    if not isinstance(version, str) or not re.match(r"2\.\d+$", version):
        d.fail("asset.version", f"{_show(version)}; only glTF 2.x files are read")
    anims = d.array(d.json, "animations", "")
    if not anims:
        d.fail("", "no animations in this file")
    nodes = d.array(d.json, "nodes", "")

    def nname(i):
        nd = nodes[i] if 0 <= i < len(nodes) else None
        name = nd.get("name") if isinstance(nd, dict) else None
        return name if isinstance(name, str) and name else f"#{i}"

    for i, a in enumerate(anims):
        if not isinstance(a, dict):
            d.fail(f"animations[{i}]", "is not an object")
        d.string(a, "name", f"animations[{i}]")
    if animation is not None:
        idx = [
            i
            for i, a in enumerate(anims)
            if (_is_int(animation) and i == animation) or a.get("name") == animation
        ]
        if not idx:
            names = ", ".join(a.get("name") or f"#{i}" for i, a in enumerate(anims))
            d.fail("", f"no animation {animation!r}; animations: {names}")
        anims_sel = [idx[0]]
    else:
        anims_sel = range(len(anims))
    animated: dict = {}
    for ai in anims_sel:
        aw = f"animations[{ai}]"
        a = anims[ai]
        samplers = d.array(a, "samplers", aw, required=True)
        for ci, ch in enumerate(d.array(a, "channels", aw, required=True)):
            cw = f"{aw}.channels[{ci}]"
            if not isinstance(ch, dict) or not isinstance(ch.get("target"), dict):
                d.fail(cw, "is not an object with a target")
            tgt = ch["target"]
            tpath = d.string(tgt, "path", f"{cw}.target")
            if tpath is None:
                d.fail(f"{cw}.target.path", "missing")
            si = ch.get("sampler")
            if not _is_int(si) or not 0 <= si < len(samplers):
                d.fail(f"{cw}.sampler", f"{_show(si)} is not an index into {aw}.samplers")
            ni = d.index(tgt, "node", f"{cw}.target", "nodes", required=False)
            if ni is None or tpath not in ("rotation", "translation"):
                continue
            slot = animated.setdefault(ni, {}).setdefault(ai, {})
            if tpath in slot:
                d.fail(cw, f"a second channel for node {ni}'s {tpath} in one animation")
            slot[tpath] = si
    if node is None:
        if len(animated) != 1:
            d.fail(
                "",
                f"{len(animated)} animated nodes; choose one with node= (--node): "
                + ", ".join(nname(i) for i in sorted(animated)),
            )
        ni = next(iter(animated))
    else:
        match = [i for i in range(len(nodes)) if nname(i) == node or str(i) == str(node)]
        if not match:
            d.fail(
                "",
                f"no node {node!r}; animated nodes: "
                + (", ".join(nname(i) for i in sorted(animated)) or "none"),
            )
        ni = match[0]
        if ni not in animated:
            d.fail(
                "",
                f"node {node!r} has no rotation or translation animation; animated "
                "nodes: " + (", ".join(nname(i) for i in sorted(animated)) or "none"),
            )
    nw = f"nodes[{ni}]"
    nd = d.item("nodes", ni)
    d.string(nd, "name", nw)
    if "matrix" in nd:
        d.fail(f"{nw}.matrix", "an animated node must not have a matrix (only TRS)")
    ai, chans = next(iter(animated[ni].items()))
    samplers = anims[ai]["samplers"]
    ext = d.array(d.json, "extensionsUsed", "")
    quantized = "KHR_mesh_quantization" in ext

    def sampler(k, what):
        sw = f"animations[{ai}].samplers[{k}]"
        s = samplers[k]
        if not isinstance(s, dict):
            d.fail(sw, "is not an object")
        kind = d.string(s, "interpolation", sw, default="LINEAR")
        if kind not in ("LINEAR", "STEP", "CUBICSPLINE"):
            d.fail(f"{sw}.interpolation", f"unknown interpolation {kind!r}")
        ki = d.index(s, "input", sw, "accessors")
        oi = d.index(s, "output", sw, "accessors")
        kt = _accessor(d, ki, "SCALAR", {(5126, False)}, "key times (SCALAR FLOAT)", True)[:, 0]
        bad = ~np.isfinite(kt)
        bad[1:] |= ~(kt[1:] > kt[:-1])
        if np.any(bad) or kt[0] < 0:
            i = int(np.argmax(bad)) if np.any(bad) else 0
            d.fail(
                f"accessors[{ki}]",
                "key times must be finite, non-negative and strictly increasing "
                f"(key {i}: {float(kt[i])!r})",
            )
        per = 3 if kind == "CUBICSPLINE" else 1
        if kind == "CUBICSPLINE" and len(kt) < 2:
            d.fail(sw, "CUBICSPLINE needs at least two keys")
        ocount = d.item("accessors", oi).get("count")
        if not _is_int(ocount) or ocount != len(kt) * per:
            d.fail(
                f"accessors[{oi}].count",
                f"{_show(ocount)} output values for {len(kt)} key times ({kind} needs "
                f"{len(kt) * per})",
            )
        if what == "rotation":
            kv = _accessor(d, oi, "VEC4", _ROTATION_TYPES, "rotations")
        else:
            types = {(5126, False)} | (_QUANTIZED_TRANSLATION if quantized else set())
            kv = _accessor(d, oi, "VEC3", types, "translations")
        return kind, kt, kv

    pos = None
    if "rotation" in chans:
        kind, kt, kv = sampler(chans["rotation"], "rotation")
        times = kt
        quats = (kv[1::3] if kind == "CUBICSPLINE" else kv)[:, [3, 0, 1, 2]]
        if "translation" in chans:
            pk, pt, pv = sampler(chans["translation"], "translation")
            if len(pt) == len(kt) and np.array_equal(pt, kt):
                pos = pv[1::3] if pk == "CUBICSPLINE" else pv
            else:
                pos = _play_channel(pk, pt, pv, kt, rot=False)
    else:
        pk, times, pv = sampler(chans["translation"], "translation")
        pos = pv[1::3] if pk == "CUBICSPLINE" else pv
        r = nd.get("rotation", [0.0, 0.0, 0.0, 1.0])
        ok = isinstance(r, list) and len(r) == 4
        ok = ok and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in r)
        if not ok or not all(math.isfinite(x) for x in r) or abs(math.hypot(*r) - 1) > 1e-3:
            d.fail(f"{nw}.rotation", "is not a unit quaternion of four numbers")
        quats = np.tile(np.array(r, dtype=float)[[3, 0, 1, 2]], (len(times), 1))
    with np.errstate(invalid="ignore", over="ignore"):
        return finish(
            path, times, quats, pos, np.arange(1, len(times) + 1), sort, dedupe, name=nname(ni)
        )


# ---- writing ------------------------------------------------------------------------------
#: The largest finite float32 value (glTF stores times, values and meshes as float32).
F32_MAX = float(np.finfo(np.float32).max)


def sign_continuous(q: np.ndarray) -> np.ndarray:
    """Flips signs so consecutive quaternions have a non-negative dot product (players
    interpolate component-wise or by slerp between the stored keys, so ``q`` and ``−q`` are
    not the same key to them)."""
    flips = np.concatenate([[False], np.sum(q[1:] * q[:-1], axis=1) < 0])
    sign = np.where(np.cumsum(flips) % 2 == 1, -1.0, 1.0)
    return q * sign[:, None]


@dataclass
class Keys:
    """One channel's keys as the document stores them.

    ``times`` (N,) in seconds from 0; ``values`` (N, 4) rotations (w, x, y, z) or (N, 3)
    translations; for CUBICSPLINE the one-sided derivatives ``in_tangents`` and
    ``out_tangents`` (per second, same shape as ``values``). Stored as float32.
    """

    times: np.ndarray
    values: np.ndarray
    in_tangents: np.ndarray | None = None
    out_tangents: np.ndarray | None = None


def check_options(path, interpolation: str, node, mesh, size) -> tuple[Path, float]:
    """Refuses an option of the document before anything is computed or written; returns the
    output path and the mesh size as a float."""
    if interpolation not in ("linear", "cubicspline"):
        raise ValueError(
            f"interpolation: expected 'linear' or 'cubicspline', got {interpolation!r}"
        )
    if mesh not in ("axes", None):
        raise ValueError(f"mesh: expected 'axes' or None, got {mesh!r}")
    if not isinstance(node, str):
        raise TypeError(f"node: expected a string, got {type(node).__name__}")
    if not node:
        raise ValueError("node: expected a non-empty name")
    try:
        node.encode("utf-8")
    except UnicodeEncodeError:
        raise ValueError("node: not valid Unicode text (a lone surrogate)") from None
    size = _checks.real(size, "size", positive=True)
    if not size <= F32_MAX:
        raise ValueError(f"size: {size:g} m is beyond float32 range (glTF stores float32)")
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path: expected a file path, got {type(path).__name__}")
    path = Path(path)
    if path.suffix.lower() not in (".glb", ".gltf"):
        raise ValueError(f"{path}: expected a .glb or .gltf output")
    return path, size


def _axes_mesh(size: float):
    """Three boxes along +x, +y, +z (red, green, blue), 8 vertices and 12 triangles each."""
    w = size * 0.04
    prims = []
    for k in range(3):
        lo, hi = np.full(3, -w), np.full(3, w)
        hi[k] = size
        c = np.array(
            [[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
        )
        faces = [
            (0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
            (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3),
        ]  # fmt: skip
        prims.append((c.astype(np.float32), np.array(faces, dtype=np.uint16).ravel()))
    return prims


class _Builder:
    """The binary buffer and its bufferViews and accessors, each view 4-byte aligned."""

    def __init__(self):
        self.blob = bytearray()
        self.views, self.accessors = [], []

    def add(self, arr: np.ndarray, kind: str, target=None, minmax: bool = False) -> int:
        arr = np.ascontiguousarray(arr)
        while len(self.blob) % 4:
            self.blob.append(0)
        view = {"buffer": 0, "byteOffset": len(self.blob), "byteLength": arr.nbytes}
        if target:
            view["target"] = target
        self.blob += arr.tobytes()
        self.views.append(view)
        comp = {np.dtype(np.float32): 5126, np.dtype(np.uint16): 5123}[arr.dtype]
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[kind]
        acc = {
            "bufferView": len(self.views) - 1,
            "componentType": comp,
            "count": int(arr.size // width),
            "type": kind,
        }
        if minmax:
            a2 = arr.reshape(-1, width)
            acc["min"] = [float(x) for x in a2.min(axis=0)]
            acc["max"] = [float(x) for x in a2.max(axis=0)]
        self.accessors.append(acc)
        return len(self.accessors) - 1


def _check_keys(path: Path, channel: str, keys: Keys, width: int, cubic: bool):
    """The keys as float32 arrays (times, values, in/out tangents), refused with a one-line
    error naming the file and the channel unless glTF can hold them: finite, within float32,
    times non-negative and strictly increasing once stored as float32."""
    where = f"{path}: {channel} keys"
    t = np.asarray(keys.times, dtype=float).reshape(-1)
    arrays = [("values", keys.values)]
    if cubic:
        arrays += [("in_tangents", keys.in_tangents), ("out_tangents", keys.out_tangents)]
    out = []
    for what, v in arrays:
        if v is None:
            raise ValueError(f"{where}: CUBICSPLINE needs {what}")
        v = np.asarray(v, dtype=float)
        if v.shape != (len(t), width):
            raise ValueError(f"{where}: {what} of shape {v.shape}, expected ({len(t)}, {width})")
        if not np.all(np.isfinite(v)) or np.abs(v).max(initial=0.0) > F32_MAX:
            raise ValueError(f"{where}: {what} hold NaN, inf or values beyond float32 range")
        out.append(v)
    if len(t) == 0 or (cubic and len(t) < 2):
        raise ValueError(f"{where}: {len(t)} keys (glTF needs {2 if cubic else 1} or more)")
    with np.errstate(over="ignore"):
        t32 = t.astype(np.float32)
    bad = ~np.isfinite(t32) | (t32 < 0)
    if np.any(bad):
        k = int(np.argmax(bad))
        raise ValueError(
            f"{where}: time {float(t[k])!r} (key {k}) is not a float32 time ≥ 0 (glTF stores "
            "key times as float32 seconds from 0)"
        )
    same = t32[1:] <= t32[:-1]
    if np.any(same):
        k = int(np.argmax(same)) + 1
        raise ValueError(
            f"{where}: times {float(t[k - 1])!r} and {float(t[k])!r} (keys {k - 1} and {k}) "
            "are not increasing once stored as float32, as glTF stores key times"
        )
    return t, out


def write_animation(
    path,
    rotation: Keys,
    translation: Keys | None = None,
    *,
    interpolation: str = "linear",
    node: str = "body",
    mesh: str | None = "axes",
    size: float = 0.1,
    name: str = "",
) -> None:
    """Writes one animated node as a glTF 2.0 document, atomically.

    The format's writer: the keys are stored as they are given (float32), in one buffer with
    a bufferView and accessor each, one sampler and channel per path of the node; the node's
    static rotation and translation are the first keys. :func:`write` gives it a
    trajectory's samples, :func:`quatspline.ops.to_gltf` the error-bounded keys of a spline.

    Parameters
    ----------
    path : path-like
        ``.glb`` (binary) or ``.gltf`` (JSON with the data embedded as a base64 data URI).
    rotation : Keys
        Rotation keys, (w, x, y, z) values (stored (x, y, z, w) as glTF does).
    translation : Keys, optional
        Translation keys (metres).
    interpolation : {"linear", "cubicspline"}
        The samplers' interpolation (CUBICSPLINE keys need their tangents).
    node : str
        The node's name (any non-empty Unicode text).
    mesh : {"axes", None}
        A small red/green/blue axes mesh of length ``size`` (metres), or an empty node.
    name : str, optional
        The scene's and the animation's name (a trajectory's name).

    Raises
    ------
    ValueError
        An option, or keys glTF cannot hold (the message names the file and the channel).
    TypeError
        An option of the wrong kind.
    """
    path, size = check_options(path, interpolation, node, mesh, size)
    cubic = interpolation == "cubicspline"
    channels = [("rotation", rotation, 4)]
    if translation is not None:
        channels.append(("translation", translation, 3))
    checked = []
    for channel, keys, width in channels:
        if not isinstance(keys, Keys):
            raise TypeError(f"{channel}: expected gltf.Keys, got {type(keys).__name__}")
        checked.append((channel, *_check_keys(path, channel, keys, width, cubic)))
    # a name from a file name may hold lone surrogates (undecodable bytes): JSON needs Unicode
    label = name.encode("utf-8", "replace").decode("utf-8") if name else ""
    b = _Builder()
    doc: dict = {
        "asset": {"version": "2.0", "generator": "quatspline"},
        "scene": 0,
        "scenes": [{"name": label or "quatspline", "nodes": [0]}],
        "nodes": [{"name": node}],
    }
    if mesh == "axes":
        colours = ([0.84, 0.15, 0.16, 1.0], [0.17, 0.63, 0.17, 1.0], [0.12, 0.47, 0.71, 1.0])
        prims = []
        for k, (pts, idx) in enumerate(_axes_mesh(float(size))):
            pa = b.add(pts, "VEC3", target=34962, minmax=True)
            ia = b.add(idx, "SCALAR", target=34963)
            prims.append({"attributes": {"POSITION": pa}, "indices": ia, "material": k})
        doc["materials"] = [
            {"name": f"axis {'xyz'[k]}", "pbrMetallicRoughness": {"baseColorFactor": c}}
            for k, c in enumerate(colours)
        ]
        doc["meshes"] = [{"name": "axes", "primitives": prims}]
        doc["nodes"][0]["mesh"] = 0
    gl_channels, samplers = [], []
    for channel, kt, values in checked:
        if channel == "rotation":
            values = [v[:, [1, 2, 3, 0]] for v in values]  # glTF stores (x, y, z, w)
        kv = values[0]
        out = np.stack([values[1], kv, values[2]], axis=1).reshape(-1, kv.shape[1]) if cubic else kv
        ia = b.add(kt.astype(np.float32), "SCALAR", minmax=True)
        oa = b.add(out.astype(np.float32), "VEC4" if channel == "rotation" else "VEC3")
        samplers.append({"input": ia, "output": oa, "interpolation": interpolation.upper()})
        gl_channels.append({"sampler": len(samplers) - 1, "target": {"node": 0, "path": channel}})
        doc["nodes"][0][channel] = kv[0].astype(np.float32).astype(float).tolist()
    doc["animations"] = [{"name": label or "motion", "channels": gl_channels, "samplers": samplers}]
    doc["accessors"], doc["bufferViews"] = b.accessors, b.views
    _write_file(path, doc, bytes(b.blob))


def _write_file(path: Path, doc: dict, blob: bytes) -> None:
    """The document as ``.gltf`` (JSON, the buffer as a data URI) or ``.glb`` (binary),
    written atomically."""
    if path.suffix.lower() == ".gltf":
        doc["buffers"] = [
            {
                "byteLength": len(blob),
                "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode(),
            }
        ]
        with atomic_write(path, encoding="utf-8") as f:
            json.dump(doc, f, separators=(",", ":"))
        return
    doc["buffers"] = [{"byteLength": len(blob)}]
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    bin_ = bytes(blob) + b"\0" * (-len(blob) % 4)
    total = 12 + 8 + len(js) + 8 + len(bin_)
    with atomic_write(path, mode="wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, total))
        f.write(struct.pack("<I4s", len(js), b"JSON") + js)
        f.write(struct.pack("<I4s", len(bin_), b"BIN\0") + bin_)


def write(
    path, traj: Trajectory, node: str = "body", mesh: str | None = "axes", size: float = 0.1
) -> None:
    """Writes the trajectory's samples as the LINEAR keys of one node, exact at every sample.

    Each sample is a key: its time (from the first sample's, which is 0 in the file), its
    orientation (normalised, signs made continuous so players interpolate the short way) and
    its position, all as glTF stores them (float32). Between samples players interpolate
    linearly (slerp). This writes what the trajectory holds, like every other writer; an
    export of a spline through the samples with a guaranteed playback error between them
    is :func:`quatspline.ops.to_gltf` (``quatspline export``).

    Parameters
    ----------
    path : path-like
        A ``.glb`` or ``.gltf`` file.
    traj : Trajectory
        The samples (no extra columns: glTF has no place for them).
    node : str
        The animated node's name.
    mesh : {"axes", None}
        A small axes mesh of length ``size`` (metres), or an empty node.

    Raises
    ------
    ValueError
        What the reader would reject (no rows, NaN, repeated times), extra columns, times that
        float32 cannot tell apart, positions beyond float32 range.

    Examples
    --------
    >>> import tempfile, os, numpy as np
    >>> from quatspline import io
    >>> tr = io.Trajectory([10.0, 10.5, 11.0], [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     io.write(os.path.join(d, "m.glb"), tr)
    ...     back = io.read(os.path.join(d, "m.glb"))
    >>> back.times, np.abs(back.quats).round(6).tolist()
    (array([0. , 0.5, 1. ]), [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])
    """
    path, _ = check_options(path, "linear", node, mesh, size)
    check_for_writing(path, traj)
    refuse_extra(path, traj, "glTF")
    with np.errstate(over="ignore", invalid="ignore"):
        t = traj.times - traj.times[0]
    _, unit = quat_norms(traj.quats)
    rotation = Keys(t, sign_continuous(unit))
    translation = None if traj.positions is None else Keys(t, traj.positions)
    write_animation(path, rotation, translation, node=node, mesh=mesh, size=size, name=traj.name)
