"""Shared fixtures: the repository's paths and the `hullskin` command line whose figures the
bindings must equal.

The command line is HULLSKIN_CLI if set, else the first of target/release/hullskin and
target/debug/hullskin under CARGO_TARGET_DIR or the checkout's target/ (`.ci/run` sets
HULLSKIN_CLI to the binary `cargo test --workspace` built). Without one the comparisons are
skipped, with the reason, except under CI=true, where they fail.
"""

import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]
TESTDATA = ROOT / "testdata"

# Keys of report.json that are measured times, different on every run.
TIMING_KEYS = {"seconds", "fit_seconds", "error_seconds", "default_fit_seconds", "default_held_out_seconds"}


def _cli_candidates():
    if os.environ.get("HULLSKIN_CLI"):
        yield pathlib.Path(os.environ["HULLSKIN_CLI"])
        return
    targets = [pathlib.Path(os.environ["CARGO_TARGET_DIR"])] if os.environ.get("CARGO_TARGET_DIR") else []
    targets.append(ROOT / "target")
    for t in targets:
        for profile in ("release", "debug"):
            yield t / profile / "hullskin"


@pytest.fixture(scope="session")
def cli():
    """A function running the command line with arguments, returning its standard output."""
    path = next((p for p in _cli_candidates() if p.is_file()), None)
    if path is None:
        message = "no hullskin binary (set HULLSKIN_CLI or run cargo build -p hullskin)"
        if os.environ.get("CI") == "true":
            pytest.fail(message)
        pytest.skip(message)

    def run(*args, cwd=None, stderr=False):
        env = dict(os.environ, SOURCE_DATE_EPOCH="1000000000")
        r = subprocess.run([str(path), *map(str, args)], capture_output=True, text=True, cwd=cwd, env=env)
        if r.returncode != 0:
            raise AssertionError(f"hullskin {' '.join(map(str, args))} exited {r.returncode}: {r.stderr}")
        return (r.stdout, r.stderr) if stderr else r.stdout

    return run


def import_or_skip(name):
    """`name` imported; where it is not installed, a skip saying so, except under CI=true
    (where `.ci/run` installs it), where the import error fails the test."""
    import importlib

    try:
        return importlib.import_module(name)
    except ImportError:
        if os.environ.get("CI") == "true":
            raise
        pytest.skip(f"{name} is not installed (pip install -r crates/python/requirements-ci.txt)", allow_module_level=True)


def without_timings(value):
    """A report with its measured times removed (everything else is compared exactly)."""
    if isinstance(value, dict):
        return {k: without_timings(v) for k, v in value.items() if k not in TIMING_KEYS}
    if isinstance(value, list):
        return [without_timings(v) for v in value]
    return value


@pytest.fixture(scope="session")
def sample_fit():
    import hullskin

    return hullskin.fit()


def cli_json(cli, *args):
    return json.loads(cli(*args))
