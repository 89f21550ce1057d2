"""The README's Python snippets run as written (each in a fresh namespace with
numpy and rigidrs imported), so the documented API stays the real one."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"
SNIPPETS = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.S)


def test_readme_has_snippets() -> None:
    assert len(SNIPPETS) >= 4


@pytest.mark.parametrize("code", SNIPPETS, ids=[f"snippet{i}" for i in range(len(SNIPPETS))])
def test_snippet_runs(code: str) -> None:
    namespace: dict[str, object] = {}
    exec(compile("import numpy as np\nimport rigidrs as rr\n" + code, str(README), "exec"), namespace)
