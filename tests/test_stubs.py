"""The typed stubs match the compiled module (``mypy.stubtest``) and the package's
Python files type-check (``mypy``)."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "python" / "rigidrs"


def run(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    # MYPYPATH would let mypy find the source tree's stub instead of the installed
    # package's; clear it so that stubtest checks what users import.
    env = {k: v for k, v in os.environ.items() if k != "MYPYPATH"}
    return subprocess.run([sys.executable, "-m", *args], cwd=cwd, env=env, capture_output=True, text=True, timeout=300)


@pytest.fixture(scope="module")
def mypy_available() -> None:
    try:
        import mypy  # noqa: F401
    except ImportError:
        pytest.skip("mypy is not importable: install the test extra (pip install '.[test]')")


def test_stubtest_accepts_the_compiled_module(mypy_available: None, tmp_path: Path) -> None:
    # Run outside the source tree so that `rigidrs` resolves to the installed wheel.
    result = run("mypy.stubtest", "rigidrs._core", "--mypy-config-file", os.devnull, cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr


def test_mypy_accepts_the_package_sources(mypy_available: None, tmp_path: Path) -> None:
    files = sorted(str(p) for p in PACKAGE.rglob("*.py*") if p.suffix in {".py", ".pyi"})
    assert any(f.endswith("_core.pyi") for f in files)
    result = run("mypy", "--no-incremental", "--config-file", os.devnull, *files, cwd=tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
