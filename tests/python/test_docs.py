"""docs/python.md's example runs as printed, so the page cannot drift from
the API."""

import contextlib
import io
import re


def test_the_documented_example_runs(source_dir):
    text = (source_dir / "docs" / "python.md").read_text()
    code = re.search(r"```python\n(.*?)\n```", text, re.S).group(1)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, "docs/python.md", "exec"), {})
    lines = out.getvalue().splitlines()
    assert lines[0].startswith(
        "[MapObject(id=0, class_name='table', symmetry='discrete'")
    assert lines[1] == "(6, 7)"
