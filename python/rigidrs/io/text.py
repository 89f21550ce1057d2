"""Scene data as text: a small TOML writer (scene data only holds tables, arrays,
str, int, float and bool; floats are written with ``repr``, which reads back to
the same bits) and a JSON writer that keeps arrays of numbers on one line."""
from __future__ import annotations

import json
import math
import re
from typing import Any

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: str) -> str:
    return k if _BARE.match(k) else json.dumps(k, ensure_ascii=False)


def _scalar(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            raise ValueError(f"non-finite float {v} in scene data (write it as \"inf\")")
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    raise ValueError(f"cannot write a {type(v).__name__} to TOML")


def _toml_value(v: Any, indent: str = "") -> str:
    if isinstance(v, list):
        if any(isinstance(x, list) for x in v):
            inner = indent + "  "
            rows = "".join(f"{inner}{_toml_value(x, inner)},\n" for x in v)
            return f"[\n{rows}{indent}]"
        if any(isinstance(x, dict) for x in v):
            raise ValueError("arrays mixing tables and values cannot be written")
        return "[" + ", ".join(_scalar(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {_toml_value(x)}" for k, x in v.items()) + "}"
    return _scalar(v)


def _is_table_array(v: Any) -> bool:
    return isinstance(v, list) and len(v) > 0 and all(isinstance(x, dict) for x in v)


def _toml_table(lines: list[str], path: list[str], d: dict[str, Any]) -> None:
    for k, v in d.items():
        if v is None:
            raise ValueError(f"{'.'.join(path + [k])}: None cannot be written to TOML")
        if not isinstance(v, dict) and not _is_table_array(v):
            lines.append(f"{_key(k)} = {_toml_value(v)}")
    for k, v in d.items():
        if isinstance(v, dict):
            sub = path + [_key(k)]
            lines += ["", f"[{'.'.join(sub)}]"]
            _toml_table(lines, sub, v)
    for k, v in d.items():
        if _is_table_array(v):
            sub = path + [_key(k)]
            for item in v:
                lines += ["", f"[[{'.'.join(sub)}]]"]
                _toml_table(lines, sub, item)


def to_toml(d: dict[str, Any]) -> str:
    """TOML text of `d` (tables as ``[a.b]``, arrays of tables as ``[[a]]``)."""
    lines: list[str] = []
    _toml_table(lines, [], d)
    return "\n".join(lines).lstrip("\n") + "\n"


def to_json(v: Any, indent: str = "") -> str:
    """JSON text of `v`: objects one key a line, arrays of numbers on one line."""
    inner = indent + "  "
    if isinstance(v, dict):
        if not v:
            return "{}"
        items = ",\n".join(f"{inner}{json.dumps(k, ensure_ascii=False)}: {to_json(x, inner)}" for k, x in v.items())
        return "{\n" + items + "\n" + indent + "}"
    if isinstance(v, list):
        if not any(isinstance(x, (dict, list)) for x in v):
            return json.dumps(v, allow_nan=False, ensure_ascii=False)
        items = ",\n".join(inner + to_json(x, inner) for x in v)
        return "[\n" + items + "\n" + indent + "]"
    return json.dumps(v, allow_nan=False, ensure_ascii=False)
