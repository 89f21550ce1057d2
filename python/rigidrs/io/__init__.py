"""Models in: URDF (``rr.Scene.from_urdf``) and MJCF (``rr.Scene.from_mjcf``) importers
and the report of what they dropped or approximated (``scene.import_report``)."""
from .. import _core
from .mjcf import from_mjcf
from .report import ImportReport, ReportEntry
from .robot import ModelError
from .urdf import from_urdf

setattr(_core.Scene, "from_urdf", classmethod(from_urdf))
setattr(_core.Scene, "from_mjcf", classmethod(from_mjcf))

__all__ = ["ImportReport", "ModelError", "ReportEntry", "from_mjcf", "from_urdf"]
