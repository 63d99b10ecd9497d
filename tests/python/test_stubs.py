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


def doc_parameters(function):
    """The parameter names in pybind11's signature line (the docstring's
    first line), with "*" for the start of the keyword-only ones; None for
    an overloaded function."""
    line = (function.__doc__ or "").splitlines()[0] if function.__doc__ else ""
    if "(" not in line:
        return None
    text = line[line.index("(") + 1:]
    names, depth, current, quote = [], 0, "", None
    for char in text:
        if quote:
            quote = None if char == quote else quote
        elif char in "'\"":
            quote = char
        elif char in "([{":
            depth += 1
        elif char in ")]}":
            if depth == 0:
                break
            depth -= 1
        elif char == "," and depth == 0:
            names.append(current)
            current = ""
            continue
        current += char
    names.append(current)
    names = [n.split(":")[0].split("=")[0].strip() for n in names]
    return [n for n in names if n and n != "self"]


def stub_parameters(node):
    args = node.args
    names = [a.arg for a in args.posonlyargs + args.args if a.arg != "self"]
    if args.vararg:
        names.append("*" + args.vararg.arg)
    elif args.kwonlyargs:
        names.append("*")
    names += [a.arg for a in args.kwonlyargs]
    if args.kwarg:
        names.append("**" + args.kwarg.arg)
    return names


def test_stub_signatures_name_the_modules_parameters():
    """Every function and method of the stubs has the module's parameters,
    in order, keyword-only where the module's are."""
    path = pathlib.Path(symba.__file__).with_name("__init__.pyi")
    tree = ast.parse(path.read_text())
    checked = 0
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            functions = [(node, getattr(symba, node.name))]
        elif isinstance(node, ast.ClassDef):
            cls = getattr(symba, node.name)
            functions = [
                (item, getattr(cls, item.name)) for item in node.body
                if isinstance(item, ast.FunctionDef)
                and not any(isinstance(d, ast.Name) and d.id == "property"
                            for d in item.decorator_list)
                and hasattr(getattr(cls, item.name, None), "__doc__")
                and type(getattr(cls, item.name)).__name__ in (
                    "builtin_function_or_method", "instancemethod")]
        else:
            continue
        for stub, function in functions:
            if type(function).__name__ == "function":
                continue  # defined in Python: no pybind11 signature line
            expected = doc_parameters(function)
            if expected is None:
                continue
            assert stub_parameters(stub) == expected, (
                node.name, stub.name)
            checked += 1
    assert checked > 30
