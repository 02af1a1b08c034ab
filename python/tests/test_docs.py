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
