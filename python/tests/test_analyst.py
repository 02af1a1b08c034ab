"""The worked example (python/examples/analyst.py) runs, and prints what
docs/python.md section 4 shows.

    bash scripts/python-env.sh && .venv/bin/pytest python/tests/test_analyst.py -q
"""

import re
import subprocess
import sys


def test_the_analyst_example_prints_what_the_docs_show(root, tmp_path):
    out = subprocess.run(
        [sys.executable, str(root / "python/examples/analyst.py"), str(tmp_path)],
        cwd=root, capture_output=True, text=True, timeout=900,
    )
    assert out.returncode == 0, out.stderr
    doc = (root / "docs/python.md").read_text()
    m = re.search(r"<!-- python/tests/test_analyst\.py compares the next block with the example's output -->\n"
                  r"```text\n(.*?)```", doc, re.S)
    assert m, "the marked block of docs/python.md is gone"
    assert out.stdout == m.group(1), out.stdout
    # The diagnosis' report and the project's plots are written.
    assert (tmp_path / "diagnosis.json").exists() and (tmp_path / "diagnosis.md").exists()
    assert list(tmp_path.glob("diagnosis_*.png"))
