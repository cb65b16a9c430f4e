"""The Python examples of the README and of the Python guide run as written and print what
they show."""

import subprocess
import sys

import pytest

from conftest import REPO

# Each file with a tested example, and the heading of the section that holds it: the first
# ```python block after the heading, and the ```text block after that, which shows its output.
EXAMPLES = [
    ("README.md", "## From Python: `import muse`"),
    ("docs/guides/python.md", "# From Python: `import muse`"),
]


def _example(path: str, heading: str) -> tuple[str, str]:
    """The code and the output printed after it in the section `heading` of `path`."""
    text = (REPO / path).read_text()
    section = text[text.index(heading + "\n") :]
    code = section[section.index("```python\n") + len("```python\n") :]
    code = code[: code.index("```")]
    shown = section[section.index("```text\n") + len("```text\n") :]
    return code, shown[: shown.index("```")]


@pytest.mark.parametrize(("path", "heading"), EXAMPLES, ids=[p for p, _ in EXAMPLES])
def test_the_example_prints_the_default_days_summary(tmp_path, path, heading):
    code, shown = _example(path, heading)
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path
    )
    assert done.returncode == 0, done.stderr
    print(done.stdout)
    assert done.stdout == shown
