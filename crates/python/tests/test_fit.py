"""hullskin.fit equals `hullskin fit --json` (report.json) on the same input, bit for bit
except the measured times; and the surface equals the surface.json the command line writes."""

import json
import math

import numpy as np
import pytest

import hullskin
from conftest import TESTDATA, cli_json, without_timings


def test_the_sample_fits_with_no_argument(sample_fit):
    e = sample_fit.error
    # The Series 60 table fits within 0.25 m max (its known approximation error at 6 x 19
    # control points is 0.144 m; README), and the figures are consistent.
    assert 0 < e["rms"] <= e["max"] < 0.25
    assert e["points"] == 200
    assert len(e["per_section"]) == 25
    assert e["held_out"]["folds"] == hullskin.DEFAULT_HELD_OUT_FOLDS
    s = sample_fit.surface
    assert s.control_points.shape == (*s.weights.shape, 3)
    assert s.degree == (3, 3)
    assert sample_fit.validity == []
    assert set(sample_fit.timings) >= {"seconds", "fit_seconds", "error_seconds"}


@pytest.mark.parametrize(
    "args, kwargs",
    [
        ([], {}),
        (["testdata/wigley_offsets.csv"], {}),
        (["testdata/series60_cb070_offsets.csv", "--ctrl", "7,12", "--fair", "0"], {"ctrl": (7, 12), "fair": 0}),
        (["testdata/wigley_offsets.csv", "--method", "interp", "--held-out", "0"], {"method": "interp", "held_out": 0}),
        (["testdata/wigley_offsets.csv", "--tolerance", "0.02"], {"tolerance": 0.02}),
        (
            ["testdata/wigley_offsets.csv", "--method", "lm", "--iterations", "5", "--ctrl", "6,8", "--held-out", "2"],
            {"method": "lm", "iterations": 5, "ctrl": (6, 8), "held_out": 2},
        ),
        (
            ["--method", "pso", "--iterations", "4", "--population", "6", "--seed", "7", "--ctrl", "5,8",
             "--held-out", "0"],
            {"method": "pso", "iterations": 4, "population": 6, "seed": 7, "ctrl": (5, 8), "held_out": 0},
        ),
        (["--envelope", "hold-surface", "--held-out", "0"], {"envelope": "hold-surface", "held_out": 0}),
    ],
    ids=["sample", "wigley", "s60-cb070-ctrl", "interp", "tolerance", "lm", "pso-seeded", "hold-surface"],
)
def test_the_report_equals_the_command_lines(cli, tmp_path, args, kwargs):
    out = tmp_path / "out"
    expected = cli_json(cli, "fit", *[str(TESTDATA.parent / a) if a.startswith("testdata/") else a for a in args],
                        "--json", "-o", out)
    path = next((TESTDATA.parent / a for a in args if a.startswith("testdata/")), None)
    f = hullskin.fit(str(path) if path else None, **kwargs)
    assert without_timings(f.report) == without_timings(expected)
    # The surface itself: the same surface.json text (shortest round-trip digits of every
    # knot, control point and weight).
    assert f.surface.to_json() == (out / "surface.json").read_text()


def test_offsets_read_once_fit_as_the_path(tmp_path):
    path = TESTDATA / "wigley_offsets.csv"
    o = hullskin.read_offsets(path)
    assert len(o) == len(o.sections) == len(o.labels)
    assert all(s.shape[1] == 3 for s in o.sections)
    a, b = hullskin.fit(o, held_out=0), hullskin.fit(str(path), held_out=0)
    assert a.surface == b.surface
    assert without_timings(a.report) == without_timings(b.report)


def test_the_same_seed_gives_the_same_surface():
    kw = dict(method="ga", iterations=3, population=8, ctrl=(5, 8), held_out=0)
    a, b = hullskin.fit(seed=3, **kw), hullskin.fit(seed=3, **kw)
    assert a.surface == b.surface
    c = hullskin.fit(seed=4, **kw)
    # Another seed draws other populations: the weights differ.
    assert not np.array_equal(a.surface.weights, c.surface.weights)


def test_offsets_from_arrays_fit_as_read(tmp_path):
    o = hullskin.read_offsets(TESTDATA / "wigley_offsets.csv")
    rebuilt = hullskin.Offsets.from_sections(o.sections, units=o.units, labels=o.labels, source=o.source,
                                             perpendiculars=o.perpendiculars)
    assert hullskin.fit(rebuilt, held_out=0).surface == hullskin.fit(o, held_out=0).surface


def test_scaled_offsets_scale_the_fit():
    o = hullskin.read_offsets()
    s = o.scaled(x=2.0, y=1.0, z=1.0)
    assert s.perpendiculars == (o.perpendiculars[0] * 2, o.perpendiculars[1] * 2)
    for a, b in zip(o.sections, s.sections):
        np.testing.assert_array_equal(b[:, 0], 2 * a[:, 0])
        np.testing.assert_array_equal(b[:, 1:], a[:, 1:])


def test_the_report_is_json_and_pickles(sample_fit):
    import pickle

    assert json.loads(sample_fit.to_json()) == sample_fit.report
    back = pickle.loads(pickle.dumps(sample_fit))
    assert back.report == sample_fit.report and back.surface == sample_fit.surface
    assert back.warnings == sample_fit.warnings
    o = pickle.loads(pickle.dumps(sample_fit.offsets))
    assert [s.tolist() for s in o.sections] == [s.tolist() for s in sample_fit.offsets.sections]
    assert math.isfinite(back.error["max"])


@pytest.mark.parametrize("name", ["freeship_wigley_offsets.txt", "series60_cb070_offsets.csv", "gunnerus_offsets.csv", "matlab_trawler.csv"])
def test_reading_notes_and_warnings_are_the_command_lines(cli, tmp_path, name):
    path = TESTDATA / name
    _, err = cli("fit", path, "--held-out", "0", "-o", tmp_path, stderr=True)
    o = hullskin.read_offsets(path)
    notes = [line.removeprefix("hullskin: note: ") for line in err.splitlines() if line.startswith("hullskin: note: ")]
    warnings = [line.removeprefix("hullskin: warning: ") for line in err.splitlines()
                if line.startswith("hullskin: warning: ")]
    # The command line prints a sections CSV's or offset table's reading notes only when
    # there is more to say than the format; the bindings always keep them.
    if notes:
        assert o.notes == notes
    else:
        assert len(o.notes) == 1 and "read as" in o.notes[0]
    f = hullskin.fit(o, held_out=0)
    assert f.warnings == warnings
