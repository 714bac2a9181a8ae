"""The notebook-style example runs and draws its two figures."""

import pathlib
import subprocess
import sys

from conftest import import_or_skip

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "notebook.py"


def test_the_example_runs(tmp_path):
    import_or_skip("matplotlib")
    r = subprocess.run([sys.executable, str(EXAMPLE), "--out", str(tmp_path)], capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, r.stderr
    assert "max error" in r.stdout and "displ" in r.stdout
    for name in ("sections.png", "curvature.png"):
        data = (tmp_path / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000, name
