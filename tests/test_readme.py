"""The README's code, run as pasted: every ``python`` block of README.md is executed
on its own, in a fresh namespace, exactly as it stands (so it must import what it
uses), so the documented API stays the real one. A block that drifts from the API
fails here, naming its section and its position."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"


def blocks() -> list[tuple[str, str]]:
    """(section title, code) of every python block, in order."""
    out: list[tuple[str, str]] = []
    title = "(top)"
    text = README.read_text(encoding="utf-8")
    for match in re.finditer(r"^## ([^\n]*)$|^```python\n(.*?)^```", text, flags=re.S | re.M):
        if match.group(1) is not None:
            title = match.group(1).strip()
        else:
            out.append((title, match.group(2)))
    return out


BLOCKS = blocks()


def test_readme_has_snippets() -> None:
    assert len(BLOCKS) >= 4


@pytest.mark.parametrize("title,code", BLOCKS, ids=[f"{i}:{t[:30]}" for i, (t, _) in enumerate(BLOCKS)])
def test_snippet_runs_as_pasted(title: str, code: str) -> None:
    exec(compile(code, f"README.md ## {title}", "exec"), {"__name__": "readme"})
