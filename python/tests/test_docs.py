"""The Python examples of docs/reliability.md run as shown: section 3's
(the block after the comment that names this file), from the repository
root, and section 4's command and its Dask call, which give the same
result; docs/python.md's first two blocks.

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


def test_the_docs_dask_example_gives_the_cli_s_bits(root, cli, tmp_path):
    """docs/reliability.md section 4: the command of its first block, then
    its Dask block (which asserts equality with the command's JSON), in a
    folder where `data/` is the repository's."""
    import shlex
    import subprocess

    text = (root / "docs/reliability.md").read_text()
    section = text[text.index("## 4. "):text.index("## 5. ")]
    sh = re.search(r"```sh\n(.*?)\n```", section, re.S).group(1)
    command = " ".join(line for line in sh.replace("\\\n", " ").splitlines() if not line.startswith("#"))
    args = shlex.split(command)
    assert args[0] == "deploywatch", args
    (tmp_path / "data").symlink_to(root / "data")
    out = subprocess.run([cli, *args[1:]], cwd=tmp_path, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    block = python_blocks(section)[0]
    here = os.getcwd()
    try:
        os.chdir(tmp_path)
        exec(compile(block, "docs/reliability.md", "exec"), {})
    finally:
        os.chdir(here)


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
