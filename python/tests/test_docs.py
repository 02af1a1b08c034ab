"""The Python example of docs/reliability.md section 3 runs as shown (the
block after the comment that names this file), from the repository root.

    bash scripts/python-env.sh && .venv/bin/pytest python/tests/test_docs.py -q
"""

import contextlib
import io
import os
import re


def test_the_docs_python_example_runs(root):
    text = (root / "docs/reliability.md").read_text()
    m = re.search(r"<!-- python/tests/test_docs\.py runs the next block -->\n```python\n(.*?)\n```", text, re.S)
    assert m, "the marked block of docs/reliability.md is gone"
    out = io.StringIO()
    here = os.getcwd()
    try:
        os.chdir(root)
        with contextlib.redirect_stdout(out):
            exec(compile(m.group(1), "docs/reliability.md", "exec"), {})
    finally:
        os.chdir(here)
    # The block's comment shows the start of what it prints.
    shown = re.search(r"print\(e\)\s+# (.*?)\.\.\.", m.group(1)).group(1)
    assert out.getvalue().startswith(shown), out.getvalue()


def python_blocks(text):
    return re.findall(r"```python\n(.*?)\n```", text, re.S)


def test_docs_python_md_blocks_run_and_say_what_they_show(root, cli, tmp_path):
    """docs/python.md: section 1's block runs; section 2's refusal is what
    Python raises and what the binary says, as shown."""
    first, second = python_blocks((root / "docs/python.md").read_text())[:2]
    here = os.getcwd()
    try:
        os.chdir(root)
        scope: dict = {}
        exec(compile(first, "docs/python.md", "exec"), scope)
        code = [line for line in second.splitlines() if not line.startswith("#")]
        shown_py = re.search(r"^# InputError: (.*)$", second, re.M).group(1)
        shown_cli = re.search(r"^# error: (.*)$", second, re.M).group(1)
        import deploywatch

        try:
            exec(compile("\n".join(code), "docs/python.md", "exec"), scope)
        except deploywatch.InputError as e:
            assert str(e) == shown_py
        else:
            raise AssertionError("docs/python.md section 2: the shown refusal did not happen")
    finally:
        os.chdir(here)
    import subprocess

    effect = re.search(r'effects=\["([^"]+)"\]', second).group(1)
    out = subprocess.run(
        [cli, "simulate", str(root / "data/mechanisms/seed001_T01.toml"), "--out", str(tmp_path / "r.csv"),
         "--effect", effect],
        capture_output=True, text=True,
    )
    assert out.returncode == 2 and out.stderr.strip().splitlines()[0] == "error: " + shown_cli, out.stderr
