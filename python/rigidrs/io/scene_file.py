"""``scene.save(path)`` and ``rigidrs.load_scene(path)``: scene data in a TOML or
JSON file (chosen by the extension). Saving writes a temporary file next to the
target and renames it over, so a reader never sees half a file. Loading names
the file, the path inside it and, where the format gives one, the line."""
from __future__ import annotations

import json
import os
import re
import tempfile
import tomllib
from pathlib import Path
from typing import Any

from .. import _core
from .scene_dict import SceneDataError, from_dict, to_dict
from .text import to_json, to_toml

SUFFIXES = (".toml", ".json")


def _suffix(path: Path) -> str:
    s = path.suffix.lower()
    if s not in SUFFIXES:
        raise ValueError(f"{path}: unknown scene file extension {path.suffix!r}; supported: {', '.join(SUFFIXES)}")
    return s


def save(scene: _core.Scene, path: str | os.PathLike[str]) -> None:
    """Writes ``scene`` (its ``to_dict`` data) to ``path``: ``.toml`` or ``.json``.
    Mesh data is written inline (the file stands alone)."""
    p = Path(path)
    kind = _suffix(p)
    data = to_dict(scene)
    text = to_toml(data) if kind == ".toml" else to_json(data) + "\n"
    folder = p.parent if str(p.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, p)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _parse(p: Path, text: str, kind: str) -> Any:
    try:
        if kind == ".toml":
            return tomllib.loads(text)
        return json.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise SceneDataError(f"{p}: malformed TOML: {e}") from None
    except json.JSONDecodeError as e:
        raise SceneDataError(f"{p}: malformed JSON: {e.msg} (at line {e.lineno}, column {e.colno})") from None


_ITEM = re.compile(r"^(\w+)\[(\d+)\]((?:\.\w+|\[\d+\])*)")
_HEADER = re.compile(r"^\[\[?([^\]]+)\]\]?\s*$")
_KEY = re.compile(r"^(\w+)\s*=")


def _toml_line(text: str, message: str) -> int | None:
    """The line of ``array[i].key...`` in TOML written with ``[[array]]`` tables (as
    ``save`` writes them): the line of the deepest part of the path found within
    item ``i`` (array indices below it are not told apart), or None."""
    m = _ITEM.match(message)
    if not m:
        return None
    array, index = m.group(1), int(m.group(2))
    want = re.findall(r"\.(\w+)", m.group(3))
    lines = text.splitlines()
    starts = [n for n, line in enumerate(lines) if line.strip() == f"[[{array}]]"]
    if index >= len(starts):
        return None
    best, depth, table = starts[index] + 1, 0, []
    for n in range(starts[index] + 1, len(lines)):
        s = lines[n].strip()
        h = _HEADER.match(s)
        if h:
            parts = [x.strip() for x in h.group(1).split(".")]
            if parts[0] != array or len(parts) == 1:
                break
            table = parts[1:]
            key_path = table
        else:
            k = _KEY.match(s)
            if not k:
                continue
            key_path = table + [k.group(1)]
        matched = 0
        while matched < min(len(key_path), len(want)) and key_path[matched] == want[matched]:
            matched += 1
        if matched == len(key_path) and matched > depth:
            best, depth = n + 1, matched
    return best


def load_scene(path: str | os.PathLike[str]) -> _core.Scene:
    """A scene from a ``.toml`` or ``.json`` scene file (see ``docs/scene_format.md``).

    Mesh ``file`` entries are read relative to the scene file. Its ``build`` table
    becomes ``scene.build_settings`` (``scene.build(**scene.build_settings)``).
    Raises ``FileNotFoundError`` for a missing file, ``ValueError`` for an unknown
    extension, and a ``RigidError`` (a ``ValueError``) naming the file, the path
    inside it and the line (TOML syntax, JSON syntax, and TOML tables) otherwise.
    """
    p = Path(path)
    kind = _suffix(p)
    text = p.read_text(encoding="utf-8")
    data = _parse(p, text, kind)
    try:
        return from_dict(data, base_dir=p.parent)
    except (ValueError, TypeError) as e:
        line = _toml_line(text, str(e)) if kind == ".toml" else None
        where = f"{p}, line {line}" if line else f"{p}"
        try:
            new = type(e)(f"{where}: {e}")
        except Exception:
            new = SceneDataError(f"{where}: {e}")
        raise new from e
