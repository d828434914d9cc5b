"""Every ```python example block of README.md and docs/ runs (from the repository's root, its
outputs kept out of it), so the documented Python cannot rot."""

import os
import re

import pytest

from conftest import REPO

DOCS = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]


def blocks():
    return list(_blocks())


def _blocks():
    for doc in DOCS:
        text = doc.read_text(encoding="utf-8")
        for k, m in enumerate(re.finditer(r"^```python example\n(.*?)^```$", text, re.S | re.M)):
            yield pytest.param(m.group(1), id=f"{doc.name}-{k}")


def test_there_are_python_examples():
    assert len(blocks()) >= 2


@pytest.mark.parametrize("code", blocks())
def test_python_example_runs(code, tmp_path, monkeypatch):
    monkeypatch.chdir(REPO)
    code = code.replace("out/", f"{tmp_path}{os.sep}")
    exec(compile(code, "<example>", "exec"), {})
