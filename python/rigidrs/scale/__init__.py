"""Scale beyond one world: :func:`sweep` runs a function over parameters in
processes or on a Dask cluster. (``Batch``, B worlds stepped together, and the
``threads=`` build argument live in the compiled core.)"""
from __future__ import annotations

from .sweep import SweepError, SweepFailure, sweep

__all__ = ["SweepError", "SweepFailure", "sweep"]
