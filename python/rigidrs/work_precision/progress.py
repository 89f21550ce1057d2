"""A progress bar: tqdm's if it is installed, a one-line text bar otherwise."""
from __future__ import annotations

import importlib
import sys
from typing import Any, TextIO


class Progress:
    """``tick(text)`` before each of ``total`` runs, ``close()`` at the end."""

    def __init__(self, total: int, enabled: bool = True, stream: TextIO | None = None) -> None:
        self.total, self.done, self.enabled = total, -1, enabled
        self.stream = stream or sys.stderr
        self.bar: Any = None
        if enabled:
            try:
                tqdm = importlib.import_module("tqdm").tqdm
                self.bar = tqdm(total=total, file=self.stream, unit="run", dynamic_ncols=True)
            except ImportError:
                self.bar = None

    def tick(self, text: str) -> None:
        self.done += 1
        if not self.enabled:
            return
        if self.bar is not None:
            self.bar.update(0 if self.done == 0 else 1)
            self.bar.set_description_str(text)
            return
        width = 30
        filled = width * self.done // max(self.total, 1)
        line = f"[{'#' * filled}{'.' * (width - filled)}] {self.done}/{self.total} {text}"
        self.stream.write("\r" + line[:100].ljust(100))
        self.stream.flush()

    def close(self) -> None:
        if not self.enabled:
            return
        if self.bar is not None:
            self.bar.update(self.total - self.bar.n)
            self.bar.close()
        else:
            self.stream.write(f"\r[{'#' * 30}] {self.total}/{self.total}".ljust(100) + "\n")
            self.stream.flush()
