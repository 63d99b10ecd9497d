"""The option table (src/backend/backend_option_table.cc, read through
symba._symba._option_table()) against Python's options classes, their
type stubs, and `symba replay`'s flags and summary.json: one name, one
default, one range everywhere (docs/backend.md, "Options and defaults")."""

import ast
import json
import math
import pathlib
import re

import pytest

import symba

TABLE = symba._symba._option_table()
GROUPS = {"mixture": symba.MixtureOptions,
          "categorization": symba.CategorizationOptions}
PYTHON_TYPES = {"bool": bool, "int": int, "float": float, "enum": str}


def split(name):
    """("mixture", "null_weight") or (None, "window_size")."""
    group, _, member = name.rpartition(".")
    return group or None, member


def resolve(options, name):
    for part in name.split("."):
        options = getattr(options, part)
    return options


def in_range(row, value):
    if math.isnan(value) or (math.isinf(value) and not row["allow_infinity"]):
        return False
    low_ok = value > row["low"] if row["low_open"] else value >= row["low"]
    high_ok = value < row["high"] if row["high_open"] else value <= row["high"]
    return low_ok and high_ok


def other_value(row):
    """An allowed value that is not the default."""
    default = row["default"]
    if row["type"] == "bool":
        return not default
    if row["type"] == "enum":
        choices = row["choices"]
        return choices[1] if default == choices[0] else choices[0]
    if row["type"] == "int":
        return default + 1 if in_range(row, default + 1) else default - 1
    candidate = 1.5 * default + 0.25
    return candidate if in_range(row, candidate) else (default + row["low"]) / 2


def flag_text(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value) if isinstance(value, float) else str(value)


def test_the_table_covers_every_attribute_of_the_options_classes():
    names = {row["name"] for row in TABLE}
    own = {n for n in names if "." not in n} | set(GROUPS)
    public = {n for n in dir(symba.BackendOptions()) if not n.startswith("_")}
    assert public - {"validate"} == own
    for group, cls in GROUPS.items():
        members = {n for n in dir(cls()) if not n.startswith("_")}
        assert members - {"validate"} == {
            split(n)[1] for n in names if n.startswith(group + ".")}


def test_every_option_has_the_table_default_type_and_doc():
    options = symba.BackendOptions()
    for row in TABLE:
        value = resolve(options, row["name"])
        assert value == row["default"], row["name"]
        assert type(value) is PYTHON_TYPES[row["type"]], row["name"]
        group, member = split(row["name"])
        cls = GROUPS[group] if group else symba.BackendOptions
        assert getattr(cls, member).__doc__ == row["doc"], row["name"]


def test_every_option_is_a_keyword():
    for row in TABLE:
        group, member = split(row["name"])
        value = other_value(row)
        options = (GROUPS[group] if group else symba.BackendOptions)(
            **{member: value})
        assert getattr(options, member) == value, row["name"]


def test_the_keywords_python_had_still_work():
    options = symba.BackendOptions(window_size=5, num_threads=2,
                                   object_loss="huber")
    assert (options.window_size, options.num_threads,
            options.object_loss) == (5, 2, "huber")


def stub_annotations(class_name):
    path = pathlib.Path(symba.__file__).with_name("__init__.pyi")
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.ClassDef) and node.name == class_name:
            return {item.target.id: ast.unparse(item.annotation)
                    for item in node.body if isinstance(item, ast.AnnAssign)}
    raise AssertionError(class_name + " is not in the stubs")


def stub_type(row):
    if row["type"] == "enum":
        return "Literal[" + ", ".join(
            f"'{choice}'" for choice in row["choices"]) + "]"
    return row["type"]


def test_the_stubs_give_every_option_the_table_type():
    for row in TABLE:
        group, member = split(row["name"])
        stubs = stub_annotations(GROUPS[group].__name__ if group
                                 else "BackendOptions")
        assert stubs[member] == stub_type(row), row["name"]


def test_replay_help_lists_every_option_with_its_default(cli):
    lines = cli("replay", "--help").stdout.splitlines()
    for row in TABLE:
        flag = "--" + row["name"]
        matching = [line for line in lines
                    if flag in line.replace(",", " ").split()]
        assert matching, flag
        shown_default = "=" + re.escape(row["default_text"]) + r"(\s|$)"
        assert re.search(shown_default, matching[0]), matching[0]


def replay_summary(cli, source_dir, tmp_path, *flags):
    out = tmp_path / "out"
    cli("replay", source_dir / "tests/data/replay/table.jsonl", "--out", out,
        "--quiet", *flags)
    return json.loads((out / "summary.json").read_text())["options"]


def test_every_flag_reaches_summary_json_under_its_name(cli, source_dir,
                                                        tmp_path):
    flags, expected = [], {}
    for row in TABLE:
        value = other_value(row)
        flags += ["--" + row["name"], flag_text(value)]
        expected[row["name"]] = value
    options = replay_summary(cli, source_dir, tmp_path, *flags)
    for name, value in expected.items():
        group, member = split(name)
        reported = options[group][member] if group else options[member]
        assert reported == value, name


def test_the_old_flags_still_work(cli, source_dir, tmp_path):
    options = replay_summary(
        cli, source_dir, tmp_path, "--window", "3", "--threads", "2",
        "--loss", "huber", "--loss-scale", "2.5", "--point-sigma", "1.5",
        "--gate-axis", "10", "--null-hypothesis", "--merge-modes", "false")
    assert options["window_size"] == options["window"] == 3
    assert options["num_threads"] == options["threads"] == 2
    assert options["object_loss"] == "huber"
    assert options["object_loss_scale"] == 2.5
    assert options["point_sigma_px"] == 1.5
    assert options["gate_axis"] == pytest.approx(math.radians(10), rel=1e-15)
    assert options["mixture"]["use_null_hypothesis"] is True
    assert options["null_hypothesis"] is True
    assert options["merge_modes"] is False
