"""The README's Python example prints what the README says it prints."""

import contextlib
import io
import os
import re

from conftest import ROOT


def test_readme_example_prints_its_numbers(tmp_path):
    text = (ROOT / "README.md").read_text()
    section = text[text.index("## Python") :]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    printed = re.search(r"\nprints `([^`]*)`", section).group(1)
    out = io.StringIO()
    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        code = code.replace('"model.json"', repr(str(tmp_path / "model.json")))
        with contextlib.redirect_stdout(out):
            exec(compile(code, "README.md", "exec"), {})
    finally:
        os.chdir(cwd)
    assert out.getvalue().strip() == printed
    assert (tmp_path / "model.json").read_text().startswith('{\n  "format": "hsid-model/1"')
