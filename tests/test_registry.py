"""The method registry: one row per method that every reader (``quatspline.spline``, the
operations, the command line, the viewer) reads, and typed errors raised where they are known."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from quatspline import ops, registry
from quatspline._util.errors import ParameterError
from quatspline.cli import main
from quatspline.cli._commands import build_parser
from quatspline.ops import design
from quatspline.registry import METHODS, Method, Param

KEYS = qs.from_rotvec([[0, 0, 0], [0, 0, 0.6], [0.3, 0.2, 1.1], [0.5, -0.2, 1.4], [0.2, 0.1, 2]])
TIMES = np.array([0.0, 0.7, 1.5, 2.0, 3.1])


class FlavouredSlerp(qs.PiecewiseSlerp):
    """A new method: piecewise slerp that remembers a flavour (the one class)."""

    def __init__(self, quats, times, flavour):
        super().__init__(quats, times)
        self.flavour = flavour


@pytest.fixture
def flavoured(monkeypatch):
    """The one row of the new method, in the registry for one test only."""
    row = Method(
        "flavoured",
        "piecewise slerp with a flavour (a test method)",
        True,
        "C0",
        {"flavour": Param(str, "plain", "a flavour", ("plain", "mint"))},
        lambda q, t, p: FlavouredSlerp(q, t, p["flavour"]),
    )
    monkeypatch.setitem(METHODS, row.name, row)
    return row


def test_a_new_method_is_one_class_and_one_row_that_every_reader_finds(flavoured, tmp_path, capsys):
    # the Python API and the library operation
    s = qs.spline("flavoured", KEYS, TIMES, flavour="mint")
    assert isinstance(s, FlavouredSlerp) and s.flavour == "mint"
    traj = qio.Trajectory(TIMES + 100.0, KEYS)
    s = ops.build_spline("flavoured", traj, {"flavour": "plain"})
    assert isinstance(s, FlavouredSlerp) and s.domain[0] == 0.0
    assert s.domain[1] == traj.times[-1] - traj.times[0]
    # the command line: its method list, its --param checks and a run
    assert "flavoured" in build_parser().epilog
    src, out = tmp_path / "keys.csv", tmp_path / "out.csv"
    qio.write(src, traj)
    run = ["sample", str(src), "-o", str(out), "--method", "flavoured", "--count", "7"]
    assert main([*run, "--param", "flavour=mint"]) == 0
    assert len(qio.read(out)) == 7
    capsys.readouterr()
    assert main([*run, "--param", "flavour=sour", "--force"]) == 2
    assert "supported: plain, mint" in capsys.readouterr().err
    # the viewer: its method list with the row's controls, and a design
    spec = next(m for m in design.method_specs() if m["name"] == "flavoured")
    assert spec["params"] == [
        {"name": "flavour", "kind": "str", "default": "plain", "help": "a flavour",
         "choices": ["plain", "mint"]}
    ]  # fmt: skip
    d = design.evaluate("flavoured", KEYS, TIMES, {"flavour": "mint"}, samples=9)
    np.testing.assert_array_equal(d["quats"], qs.spline("slerp", KEYS, TIMES)(d["t"]))


BAD_PARAMETERS = [
    ("cubic", {}, r"^method: unknown method 'cubic'; valid: slerp"),
    ("c3", {"gamma": 1}, r"^gamma: unknown parameter of c3; valid: alpha, beta"),
    ("c3", {"alpha": "big"}, r"^alpha: expected a number or 'auto', got 'big'"),
    ("c3", {"holds": "maybe"}, r"^holds: expected true or false"),
    ("c3", {"variant": "knotty"}, r'^variant: c3 does not support "knotty"; supported: knot'),
    ("c3", {"alpha": float("nan")}, r"^alpha: non-finite value"),
    ("c3", {"beta": 1e9}, r"^beta: beta\[0\] = 1000000000 is beyond the supported range"),
    ("squad", {"ends": "reflect"}, r'^ends: squad does not support "reflect"; supported: open'),
    ("natural", {"ends": "open"}, r"^ends: natural does not support .*clamped, rest, closed$"),
    ("catmull_rom", {"alpha": 2.0}, r"^alpha: expected a value in \[0, 1\], got 2.0"),
    ("kochanek_bartels", {"tension": "inf"}, r"^tension: non-finite value"),
    ("hermite", {"rates": "/nonexistent/rates.txt"}, r"^rates: expected 'bessel', 'zero'"),
    ("hermite", {"frame": "local"}, r'^frame: hermite does not support "local"'),
    ("lin_euler", {"seq": "xyy"}, r'^seq: lin_euler does not support "xyy"'),
    ("bspline", {"order": 3}, r"^order: the registry's bspline spans the keys with order 4"),
    ("bspline", {"ends": "natural"}, r'^ends: bspline does not support "natural"'),
    ("beta", {"beta1": 0.0}, r"^beta1: beta1\[0\] = 0 must be > 0"),
    ("fit", {"smoothing": -1}, r"^smoothing: expected 'auto' or a finite λ ≥ 0, got -1"),
    (
        "fit",
        {"smoothing": "lots"},
        r"^smoothing: expected 'auto', 'gcv', 'adaptive' or a number ≥ 0, got 'lots'",
    ),
    ("fit", {"knots": 0}, r"^knots: expected a finite positive spacing, got 0"),
    ("fit", {"knots": 10.0}, r"^knots: spacing 10 exceeds the data's time span 3.1"),
    ("fit", {"penalty": "snap"}, r'^penalty: fit does not support "snap"'),
    ("fit", {"robust": "tukey"}, r'^robust: fit does not support "tukey"; .*none, huber'),
    ("min_energy", {"resolution": 99}, r"^resolution: expected an integer from 0 to 16, got 99"),
]


@pytest.mark.parametrize(("method", "params", "match"), BAD_PARAMETERS)
def test_the_registry_raises_parameter_error_itself_for_a_bad_method_or_parameter(
    method, params, match
):
    # The registry raised a plain ValueError and ops turned it into a ParameterError when the
    # message contained "unknown parameter" or began with a parameter's name.
    with pytest.raises(ParameterError, match=match):
        qs.spline(method, KEYS, TIMES, **params)
    with pytest.raises(ParameterError, match=match):
        ops.build_spline(method, qio.Trajectory(TIMES, KEYS), params)


def test_pose_registry_raises_parameter_error_itself():
    pos = np.zeros((len(KEYS), 3))
    with pytest.raises(ParameterError, match=r"^method: unknown pose method 'sclerp'"):
        registry.pose_spline("sclerp", KEYS, TIMES, pos)
    with pytest.raises(ParameterError, match=r"^gamma: unknown parameter of screw; valid: none"):
        registry.pose_spline("screw", KEYS, TIMES, pos, gamma=1)
    with pytest.raises(ParameterError, match=r'^formulation: pose_bspline does not support "x"'):
        registry.pose_spline("pose_bspline", KEYS, TIMES, pos, formulation="x")


@pytest.mark.parametrize(
    ("method", "keys", "params", "match"),
    [
        ("squad", KEYS[:2], {"ends": "closed"}, r"^quats: a closed squad needs at least"),
        ("c3", np.vstack([KEYS[:2], [[np.nan, 0, 0, 1]], KEYS[3:]]), {}, r"^quats"),
    ],
)
def test_bad_keys_stay_a_data_error_not_a_parameter_error(method, keys, params, match):
    with pytest.raises(ValueError, match=match) as e:
        ops.build_spline(method, qio.Trajectory(TIMES[: len(keys)], keys), params)
    assert not isinstance(e.value, ParameterError)


def test_ops_does_not_classify_a_builders_error_by_its_message(monkeypatch):
    # A data error whose message begins with a parameter's name ("ends: …") was turned into a
    # ParameterError (exit code 2, bad usage) by matching the text.
    def build(q, t, p):
        raise ValueError("ends: the recording is too short to close")

    row = Method("picky", "refuses its keys", True, "C0", {"ends": Param(str, "open", "")}, build)
    monkeypatch.setitem(METHODS, row.name, row)
    with pytest.raises(ValueError, match="^ends: the recording") as e:
        ops.build_spline("picky", qio.Trajectory(TIMES, KEYS))
    assert not isinstance(e.value, ParameterError)


def test_method_specs_offer_every_choice_of_a_parameter():
    # The viewer regex-parsed the choices out of the help text and lost every choice after a
    # parenthesis: natural offered only natural and clamped ends, bspline only open and rest.
    specs = {m["name"]: {p["name"]: p for p in m["params"]} for m in design.method_specs()}
    assert specs["natural"]["ends"]["choices"] == ["natural", "clamped", "rest", "closed"]
    assert specs["bspline"]["ends"]["choices"] == ["open", "rest", "closed"]
    assert specs["hermite"]["frame"]["choices"] == ["world", "body"]
    for name, m in METHODS.items():
        for pname, p in m.params.items():
            want = None if p.choices is None else list(p.choices)
            assert specs[name][pname]["choices"] == want, (name, pname)
            if p.choices is not None and isinstance(p.default, str):
                assert p.default in p.choices, (name, pname)
                for choice in p.choices:  # every offered choice passes the registry's checks
                    p.validate(pname, name, p.convert(pname, choice), {"penalty": "jerk"})


def test_parameter_error_is_one_class_under_every_name():
    assert ops.ParameterError is ParameterError is registry.ParameterError
    assert issubclass(ParameterError, ValueError)
