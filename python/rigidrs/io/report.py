"""What an importer dropped or approximated, and why: one entry per element."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable

# What happened to an element of the file.
DROPPED = "dropped"            # not in the scene at all
APPROXIMATED = "approximated"  # in the scene, but not exactly as the file says
MAPPED = "mapped"              # in the scene, through a rule worth knowing (e.g. effort -> max_force)


@dataclass(frozen=True)
class ReportEntry:
    """One thing the file had that the scene does not hold exactly.

    ``element``: the tag or kind (``"visual"``, ``"transmission"``, ``"joint.limit"``,
    ``"geom"``, ...); ``name``: the named element it belongs to (link, joint, geom),
    or None; ``action``: ``"dropped"``, ``"approximated"`` or ``"mapped"``;
    ``reason``: why, in words; ``line``: line in ``file`` (None where unknown);
    ``file``: the file it came from."""

    element: str
    name: str | None
    action: str
    reason: str
    line: int | None = None
    file: str | None = None

    def __str__(self) -> str:
        where = f" (line {self.line})" if self.line is not None else ""
        who = f" {self.name!r}" if self.name is not None else ""
        return f"{self.action}: <{self.element}>{who}{where}: {self.reason}"


class ImportReport(list[ReportEntry]):
    """The entries of one import, in file order; ``str()`` groups them for reading.

    A plain list of ``ReportEntry``; ``source`` is the file read (None for a scene
    built by hand). ``dropped()``, ``approximated()`` and ``mapped()`` filter by action."""

    def __init__(self, entries: Iterable[ReportEntry] = (), source: str | None = None) -> None:
        super().__init__(entries)
        self.source = source

    def add(self, element: str, name: str | None, action: str, reason: str,
            line: int | None = None) -> None:
        """Appends an entry for ``element`` of this report's ``source``."""
        if action not in (DROPPED, APPROXIMATED, MAPPED):
            raise ValueError(f"action must be dropped, approximated or mapped, got {action!r}")
        self.append(ReportEntry(element, name, action, reason, line, self.source))

    def dropped(self) -> list[ReportEntry]:
        return [e for e in self if e.action == DROPPED]

    def approximated(self) -> list[ReportEntry]:
        return [e for e in self if e.action == APPROXIMATED]

    def mapped(self) -> list[ReportEntry]:
        return [e for e in self if e.action == MAPPED]

    def __str__(self) -> str:
        head = f"import report for {self.source}" if self.source else "import report"
        if not self:
            return f"{head}: nothing dropped or approximated"
        groups: dict[tuple[str, str, str], list[ReportEntry]] = {}
        for e in self:
            groups.setdefault((e.action, e.element, e.reason), []).append(e)
        lines = [f"{head}: {len(self.dropped())} dropped, {len(self.approximated())} approximated, "
                 f"{len(self.mapped())} mapped"]
        for (action, element, reason), entries in groups.items():
            names = [n for n in (e.name for e in entries) if n is not None]
            shown = ", ".join(repr(n) for n in names[:6]) + (f", ... ({len(names)} in all)" if len(names) > 6 else "")
            count = f" x{len(entries)}" if len(entries) > 1 else ""
            lines.append(f"  {action} <{element}>{count}{': ' + shown if shown else ''} -- {reason}")
        return "\n".join(lines)

    def __repr__(self) -> str:
        return f"ImportReport({list.__repr__(self)}, source={self.source!r})"
