"""The Blender add-on in a real Blender (headless): what Blender's own F-curve evaluation
plays after each operator, at random frames, against quatspline's spline through the same
keys — within the stated bounds (0.01° and 0.1 mm by default), with the keys as Blender
stores them (float32) and no slack. One Blender run drives every scene of this file, in
each Blender of :data:`blender_run.BLENDERS` (Debian's 3.4 and the official 4.2 module)."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from quatspline.io.gltf import sign_continuous

from .blender_run import BLENDERS, jobs, skip_unless

FPS = 24
BOUND = np.radians(0.01)
POS_BOUND = 1e-4
RESAMPLE = [
    ("QUATERNION", "c3", "alpha=0.5", {"alpha": 0.5}),
    ("XYZ", "natural", "", {}),
    ("ZXY", "squad", "", {}),
]


def _f32(x):
    return np.asarray(x, dtype=np.float32).astype(float)


def _keys(seed=0, n=8, step=12):
    rng = np.random.default_rng(seed)
    frames = [1 + step * k for k in range(n)]
    return frames, rng.normal(0, 0.8, (n, 3)), rng.normal(0, 1, (n, 3))


def _resample_input(mode):
    frames, rv, loc = _keys()
    if mode == "QUATERNION":
        rot = qs.from_rotvec(rv)
        q = _f32(rot) / np.linalg.norm(_f32(rot), axis=1)[:, None]
    else:
        rot = rv
        q = qs.from_euler(mode.lower(), _f32(rv))  # Blender's Euler modes: extrinsic axes
    at = np.sort(np.random.default_rng(1).uniform(frames[0], frames[-1], 3000))
    return frames, rot, q, loc, at


def _noisy_input():
    rng = np.random.default_rng(3)
    frames = np.arange(1, 241, 2)  # 120 noisy samples over 10 s
    t = frames / FPS
    rv = np.column_stack([np.sin(t), 0.5 * np.cos(0.7 * t), 0.3 * t])
    p = np.column_stack([np.sin(0.5 * t), t / 10, np.cos(t)])
    rot = qs.from_rotvec(rv + rng.normal(0, 0.01, rv.shape))
    loc = p + rng.normal(0, 0.01, p.shape)
    at = np.sort(rng.uniform(frames[0], frames[-1], 3000))
    return frames, rot, loc, at


def _truth(t):
    rv = np.column_stack([np.sin(t), 0.5 * np.cos(0.7 * t), 0.3 * t])
    return qs.from_rotvec(rv), np.column_stack([np.sin(0.5 * t), t / 10, np.cos(t)])


def _tum(path, n, seed=5):
    rng = np.random.default_rng(seed)
    t = 1305031102.175304 + np.arange(n) / 30.0
    q = qs.from_rotvec(np.cumsum(rng.normal(0, 0.05, (n, 3)), axis=0))
    p = np.cumsum(rng.normal(0, 0.01, (n, 3)), axis=0)
    with open(path, "w", encoding="utf-8") as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n")
        for ti, pi, qi in zip(t, p, q):
            f.write(f"{ti:.6f} {pi[0]:.6f} {pi[1]:.6f} {pi[2]:.6f} "
                    f"{qi[1]:.8f} {qi[2]:.8f} {qi[3]:.8f} {qi[0]:.8f}\n")  # fmt: skip
    return qs.io.read(path)


def _object(mode, frames, rot, loc):
    return {"mode": mode, "frames": list(map(int, frames)), "rotation": np.asarray(rot).tolist(),
            "location": np.asarray(loc).tolist()}  # fmt: skip


@pytest.fixture(scope="module", params=list(BLENDERS))
def played(request, tmp_path_factory):
    """Every scene of this file through one run of each Blender: name → what it played."""
    skip_unless(request.param)
    d = tmp_path_factory.mktemp(f"blender-addon-{request.param}")
    specs = {}
    for mode, method, params, _ in RESAMPLE:
        frames, rot, _, loc, at = _resample_input(mode)
        specs[f"resample-{mode}"] = {
            "kind": "resample", "fps": FPS, "object": _object(mode, frames, rot, loc),
            "options": {"method": method, "params": params}, "frames": at.tolist(),
        }  # fmt: skip
    frames, rot, loc, at = _noisy_input()
    specs["fit"] = {"kind": "fit", "fps": FPS, "object": _object("QUATERNION", frames, rot, loc),
                    "frames": at.tolist()}  # fmt: skip
    for name, n, method in (("import-keys", 150, None), ("import-c3", 60, "c3")):
        traj = _tum(d / f"{name}.txt", n)
        t = traj.times - traj.times[0]
        at = np.concatenate([t * FPS, np.random.default_rng(2).uniform(0, t[-1] * FPS, 2000)])
        options = {"method": method} if method else {}
        specs[name] = {"kind": "import", "fps": FPS, "file": str(d / f"{name}.txt"),
                       "options": options, "frames": at.tolist()}  # fmt: skip
        specs[name]["_traj"] = traj
    frames, rv, loc = _keys(seed=7)
    specs["kinematics"] = {
        "kind": "kinematics", "fps": FPS,
        "object": _object("QUATERNION", frames, qs.from_rotvec(rv), loc),
        "options": {"method": "natural"},
        "frames": np.arange(frames[0], frames[-1] + 1, 1.0).tolist(),
    }  # fmt: skip
    frames, rv, loc = _keys()
    specs["bad-parameter"] = {
        "kind": "resample", "fps": FPS,
        "object": _object("QUATERNION", frames, qs.from_rotvec(rv), loc),
        "options": {"method": "c3", "params": "alpha=wide"}, "frames": [],
    }  # fmt: skip
    specs["axis-angle"] = {
        "kind": "resample", "fps": FPS,
        "object": _object("AXIS_ANGLE", frames, np.column_stack([np.ones(len(rv)), rv]), loc),
        "frames": [],
    }  # fmt: skip
    trajs = {k: s.pop("_traj") for k, s in specs.items() if "_traj" in s}
    out = jobs(d, specs, which=request.param)
    for k, s in specs.items():
        out[k]["frames"] = np.asarray(s["frames"])
        out[k]["which"] = request.param
        if k in trajs:
            out[k]["traj"] = trajs[k]
    return out


def test_the_scenes_ran_in_the_blender_named(played):
    """Debian's package is Blender 3.4; PyPI's bpy module the official 4.2 build."""
    want = {"blender": (3, 4), "bpy": (4, 2)}
    for name, out in played.items():
        assert tuple(out["blender"][:2]) == want[out["which"]], (name, out["blender"])


def _played(out):
    q = out["rotation"] / np.linalg.norm(out["rotation"], axis=1)[:, None]
    return q, out["location"]


def _errors(out, spline, t):
    q, p = _played(out)
    return qs.angle_between(q, spline.orientation(t)), np.linalg.norm(
        p - spline.position(t), axis=1
    )


@pytest.mark.parametrize(("mode", "method", "params", "kw"), RESAMPLE)
def test_resample_operator_keys_play_within_the_bound_in_blender(played, mode, method, params, kw):
    out = played[f"resample-{mode}"]
    frames, _, q, loc, at = _resample_input(mode)
    assert out["status"].tolist() == ["FINISHED"]
    assert out["mode"] == "QUATERNION" and out["euler_curves"] == 0
    assert out["interpolation"].tolist() == ["LINEAR"]
    spline = qs.PoseSpline(q, np.array(frames) / FPS, _f32(loc), rotation=method, **kw)
    e, ep = _errors(out, spline, at / FPS)
    assert e.max() <= BOUND, np.degrees(e.max())
    assert ep.max() <= POS_BOUND, ep.max()
    assert e.max() > BOUND / 3 and ep.max() > POS_BOUND / 3  # the bound is used, not wasted


def test_fit_operator_smooths_rotation_and_location_within_the_bound(played):
    out = played["fit"]
    frames, rot, loc, at = _noisy_input()
    assert out["status"].tolist() == ["FINISHED"]
    qf = _f32(rot) / np.linalg.norm(_f32(rot), axis=1)[:, None]
    fitted = qs.fit(frames / FPS, qf, positions=_f32(loc))
    e, ep = _errors(out, fitted, at / FPS)
    assert e.max() <= BOUND and ep.max() <= POS_BOUND, (np.degrees(e.max()), ep.max())
    # smoothed: closer to the noiseless motion than the samples are (σ = 0.01 rad, 1 cm)
    q, p = _played(out)
    truth_q, truth_p = _truth(at / FPS)
    assert np.sqrt(np.mean(qs.angle_between(q, truth_q) ** 2)) < 0.01
    assert np.sqrt(np.mean(np.sum((p - truth_p) ** 2, axis=1))) < 0.01


def test_import_of_a_tum_file_keys_its_samples_exactly(played):
    out = played["import-keys"]
    traj = out["traj"]
    t = traj.times - traj.times[0]
    n = len(traj)
    assert out["status"].tolist() == ["FINISHED"]
    assert out["keys"] == n and out["location_keys"] == n
    assert out["range"].tolist() == [0, int(np.ceil(t[-1] * FPS))]
    q, p = _played(out)
    # at the sample frames: the samples (float32 keys)
    assert np.max(qs.angle_between(q[:n], traj.quats)) < 1e-6
    assert np.max(np.abs(p[:n] - traj.positions)) < 1e-6
    # between them: Blender's LINEAR playback of those keys (component-wise, normalised)
    tt = out["frames"][n:] / FPS
    k = np.clip(np.searchsorted(t, tt, side="right") - 1, 0, n - 2)
    u = ((tt - t[k]) / (t[k + 1] - t[k]))[:, None]
    qk = sign_continuous(traj.quats)  # the import keys a sign-continuous path
    h = qk[k] + u * (qk[k + 1] - qk[k])
    assert np.max(qs.angle_between(q[n:], h / np.linalg.norm(h, axis=1)[:, None])) < 1e-5
    lin = traj.positions[k] + u * (traj.positions[k + 1] - traj.positions[k])
    assert np.max(np.abs(p[n:] - lin)) < 1e-5


def test_import_through_a_method_plays_its_spline_within_the_bound(played):
    out = played["import-c3"]
    traj = out["traj"]
    spline = qs.PoseSpline(traj.quats, traj.times - traj.times[0], traj.positions, rotation="c3")
    e, ep = _errors(out, spline, out["frames"] / FPS)
    assert e.max() <= BOUND and ep.max() <= POS_BOUND, (np.degrees(e.max()), ep.max())
    assert e.max() > BOUND / 3


def test_kinematics_operator_writes_the_splines_omega_alpha_and_jerk(played):
    out = played["kinematics"]
    frames, rv, _ = _keys(seed=7)
    q = _f32(qs.from_rotvec(rv))
    s = qs.spline("natural", q / np.linalg.norm(q, axis=1)[:, None], np.array(frames) / FPS)
    t = out["frames"] / FPS
    w = np.linalg.norm(s.angular_velocity(t), axis=1)
    a = np.linalg.norm(s.angular_acceleration(t), axis=1)
    j = np.linalg.norm(s.jerk(t), axis=1)
    for got, want in ((out["qs_omega"], w), (out["qs_alpha"], a), (out["qs_jerk"], j)):
        np.testing.assert_allclose(got, want, rtol=1e-5, atol=1e-5 * want.max())
    assert str(out["summary"]).startswith(f"max |ω| {w.max():.4g} rad/s")


@pytest.mark.parametrize(
    ("scene", "message"),
    [
        ("bad-parameter", "Error: alpha: "),
        (
            "axis-angle",
            "Error: body: rotation mode AXIS_ANGLE is not read; use QUATERNION or an Euler mode",
        ),
    ],
)
def test_operators_report_a_bad_value_in_one_line(played, scene, message):
    out = played[scene]
    assert out["status"].tolist() == ["ERROR"]
    assert str(out["error"]).startswith(message), str(out["error"])
    assert str(out["error"]).strip().count("\n") == 0
