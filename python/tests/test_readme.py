"""The README's Python example runs as written and prints what the README shows."""

import subprocess
import sys

from conftest import REPO


def _example() -> tuple[str, str]:
    """The code and the output printed after it in the README's section on Python."""
    text = (REPO / "README.md").read_text()
    section = text[text.index("## From Python: `import muse`") :]
    code = section[section.index("```python\n") + len("```python\n") :]
    code = code[: code.index("```")]
    shown = section[section.index("```text\n") + len("```text\n") :]
    return code, shown[: shown.index("```")]


def test_the_readme_example_prints_the_default_days_summary(tmp_path):
    code, shown = _example()
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path
    )
    assert done.returncode == 0, done.stderr
    print(done.stdout)
    assert done.stdout == shown
