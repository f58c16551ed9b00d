"""glTF files as an attacker or a careless exporter writes them: declarations that would make
the reader allocate or read far more than the file holds, fields that break the glTF 2.0
specification, and every field of valid files mutated in turn. Each must be read correctly
or refused with one TrajectoryError line naming the file and the field."""

from __future__ import annotations

import base64
import copy
import json
import struct
import tracemalloc

import numpy as np
import pytest
import quatspline.io as qio
from quatspline.io import TrajectoryError
from quatspline.ops._export import to_gltf

from ..ops.test_gltf import wavy_pose

#: Far below what the hostile declarations would allocate (GiB to TiB).
PEAK_LIMIT = 32 << 20


def exported(tmp_path, interpolation="linear", suffix=".gltf"):
    path = tmp_path / f"valid-{interpolation}{suffix}"
    to_gltf(
        wavy_pose(n=5),
        path,
        max_error="0.5deg",
        max_position_error="5mm",
        interpolation=interpolation,
        mesh=None,
        uniform=False,
        progress=False,
    )
    return path


def split_gltf(path):
    """(JSON document, binary buffer) of an exported .gltf (one data-URI buffer)."""
    doc = json.loads(path.read_text())
    uri = doc["buffers"][0]["uri"]
    return doc, base64.b64decode(uri.split(",", 1)[1])


def write_gltf(path, doc, blob=None):
    doc = copy.deepcopy(doc)
    if blob is not None:
        doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + (
            base64.b64encode(blob).decode()
        )
    path.write_text(json.dumps(doc))
    return path


def glb_bytes(doc, blob: bytes, bin_length=None) -> bytes:
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    blob += b"\0" * (-len(blob) % 4)
    n = len(blob) if bin_length is None else bin_length
    total = 12 + 8 + len(js) + 8 + n
    return (
        struct.pack("<4sII", b"glTF", 2, total)
        + struct.pack("<I4s", len(js), b"JSON")
        + js
        + struct.pack("<I4s", n, b"BIN\0")
        + blob
    )


def refused(path, where=None):
    """Reads path; asserts one TrajectoryError line naming the file (and ``where``)."""
    with pytest.raises(TrajectoryError) as e:
        qio.read(path)
    msg = str(e.value)
    assert str(path) in msg and "\n" not in msg, msg
    if where is not None:
        assert where in msg, msg
    return msg


def peak_of(fn):
    tracemalloc.start()
    try:
        fn()
    finally:
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    return peak


def sampler_accessors(doc, path_name):
    anim = doc["animations"][0]
    (ch,) = [c for c in anim["channels"] if c["target"]["path"] == path_name]
    s = anim["samplers"][ch["sampler"]]
    return s["input"], s["output"]


# ---- item: allocation from declarations ------------------------------------------------------
@pytest.mark.parametrize("count", [150_000_000, 10**12])
@pytest.mark.parametrize("which", ["output-no-view", "input-no-view", "output", "input"])
def test_gltf_declared_count_does_not_allocate_beyond_the_file(tmp_path, count, which):
    doc, blob = split_gltf(exported(tmp_path))
    ki, oi = sampler_accessors(doc, "rotation")
    k = oi if which.startswith("output") else ki
    doc["accessors"][k]["count"] = count
    if which.endswith("no-view"):
        del doc["accessors"][k]["bufferView"]
    path = write_gltf(tmp_path / "huge.gltf", doc)
    assert path.stat().st_size < 4000
    peak = peak_of(lambda: refused(path, f"accessors[{k}]"))
    assert peak < PEAK_LIMIT, peak


def test_gltf_declared_buffer_length_beyond_the_data_is_refused(tmp_path):
    doc, blob = split_gltf(exported(tmp_path))
    doc["buffers"][0]["byteLength"] = 10**12
    refused(write_gltf(tmp_path / "b.gltf", doc), "buffers[0]")
    # a GLB whose BIN chunk declares more bytes than the file has
    glb = tmp_path / "b.glb"
    doc2, _ = split_gltf(exported(tmp_path))
    del doc2["buffers"][0]["uri"]
    glb.write_bytes(glb_bytes(doc2, blob, bin_length=len(blob) + 10**9))
    refused(glb, "GLB")


def _sparse_tail(path, size):
    with open(path, "r+b") as f:
        f.truncate(size)


@pytest.mark.parametrize("kind", ["external", "glb"])
def test_gltf_reads_only_the_byte_ranges_it_uses(tmp_path, kind):
    """A 256 MiB buffer (sparse on disk) of which the animation uses a few hundred bytes."""
    size = 256 << 20
    doc, blob = split_gltf(exported(tmp_path))
    doc["buffers"][0]["byteLength"] = size
    if kind == "external":
        (tmp_path / "big.bin").write_bytes(blob)
        _sparse_tail(tmp_path / "big.bin", size)
        doc["buffers"][0]["uri"] = "big.bin"
        path = write_gltf(tmp_path / "ext.gltf", doc)
    else:
        del doc["buffers"][0]["uri"]
        path = tmp_path / "big.glb"
        path.write_bytes(glb_bytes(doc, blob, bin_length=size))
        _sparse_tail(path, path.stat().st_size + size - len(blob) - (-len(blob) % 4))
    tr = []
    peak = peak_of(lambda: tr.append(qio.read(path)))
    assert peak < PEAK_LIMIT, peak
    ref = qio.read(exported(tmp_path))
    np.testing.assert_array_equal(tr[0].quats, ref.quats)
    np.testing.assert_array_equal(tr[0].positions, ref.positions)


# ---- item: files that break the specification --------------------------------------------
def _mutations():
    """(name, mutate(doc) -> location the message must name)."""

    def stride(doc, value):
        _, oi = sampler_accessors(doc, "rotation")
        v = doc["accessors"][oi]["bufferView"]
        doc["bufferViews"][v]["byteStride"] = value
        return f"bufferViews[{v}].byteStride"

    def acc_field(path_name, io, key, value):
        def f(doc):
            k = sampler_accessors(doc, path_name)[io]
            doc["accessors"][k][key] = value
            return f"accessors[{k}]"

        return f

    def chan(key, value):
        def f(doc):
            doc["animations"][0]["channels"][0]["target"][key] = value
            return f"animations[0].channels[0].target.{key}"

        return f

    def view_field(key, value):
        def f(doc):
            k = sampler_accessors(doc, "rotation")[1]
            v = doc["accessors"][k]["bufferView"]
            doc["bufferViews"][v][key] = value
            return f"bufferViews[{v}]"

        return f

    def sampler(key, value):
        def f(doc):
            doc["animations"][0]["samplers"][0][key] = value
            return f"animations[0].samplers[0].{key}"

        return f

    def dup_channel(doc):
        chans = doc["animations"][0]["channels"]
        chans.append(copy.deepcopy(chans[0]))
        return "animations[0].channels[2]"

    def matrix(doc):
        doc["nodes"][0]["matrix"] = [1.0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
        return "nodes[0].matrix"

    def version(doc):
        doc["asset"]["version"] = "1.0"
        return "asset.version"

    return {
        "byteStride 1 on a VEC4 view": lambda d: stride(d, 1),
        "byteStride 6 (not a multiple of 4)": lambda d: stride(d, 6),
        "byteStride 256 (above 252)": lambda d: stride(d, 256),
        "byteStride 8 below a VEC4 float element": lambda d: stride(d, 8),
        "negative accessor byteOffset": acc_field("rotation", 1, "byteOffset", -4),
        "misaligned accessor byteOffset": acc_field("rotation", 1, "byteOffset", 2),
        "non-integer count": acc_field("rotation", 1, "count", 1.5),
        "boolean count": acc_field("rotation", 0, "count", True),
        "zero count": acc_field("rotation", 0, "count", 0),
        "unsigned int rotations": acc_field("rotation", 1, "componentType", 5125),
        "normalized float": acc_field("rotation", 1, "normalized", True),
        "rotation as VEC3": acc_field("rotation", 1, "type", "VEC3"),
        "translation as VEC4": acc_field("translation", 1, "type", "VEC4"),
        "byte translation without quantization": acc_field("translation", 1, "componentType", 5120),
        "integer key times": acc_field("rotation", 0, "componentType", 5125),
        "key times as VEC2": acc_field("rotation", 0, "type", "VEC2"),
        "unknown component type": acc_field("rotation", 0, "componentType", 7),
        "accessor bufferView -1": acc_field("rotation", 1, "bufferView", -1),
        "channel node -5": chan("node", -5),
        "channel node past the end": chan("node", 99),
        "channel node as a string": chan("node", "0"),
        "channel path not a string": chan("path", 3),
        "sampler input out of range": sampler("input", 1000),
        "sampler output negative": sampler("output", -1),
        "unknown interpolation": sampler("interpolation", "CUBIC"),
        "negative view byteOffset": view_field("byteOffset", -8),
        "view beyond its buffer": view_field("byteLength", 10**6),
        "view buffer index 3": view_field("buffer", 3),
        "two channels for one target": dup_channel,
        "animated node with a matrix": matrix,
        "glTF 1.0": version,
        "animated node named by a number": lambda d: _node_name(d),
    }


def _node_name(doc):
    doc["nodes"][0]["name"] = 7
    return "nodes[0].name"


MUTATIONS = _mutations()


@pytest.mark.parametrize("name", list(MUTATIONS))
def test_gltf_that_breaks_the_specification_is_refused_naming_the_field(tmp_path, name):
    doc, _ = split_gltf(exported(tmp_path))
    where = MUTATIONS[name](doc)
    refused(write_gltf(tmp_path / "bad.gltf", doc), where)


def test_gltf_negative_or_unordered_key_times_are_refused(tmp_path):
    doc, blob = split_gltf(exported(tmp_path))
    ki, _ = sampler_accessors(doc, "rotation")
    acc = doc["accessors"][ki]
    view = doc["bufferViews"][acc["bufferView"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    b = bytearray(blob)
    b[start : start + 4] = struct.pack("<f", -1.0)
    refused(write_gltf(tmp_path / "neg.gltf", doc, bytes(b)), f"accessors[{ki}]")


# ---- the property: every field of valid files mutated in turn ------------------------------
HOSTILE = [-5, -1, 0, 1, 2, 3, 1.5, 2**31, 10**12, 2**64, "x", "", True, None, [], {}, [1]]
HOSTILE += [1e308, float("nan"), "data:,", "../x.bin", "/etc/passwd", "VEC4", "CUBICSPLINE"]
FEW = [-1, 1e308, float("nan"), "x", None, []]


def _leaves(obj, prefix=()):
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield prefix + (k,)
            yield from _leaves(v, prefix + (k,))
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield prefix + (i,)
            yield from _leaves(v, prefix + (i,))


def _set(doc, where, value, delete):
    d = copy.deepcopy(doc)
    parent = d
    for k in where[:-1]:
        parent = parent[k]
    if delete and isinstance(parent, dict):
        del parent[where[-1]]
    else:
        parent[where[-1]] = value
    return d


def _read_or_refused(path):
    """A valid trajectory or one TrajectoryError line naming the file; nothing else."""
    try:
        tr = qio.read(path)
    except TrajectoryError as e:
        assert str(path) in str(e) and "\n" not in str(e), str(e)
        return
    assert len(tr) > 0 and np.all(np.diff(tr.times) > 0)
    assert np.all(np.isfinite(tr.quats)) and np.allclose(np.linalg.norm(tr.quats, axis=1), 1)
    assert tr.positions is None or np.all(np.isfinite(tr.positions))


@pytest.mark.parametrize("interpolation", ["linear", "cubicspline"])
def test_gltf_hostile_mutation_of_every_field_raises_only_trajectory_error(tmp_path, interpolation):
    doc, blob = split_gltf(exported(tmp_path, interpolation))
    n = 0
    for where in _leaves(doc):
        if where[:2] == ("buffers", 0) and where[-1] == "uri":
            values = [v for v in HOSTILE if isinstance(v, str)] + [None, 3]
        elif isinstance(where[-1], int) and where[-2] in ("min", "max", "translation"):
            values = FEW  # numbers the reader does not use (static TRS, bounds)
        else:
            values = HOSTILE
        for value in [*values, "<deleted>"]:
            target = tmp_path / f"m{n}.gltf"  # a new file: truncating one is slower
            write_gltf(target, _set(doc, where, value, delete=value == "<deleted>"))
            _read_or_refused(target)
            target.unlink()
            n += 1
    assert n > 500


def test_gltf_damaged_glb_bytes_raise_only_trajectory_error(tmp_path):
    path = exported(tmp_path, suffix=".glb")
    data = path.read_bytes()
    rng = np.random.default_rng(3)
    target = tmp_path / "d.glb"
    for _ in range(400):
        b = bytearray(data)
        for _ in range(rng.integers(1, 4)):
            i = int(rng.integers(0, len(b)))
            b[i] = int(rng.integers(0, 256))
        if rng.random() < 0.2:
            b = b[: int(rng.integers(0, len(b)))]
        target.write_bytes(bytes(b))
        _read_or_refused(target)
