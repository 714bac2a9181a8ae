"""Design studies on Dask: a study of >= 200 fits on a LocalCluster of 2 workers equals the
serial run bit for bit and uses both workers; a failed fit is a row with its message; the
example study runs."""

import math
import pathlib
import subprocess
import sys

import numpy as np
import pytest

from hullskin import study

from conftest import import_or_skip

distributed = import_or_skip("dask.distributed")
EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "series60_study.py"


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


def variants():
    # 14 x 14 = 196 transformed parents, plus seeded weight optimisations and bad inputs: 203.
    v = study.series60_variants(np.linspace(5.5, 8.5, 14), np.linspace(2.0, 3.5, 14), held_out=0)
    v += [{"name": f"pso seed {k}", "fit": {"method": "pso", "iterations": 3, "population": 6, "seed": k,
                                            "ctrl": (5, 8), "held_out": 0}} for k in (1, 2)]
    v += [{"name": "missing file", "offsets": "no-such-offsets.csv"},
          {"name": "bad method", "fit": {"method": "newton"}},
          {"name": "bad scale", "scale": (1.0, -1.0, 1.0)}]
    return v


def test_a_study_on_dask_equals_the_serial_run(client):
    vs = variants()
    assert len(vs) >= 200
    on_dask = study.run(vs, client=client)
    serial = study.run(vs)
    assert len(on_dask) == len(vs)
    # Bit for bit: every figure equal, NaN where NaN (DataFrame.equals compares exactly).
    assert on_dask.equals(serial)
    assert list(on_dask["name"]) == [str(v["name"]) for v in vs]
    workers = on_dask.attrs["workers"]
    assert len(workers) == 2 and sum(workers.values()) == len(vs) and min(workers.values()) > 0, workers
    ok = on_dask[on_dask["error"] == ""]
    assert len(ok) == len(vs) - 3
    # The transformed parents keep their form: Cb at the scaled design draft is Todd's 0.60 to
    # 0.5 %, and among the fits of one parameterization the same to 0.05 % on centripetal
    # parameters and 0.3 % on chord lengths (an affine image of the offsets is not fitted as
    # the affine image of the surface: the parameters, the fairing's and the held-out referee's
    # choices change with the proportions; measured spreads 0.02 % and 0.26 %, 2026-12-07). The
    # referee takes chord lengths held on the surface for 126 of the 196 proportions, whose
    # waterline is narrower (the parent's Bwl 16.211 m against 16.26): CB(Lpp) 0.5983 to 0.5999
    # against 0.5974.
    parents = ok[ok["name"].str.startswith("L/B")]
    assert ((parents["cb"] - 0.60).abs() < 0.005 * 0.60).all(), parents["cb"].describe()
    spread = {"centripetal,chord": 5e-4, "chord": 3e-3}
    assert set(parents["parameterization"]) <= set(spread), set(parents["parameterization"])
    for param, group in parents.groupby("parameterization"):
        assert group["cb"].max() - group["cb"].min() < spread[param] * group["cb"].mean(), param
    assert (parents["thin_plate"] > 0).all()
    # The proportions asked for, to rounding of the scale factors.
    np.testing.assert_allclose(parents["l_over_b"], np.repeat(np.linspace(5.5, 8.5, 14), 14), rtol=1e-12)
    np.testing.assert_allclose(parents["b_over_t"], np.tile(np.linspace(2.0, 3.5, 14), 14), rtol=1e-12)


def test_a_failed_fit_is_a_row_with_its_message():
    df = study.run([{"name": "missing", "offsets": "no-such-offsets.csv"}, {"name": "fine", "fit": {"held_out": 0}}])
    assert df.loc[0, "error"].startswith("FileNotFoundError: no-such-offsets.csv")
    assert math.isnan(df.loc[0, "vol"]) and df.loc[1, "error"] == "" and df.loc[1, "vol"] > 0
    bad = study.run([{"fit": {"method": "newton"}}])
    assert "unknown method `newton`" in bad.loc[0, "error"]


def test_the_example_study_runs(tmp_path):
    import_or_skip("matplotlib")
    r = subprocess.run([sys.executable, str(EXAMPLE), "--grid", "3", "2", "--out", str(tmp_path)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert "6 variants, 0 failed" in r.stdout
    assert (tmp_path / "study.png").read_bytes()[:4] == b"\x89PNG"
    assert len((tmp_path / "study.csv").read_text().splitlines()) == 7
