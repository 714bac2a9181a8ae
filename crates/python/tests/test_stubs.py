"""The type stubs name every public item of the native module, and no other."""

import ast
import pathlib

import hullskin
from hullskin import _hullskin

STUB = pathlib.Path(hullskin.__file__).with_name("_hullskin.pyi")


def test_the_stubs_match_the_module():
    tree = ast.parse(STUB.read_text())
    stubbed = set()
    for node in tree.body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            stubbed.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            stubbed.add(node.target.id)
    public = {n for n in dir(_hullskin) if not n.startswith("_")} | {"__version__"}
    assert stubbed - {"ArrayLike", "FloatArray", "PathLike"} == public
    methods = {n.name for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Surface"
               for n in n.body if isinstance(n, ast.FunctionDef)}
    native = {n for n in dir(_hullskin.Surface) if not n.startswith("_")}
    assert methods - {"__init__"} == native


def test_every_public_item_has_a_docstring():
    for name in ("fit", "read_offsets", "Fit", "Surface", "Offsets"):
        assert getattr(hullskin, name).__doc__, name
    for name in dir(hullskin.Surface):
        if not name.startswith("_"):
            assert getattr(hullskin.Surface, name).__doc__, f"Surface.{name}"
