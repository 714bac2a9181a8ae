"""Bad arguments raise ValueError or TypeError with a clear message; library errors raise
HullskinError (a ValueError) carrying the library's message and its place; nothing crashes."""

import numpy as np
import pytest

import hullskin
from conftest import TESTDATA


@pytest.fixture(scope="module")
def surface():
    return hullskin.fit(held_out=0).surface


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"method": "newton"}, "unknown method `newton`"),
        ({"ctrl": (-1, 5)}, "ctrl: -1 is negative"),
        ({"fair": "lots"}, "fair: `lots`"),
        ({"fair": -1.0}, "fair: -1"),
        ({"fair": float("nan")}, "(?i)fair: nan"),
        ({"tolerance": -0.1}, "tolerance -0.1"),
        ({"tolerance": float("nan")}, "(?i)tolerance nan"),
        ({"tolerance": 0.1, "ctrl": (5, 5)}, "tolerance or ctrl"),
        ({"held_out": 1}, "1 fold"),
        ({"knuckles": "some"}, "knuckles: unknown"),
        ({"envelope": "tight"}, "envelope: unknown `tight` \\(expected hold, hold-surface or free\\)"),
        ({"weights": "diagonal"}, "weights: unknown weight layout `diagonal`"),
        ({"control_points": "free"}, "control_points: unknown control-point mode `free`"),
        ({"corner_angle": 200.0}, "corner_angle"),
        ({"units": "furlong"}, "unknown units"),
        ({"param": "wobbly"}, "param"),
        ({"degree": (30, 3)}, "degree"),
        ({"ctrl": (2, 2)}, "control"),
    ],
)
def test_bad_fit_arguments_are_value_errors(kwargs, match):
    path = str(TESTDATA / "wigley_offsets.csv") if "units" in kwargs else None
    with pytest.raises(ValueError, match=match):
        hullskin.fit(path, **kwargs)


def test_weight_settings_are_read_as_the_command_line_reads_them():
    # One parser for both (hull's FromStr): any case, spaces around, and the layout's report
    # name as well as `rank1`; the optimisation reports the settings it ran with.
    r = hullskin.fit(method="lm", iterations=1, held_out=0, weights="Rank_One", control_points=" FIXED ")
    opt = r.report["optimization"]
    assert (opt["weight_layout"], opt["control_points"]) == ("rank_one", "fixed")


def test_a_wrong_type_is_a_type_error():
    with pytest.raises(TypeError, match="offsets_or_path"):
        hullskin.fit(42)
    with pytest.raises(TypeError):
        hullskin.fit(method=3)


def test_a_missing_file_names_it():
    with pytest.raises(FileNotFoundError, match="no_such_file.csv"):
        hullskin.read_offsets("no_such_file.csv")


def test_a_bad_file_names_its_line(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("section,x,y,z\nA,1,2\n")
    with pytest.raises(hullskin.HullskinError) as e:
        hullskin.fit(str(bad))
    assert "bad.csv" in str(e.value)
    assert e.value.file == str(bad) and e.value.line == 2
    assert isinstance(e.value, ValueError)


@pytest.mark.parametrize(
    "call, error, match",
    [
        (lambda s: s.hydrostatics(draft=-1.0), ValueError, "draft -1"),
        (lambda s: s.hydrostatics(draft=float("nan")), ValueError, "(?i)draft nan"),
        (lambda s: s.hydrostatics(draft=1e6), ValueError, "draft"),
        (lambda s: s.hydrostatics(draft=2.0, density=0.0), ValueError, "density"),
        (lambda s: s.hydrostatics(draft=2.0, to=4.0), ValueError, "to and step"),
        (lambda s: s.hydrostatics(draft=2.0, to=4.0, step=-1.0), ValueError, "step"),
        (lambda s: s.evaluate([0.1, float("nan")], 0.5), ValueError, "not finite"),
        (lambda s: s.evaluate([0.1, 0.2], [0.1, 0.2, 0.3]), ValueError, "one shape"),
        (lambda s: s.evaluate("a", 0.5), TypeError, "expected numbers"),
        (lambda s: s.evaluate([None], 0.5), ValueError, "not finite"),  # NumPy reads None as NaN
        (lambda s: s.evaluate([[0.1], [0.2, 0.3]], 0.5), TypeError, "expected numbers"),
        (lambda s: s.closest_points(np.zeros((4, 2))), ValueError, r"expected \(n, 3\)"),
        (lambda s: s.closest_points([[0, 0, float("inf")]]), ValueError, "not finite"),
        (lambda s: s.tessellate(tolerance=0.0), ValueError, "positive"),
        (lambda s: s.write_iges("/nonexistent-dir/x.igs"), OSError, "nonexistent-dir"),
        (lambda s: hullskin.Surface.from_json("{"), hullskin.HullskinError, "surface"),
        (lambda s: hullskin.Surface((3, 3), [0, 1], [0, 1], np.zeros((1, 1, 3))), ValueError, "knots_u"),
        (lambda s: hullskin.Surface(s.degree, s.knots_u, s.knots_v, s.control_points[:, :-1]), ValueError, "shape"),
        (lambda s: hullskin.Surface(s.degree, s.knots_u, s.knots_v, s.control_points, -s.weights), ValueError, "weight"),
        (lambda s: hullskin.Offsets.from_sections([np.zeros((3, 2))]), ValueError, r"sections\[0\]"),
        (lambda s: hullskin.read_offsets().scaled(x=0.0), ValueError, "scale"),
    ],
)
def test_bad_surface_arguments(surface, call, error, match):
    with pytest.raises(error, match=match):
        call(surface)


def test_a_mesh_is_refused_as_offsets_whatever_its_format():
    # hullskin.read_offsets reads offsets; a mesh (STL, OBJ, VRML, gzipped or not) is sliced by the
    # command line, and the message says so rather than failing on its bytes as offsets.
    for name in ("mesh/wigley.stl.gz", "mesh/fastship_cont.wrl.gz"):
        with pytest.raises(ValueError, match="a mesh; hullskin.read_offsets reads offsets"):
            hullskin.read_offsets(TESTDATA / name)
