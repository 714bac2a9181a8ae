"""Hydrostatics and exports equal the command line's on the same input: the JSON of
`hullskin hydrostatics --format json`, and the bytes of `hullskin export` (fixed timestamp)."""

import json
import pickle

import numpy as np
import pytest

import hullskin
from conftest import TESTDATA, cli_json

WIGLEY = TESTDATA / "wigley_offsets.csv"


@pytest.mark.parametrize(
    "cli_args, kwargs",
    [
        (["--draft", "6.5"], {"draft": 6.5}),
        (["--draft", "2", "--to", "8", "--step", "0.5"], {"draft": 2, "to": 8, "step": 0.5}),
        (["--draft", "5", "--density", "1.0", "--lpp", "120", "--ap", "1"], {"draft": 5, "density": 1.0, "lpp": 120, "ap": 1}),
    ],
    ids=["design-draft", "range", "fresh-water-lpp"],
)
def test_hydrostatics_of_the_sample_equal_the_command_lines(cli, sample_fit, cli_args, kwargs):
    expected = cli_json(cli, "hydrostatics", *cli_args, "--format", "json")
    assert sample_fit.surface.hydrostatics(**kwargs) == expected


def test_hydrostatics_of_a_fitted_file_and_of_its_surface_json(cli, tmp_path):
    f = hullskin.fit(str(WIGLEY))
    assert f.surface.hydrostatics(draft=5.0) == cli_json(cli, "hydrostatics", WIGLEY, "--draft", "5", "--format", "json")
    path = tmp_path / "surface.json"
    path.write_text(f.surface.to_json())
    s = hullskin.Surface.from_json(path.read_text(), source=str(path))
    assert s.hydrostatics(draft=5.0) == cli_json(cli, "hydrostatics", path, "--draft", "5", "--format", "json")


def test_wigley_hydrostatics_meet_the_closed_form():
    # Wigley hull y = B/2 (1 - (2x/L - 1)^2)(1 - (z/T)^2)... as tabulated: Cb = 4/9 at the design
    # draft (6.25 m of the table's 10 m depth? the table's T). The fit's error (mm on a 100 m hull)
    # bounds the difference: 0.5 % is ten times the fit's relative volume error.
    f = hullskin.fit(str(WIGLEY))
    o = f.offsets
    top = max(float(s[:, 2].max()) for s in o.sections)
    row = f.surface.hydrostatics(draft=top)["rows"][0]
    assert row["cb"] == pytest.approx(4 / 9, rel=5e-3)


@pytest.mark.parametrize("fmt, method, args", [
    ("igs", "write_iges", {}),
    ("stp", "write_step", {}),
    ("stl", "write_stl", {}),
])
@pytest.mark.parametrize("mirror", [False, True])
def test_files_equal_the_command_lines(cli, tmp_path, fmt, method, args, mirror):
    theirs, ours = tmp_path / f"cli.{fmt}", tmp_path / f"py/cli.{fmt}"
    ours.parent.mkdir()
    cli("export", WIGLEY, "-o", theirs, "--timestamp", "1000000000", *(["--mirror"] if mirror else []))
    s = hullskin.fit(str(WIGLEY), held_out=0).surface
    kw = dict(args, mirror=mirror)
    if fmt != "stl":
        kw["timestamp"] = 1000000000
    getattr(s, method)(ours, **kw)
    assert ours.read_bytes() == theirs.read_bytes()


def test_tessellation_is_the_stl_mesh(tmp_path):
    s = hullskin.fit(str(WIGLEY), held_out=0).surface
    v, f = s.tessellate()
    assert v.shape[1] == 3 and f.shape[1] == 3 and f.dtype == np.int64
    assert f.min() == 0 and f.max() == len(v) - 1
    s.write_stl(tmp_path / "a.stl")
    # Binary STL: 80-byte header, a u32 count, 50 bytes a triangle.
    data = (tmp_path / "a.stl").read_bytes()
    assert int.from_bytes(data[80:84], "little") == len(f) == (len(data) - 84) // 50
    # The vertices lie on the surface: their closest points are within the projection's
    # tolerance (1e-9 of the size), far below the chord tolerance (1e-4 of the size).
    d = s.closest_points(v[::50])["distance"]
    assert d.max() < 1e-6


def test_surface_json_and_pickle_round_trips(sample_fit):
    s = sample_fit.surface
    # A polynomial surface (all weights 1) reads back exactly from its JSON.
    assert hullskin.Surface.from_json(s.to_json()) == s
    assert json.loads(s.to_json())["units"] == "m"
    # A rational one: the JSON holds the Euclidean points and weights, the surface w·P; read
    # back, w·P is rounded once more (1 ulp), so the points agree to 2 ulps. Pickling keeps
    # w·P itself: exact.
    r = hullskin.fit(method="lm", iterations=3, ctrl=(5, 8), held_out=0).surface
    assert not np.all(r.weights == 1.0)
    back = hullskin.Surface.from_json(r.to_json())
    np.testing.assert_array_equal(back.weights, r.weights)
    np.testing.assert_allclose(back.control_points, r.control_points, rtol=4.5e-16, atol=0)
    assert pickle.loads(pickle.dumps(r)) == r
    assert pickle.loads(pickle.dumps(s)) == s
