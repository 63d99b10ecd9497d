"""The type stubs (python/symba/__init__.pyi) name every public class,
function and attribute of the module, and nothing it lacks."""

import ast
import inspect
import pathlib

import symba


def stub_definitions():
    path = pathlib.Path(symba.__file__).with_name("__init__.pyi")
    tree = ast.parse(path.read_text())
    top = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            members = set()
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    members.add(item.name)
                elif isinstance(item, ast.AnnAssign):
                    members.add(item.target.id)
            top[node.name] = members
        elif isinstance(node, ast.FunctionDef):
            top[node.name] = None
    return top


def public_members(cls):
    return {name for name, _ in inspect.getmembers(cls)
            if not name.startswith("_")}


def test_stubs_cover_the_module():
    stubs = stub_definitions()
    assert sorted(n for n in stubs) == sorted(symba.__all__)
    for name in symba.__all__:
        value = getattr(symba, name)
        if inspect.isclass(value) and stubs[name] is not None:
            if issubclass(value, Exception):
                continue
            assert public_members(value) == {
                m for m in stubs[name] if not m.startswith("_")}, name
