"""Property: a truncated or bit-flipped file of any format reads as a valid trajectory or
raises one ``ValueError`` line naming the file, never another exception.

One valid seed per reader entry (``fuzz/corpus/readers/seed-*``, the fuzzer's seeds, mapped
to formats by ``fuzz/readers_check.py``) is damaged deterministically: cut at several
lengths, single bits flipped, runs of bytes overwritten with 0x00 / 0xff / digits, a
region duplicated. The invariant is the fuzzer's (``readers_check.check_one``).
"""

from __future__ import annotations

import importlib.util
import pathlib
import random

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SEEDS = sorted((ROOT / "fuzz" / "corpus" / "readers").glob("seed-*"))


def _readers_check():
    spec = importlib.util.spec_from_file_location(
        "readers_check", ROOT / "fuzz" / "readers_check.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


CHECK = _readers_check()


def _damaged(data: bytes, rng: random.Random, count: int):
    """``count`` damaged versions of a fuzz input (its first byte, the entry, is kept)."""
    head, body = data[:1], data[1:]
    n = len(body)
    out = []
    for cut in sorted({0, 1, n // 7, n // 3, n // 2, n - 1, max(n - 9, 0)}):
        out.append(head + body[:cut])
    while len(out) < count:
        b = bytearray(body)
        kind = rng.randrange(4)
        if n == 0:
            break
        k = rng.randrange(n)
        if kind == 0:
            for _ in range(rng.randint(1, 4)):
                j = rng.randrange(n)
                b[j] ^= 1 << rng.randrange(8)
        elif kind == 1:
            fill = rng.choice([b"\x00", b"\xff", b"9", b"-", b"\n", b"["])
            length = rng.randint(1, 16)
            b[k : k + length] = fill * len(b[k : k + length])
        elif kind == 2:
            length = rng.randint(1, 64)
            b[k:k] = bytes(b[k : k + length]) * rng.randint(2, 5)
        else:
            del b[k : k + rng.randint(1, 64)]
        out.append(head + bytes(b))
    return out


@pytest.mark.parametrize("seed", SEEDS, ids=[p.name for p in SEEDS])
def test_damaged_file_of_every_format_raises_only_a_one_line_value_error_naming_it(seed, tmp_path):
    data = seed.read_bytes()
    rng = random.Random(seed.name)
    for k, bad in enumerate(_damaged(data, rng, 40)):
        try:
            CHECK.check_one(bad, str(tmp_path))
        except AssertionError as e:
            raise AssertionError(f"{seed.name} damage #{k}: {e}") from None
        except Exception as e:
            raise AssertionError(
                f"{seed.name} damage #{k}: {type(e).__name__} escaped the reader: {e}"
            ) from None
