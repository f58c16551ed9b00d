"""The high-breakdown start of robust fits on synthetic motions of different kinds (slow, fast,
speed varying along the recording) and glitch kinds (170°–180° flips, exact half turns,
uniformly random rotations): scattered glitches at 5 %, 20 % and 30 %, bursts of consecutive
flipped frames longer than the running medoid's window (rejected by the consensus of runs, or
a ValueError naming their time range — never a silent curve through them). Independent of the
bundled recordings."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs

T = np.linspace(0.0, 8.0, 801)


def rms(x):
    return float(np.sqrt(np.mean(np.asarray(x) ** 2)))


def motion(kind, t):
    """Slow (≤ 0.3 rad/s), fast (up to ~5 rad/s) or speed varying along the recording."""
    if kind == "slow":
        rv = [0.3 * np.sin(0.3 * t), 0.2 * np.cos(0.2 * t) - 0.2, 0.1 * t]
    elif kind == "fast":
        rv = [1.2 * np.sin(3.0 * t), 0.8 * np.cos(2.1 * t) - 0.8, 1.5 * t]
    else:
        bump = np.exp(-0.3 * (t - 4) ** 2)
        rv = [0.6 * np.sin(0.4 * t + 0.075 * t**2), 0.5 * np.sin(2.5 * t) * bump, 0.2 * t]
    return qs.from_rotvec(np.stack(rv, axis=1))


def glitch(rng, kind):
    """One glitch rotation: 170°–180° about a random axis, exactly 180°, or uniformly random."""
    if kind == "random":
        q = rng.normal(size=4)
        return q / np.linalg.norm(q)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    deg = 180.0 if kind == "half" else rng.uniform(170.0, 180.0)
    return qs.from_rotvec(axis * np.deg2rad(deg))


def noisy(kind, rng, deg=0.3):
    truth = motion(kind, T)
    return truth, qs.multiply(truth, qs.from_rotvec(rng.normal(size=(len(T), 3)) * np.deg2rad(deg)))


def error(f, truth):
    return rms(qs.angle_between(f(T), truth))


# The robust fits' error over the clean fit's (same frames without glitches), worst of the
# draws, measured before the consensus of runs dropped the flips: Cauchy ≤ 1.38 everywhere;
# Huber (a far glitch still pulls with c) ≤ 1.25 at 5 %, ≤ 1.64 at 20 % and ≤ 2.36 at 30 %
# (exact half turns are the worst kind for it). The consensus lowers Huber's figures where
# fewer than half of the steps are jumps (up to about 20 %); the bounds hold either way.
BOUND = {"cauchy": {0.05: 1.3, 0.2: 1.5, 0.3: 1.6}, "huber": {0.05: 1.35, 0.2: 1.9, 0.3: 2.7}}


@pytest.mark.parametrize("frac", [0.05, 0.2, 0.3])
@pytest.mark.parametrize("glitches", ["far", "half", "random"])
@pytest.mark.parametrize("kind", ["slow", "fast", "varying"])
def test_robust_start_on_scattered_glitches(kind, glitches, frac):
    """5 %, 20 % and 30 % of single frames glitched, two draws: both losses converge within
    the default iteration limit, give the glitches weight < 0.01 (Cauchy; Huber c/|r| < 0.05),
    and lie within the bounds above of the clean fit."""
    for seed in range(2):
        rng = np.random.default_rng([seed, 7])
        truth, clean = noisy(kind, rng)
        q = clean.copy()
        bad = rng.choice(len(T), int(frac * len(T)), replace=False)
        for s in bad:
            q[s] = qs.multiply(q[s], glitch(rng, glitches))
        far = qs.angle_between(q[bad], clean[bad]) > np.deg2rad(30)
        ref = error(qs.fit(T, clean), truth)
        for loss in ("huber", "cauchy"):
            f = qs.fit(T, q, robust=loss)
            assert f.iterations <= 1000
            assert error(f, truth) <= BOUND[loss][frac] * ref, (seed, loss, error(f, truth) / ref)
            assert np.all(f.robust_weights[bad[far]] < (0.01 if loss == "cauchy" else 0.05))


def bursty(kind, seed, length):
    """The motion with one burst of `length` consecutive frames turned by one 170°–180°
    rotation (a tracker flipped for that long), placed at random."""
    rng = np.random.default_rng([seed, 11])
    truth, clean = noisy(kind, rng)
    q = clean.copy()
    s = int(rng.integers(100, 700 - length))
    q[s : s + length] = qs.multiply(q[s : s + length], glitch(rng, "far"))
    return truth, clean, q, slice(s, s + length)


def floor_fit(q, burst):
    w = np.ones(len(T))
    w[burst] = 0.0
    return qs.fit(T, q, weights=w)


def near_the_floor(f, q, truth, burst, bound):
    """Outside the burst within `bound` × the floor's error (the plain fit with the burst at
    weight 0); across it (unobserved motion: the bridge depends on λ) within 0.3 rad of the
    truth — far from the burst, which is 170°–180° off."""
    out = np.ones(len(T), bool)
    out[burst] = False
    floor = floor_fit(q, burst)
    a, b = qs.angle_between(f(T), truth), qs.angle_between(floor(T), truth)
    return rms(a[out]) <= bound * rms(b[out]) and np.max(a[burst]) < 0.3


@pytest.mark.parametrize("length", [25, 50, 80])
@pytest.mark.parametrize("kind", ["slow", "varying"])
def test_bursts_longer_than_the_medoid_window_are_rejected(kind, length):
    """Bursts of 25–80 frames (longer than the running medoid's ±20 window, which followed
    them: 280–1200× the clean fit's error): the consensus of runs rejects them, and the Cauchy
    fit lies near the floor (``near_the_floor``), the burst at weight < 0.01 (three draws)."""
    for seed in range(3):
        truth, clean, q, burst = bursty(kind, seed, length)
        f = qs.fit(T, q, robust="cauchy")
        assert near_the_floor(f, q, truth, burst, 1.15), seed
        assert np.all(f.robust_weights[burst] < 0.01)


@pytest.mark.parametrize("length", [25, 50, 80])
def test_bursts_in_fast_motion_are_rejected_or_an_error(length):
    """In fast motion a flip is within reach of the motion after a few dozen frames, so long
    bursts may be contested: either the fit rejects the burst and lies near the floor
    (``near_the_floor``, 1.3× outside the burst: Huber's glitches still pull with c), or a
    ValueError names the burst's time range — never a silent curve through it."""
    for seed in range(3):
        truth, clean, q, burst = bursty("fast", seed, length)
        for loss in ("huber", "cauchy"):
            try:
                f = qs.fit(T, q, robust=loss)
            except ValueError as e:
                assert "consecutive samples at t = " in str(e)
                a, b = (float(v) for v in str(e).split("t = ")[1].split(" jump")[0].split(" … "))
                assert a <= T[burst.stop - 1] and b >= T[burst.start], (str(e), T[burst][[0, -1]])
                continue
            assert near_the_floor(f, q, truth, burst, 1.3), (seed, loss)


def test_a_burst_as_long_as_its_surroundings_is_an_error_naming_it():
    """A burst of 45 % of the recording in its middle: the frames on either side outnumber it,
    but not two to one — no choice is supported by the data, so a ValueError names the
    burst's times (before: a silent curve through the burst)."""
    rng = np.random.default_rng(3)
    _, q = noisy("slow", rng)
    q[220:580] = qs.multiply(q[220:580], qs.from_rotvec([0.0, 3.0, 0.0]))
    msg = r"^quats: the 360 consecutive samples at t = 2\.2 … 5\.79 jump"
    with pytest.raises(ValueError, match=msg):
        qs.fit(T, q, robust="cauchy")
    # weight 0 on the burst resolves it
    w = np.ones(len(T))
    w[220:580] = 0
    qs.fit(T, q, robust="cauchy", weights=w)


def test_a_burst_longer_than_its_surroundings_is_followed():
    """The majority decides: a run holding most of the recording is the motion, and the
    frames before and after it (fewer, and half as many) are the glitches."""
    rng = np.random.default_rng(4)
    truth, q = noisy("slow", rng)
    turn = qs.from_rotvec([0.0, 3.0, 0.0])
    q[:100] = qs.multiply(q[:100], turn)
    q[-100:] = qs.multiply(q[-100:], turn)
    f = qs.fit(T, q, robust="cauchy")
    assert np.all(f.robust_weights[:100] < 0.01) and np.all(f.robust_weights[-100:] < 0.01)
    assert np.median(qs.angle_between(f(T[100:-100]), truth[100:-100])) < np.deg2rad(0.3)
