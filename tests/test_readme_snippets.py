"""The README's code, run as pasted: every ``python`` block of the sections named
here is executed on its own, in a fresh namespace, exactly as it stands in README.md
(so it must import what it uses). A section whose snippets drift from the API fails
here, naming the section and the block."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parent.parent / "README.md"

# Sections (their "## " titles) whose snippets must run as pasted.
SECTIONS = ["Particles (XPBD) and shape matching"]


def snippets(title: str) -> list[str]:
    text = README.read_text(encoding="utf-8")
    match = re.search(rf"^## {re.escape(title)}\n(.*?)(?=^## |\Z)", text, flags=re.S | re.M)
    assert match, f"README.md has no section '## {title}'"
    return re.findall(r"^```python\n(.*?)^```", match.group(1), flags=re.S | re.M)


@pytest.mark.parametrize("title", SECTIONS)
def test_readme_snippets_run_as_pasted(title: str) -> None:
    blocks = snippets(title)
    assert blocks, f"'## {title}' has no python block"
    for k, code in enumerate(blocks):
        exec(compile(code, f"README.md ## {title} [block {k}]", "exec"), {"__name__": "readme"})
