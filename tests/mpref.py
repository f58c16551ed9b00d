"""High-precision references (mpmath, 50 digits) for quaternion functions."""

from __future__ import annotations

import mpmath as mp

mp.mp.dps = 50


def mq(q):
    return [mp.mpf(float(c)) for c in q]


def normalize(q):
    n = mp.sqrt(sum(c * c for c in q))
    return [c / n for c in q]


def mul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return [
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    ]


def conj(q):
    return [q[0], -q[1], -q[2], -q[3]]


def log(q):
    n = mp.sqrt(sum(c * c for c in q))
    s = mp.sqrt(q[1] ** 2 + q[2] ** 2 + q[3] ** 2)
    if s == 0:
        return [mp.log(n), mp.mpf(0), mp.mpf(0), mp.mpf(0)]
    th = mp.atan2(s, q[0])
    return [mp.log(n), th * q[1] / s, th * q[2] / s, th * q[3] / s]


def exp(q):
    s = mp.sqrt(q[1] ** 2 + q[2] ** 2 + q[3] ** 2)
    e = mp.exp(q[0])
    if s == 0:
        return [e, mp.mpf(0), mp.mpf(0), mp.mpf(0)]
    k = e * mp.sin(s) / s
    return [e * mp.cos(s), k * q[1], k * q[2], k * q[3]]


def power(q, t):
    return exp([mp.mpf(t) * c for c in log(q)])


def slerp(p, q, t):
    p, q = normalize(p), normalize(q)
    if sum(a * b for a, b in zip(p, q)) < 0:
        q = [-c for c in q]
    return mul(p, power(mul(conj(p), q), t))


def to_float(q):
    return [float(c) for c in q]
