#!/usr/bin/env bash
# Make (once) the Python environment the tests use to read our exports with real CAD tools:
# .venv in the checkout root with tools/requirements.txt (Open CASCADE via cadquery-ocp-novtk).
# Idempotent; prints the path of the Python on its last line. Needs PyPI the first time.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
venv="$PWD/.venv"
stamp="$venv/.requirements-installed"
if [ ! -x "$venv/bin/python" ]; then
    echo "==> creating a Python virtual environment in .venv ($(${PYTHON:-python3} --version))" >&2
    "${PYTHON:-python3}" -m venv "$venv"
fi
if [ ! -f "$stamp" ] || ! cmp -s tools/requirements.txt "$stamp"; then
    echo "==> installing tools/requirements.txt into .venv" >&2
    "$venv/bin/python" -m pip install --disable-pip-version-check --quiet -r tools/requirements.txt >&2
    cp tools/requirements.txt "$stamp"
fi
"$venv/bin/python" -c 'import OCP' >&2
echo "$venv/bin/python"
