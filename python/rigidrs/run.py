"""``rigidrs run SCENE``: simulate a scene file for some seconds, write what was asked
(recording, video or picture, glTF, USD: chosen by each file's extension), print what
was written and measured, and optionally open the viewer on the result.

SCENE is a Python file that defines ``scene`` (a Scene or World) or ``make_scene()``
returning one (and optionally ``dt``, s), or a scene file (``.toml``, ``.json``) read by
``rigidrs.load_scene`` where this version has it.
"""
from __future__ import annotations

import os
import runpy
import sys
import time
from pathlib import Path
from typing import Any, Callable, TextIO

from .view.render import _writable_folder

DEFAULT_DT = 1.0 / 120.0
"""Time step (s) when neither ``--dt`` nor the scene file gives one."""
FRAMES_PER_SECOND = 60.0
"""Recorded frames per simulated second when ``--every`` is not given."""

KINDS = {".npz": "recording", ".png": "picture", ".gif": "video", ".mp4": "video",
         ".glb": "glTF", ".gltf": "glTF", ".usd": "USD", ".usda": "USD", ".usdc": "USD"}
"""Output kind by extension."""


class RunError(Exception):
    """A bad argument or scene file: the message says which and why."""


def load(path: str | os.PathLike[str], dt: float | None) -> Any:
    """The World to run: ``path`` loaded (Python file or scene file) and built with time
    step ``dt`` (s; default the file's ``dt``, else :data:`DEFAULT_DT`). A World given by the
    file is used as it is (its own time step; ``dt`` must then be None or equal)."""
    import rigidrs as rr

    p = Path(path)
    if not p.is_file():
        raise RunError(f"{p}: no such scene file")
    file_dt = None
    if p.suffix == ".py":
        try:
            ns = runpy.run_path(str(p), run_name="rigidrs_scene")
        except Exception as e:
            raise RunError(f"{p}: running it raised {type(e).__name__}: {e}") from e
        if "make_scene" in ns and callable(ns["make_scene"]):
            obj = ns["make_scene"]()
        elif "scene" in ns:
            obj = ns["scene"]
        else:
            raise RunError(f"{p}: defines neither `scene` (a rigidrs Scene or World) nor `make_scene()`")
        file_dt = ns.get("dt")
    else:
        load_scene: Callable[[Any], Any] | None = getattr(rr, "load_scene", None)
        if load_scene is None:
            raise RunError(f"{p}: this rigidrs cannot read scene files (no rigidrs.load_scene); "
                           "give a Python file defining `scene` or `make_scene()`")
        try:
            obj = load_scene(p)
        except Exception as e:
            raise RunError(f"{p}: {e}") from e
    step = dt if dt is not None else file_dt
    if isinstance(obj, rr.World):
        if step is not None and dt is not None and float(dt) != obj.dt:
            raise RunError(f"{p}: gives a built World (dt = {obj.dt} s); --dt {dt} cannot change it")
        return obj
    if not isinstance(obj, rr.Scene):
        raise RunError(f"{p}: `scene` must be a rigidrs Scene or World, got {type(obj).__name__}")
    step = DEFAULT_DT if step is None else float(step)
    if not (step > 0 and step < float("inf")):
        raise RunError(f"time step must be a positive number of seconds, got {step!r}")
    try:
        return obj.build(dt=step)
    except Exception as e:
        raise RunError(f"{p}: building the scene failed: {e}") from e


def check_outputs(paths: list[str]) -> list[Path]:
    """The output paths, each with a known extension in an existing writable directory
    (checked before anything is simulated)."""
    out = []
    for s in paths:
        p = Path(s)
        if p.suffix.lower() not in KINDS:
            raise RunError(f"{p}: unknown output format {p.suffix!r}; use one of {', '.join(KINDS)}")
        try:
            _writable_folder(p)
        except OSError as e:
            raise RunError(str(e)) from e
        out.append(p)
    return out


class _Bar:
    """A one-line progress bar on a terminal, redrawn at most 10 times a second."""

    def __init__(self, stream: TextIO, total: int) -> None:
        self.stream, self.total, self.last = stream, total, -1.0

    def __call__(self, done: int) -> None:
        now = time.perf_counter()
        if now - self.last < 0.1 and done < self.total:
            return
        self.last = now
        width = 30
        k = width * done // max(self.total, 1)
        self.stream.write(f"\r[{'#' * k}{'.' * (width - k)}] {done}/{self.total} steps")
        self.stream.flush()


def simulate(world: Any, steps: int, every: int, record: bool, progress: TextIO | None,
             capture: Any = None) -> tuple[Any, float, str | None]:
    """Steps ``world`` ``steps`` times (recording every ``every``-th step when ``record``;
    through ``capture``, a :class:`rigidrs.view.extras.Capture`, when given): (recording or
    None, wall seconds spent stepping, error message or None). A step that fails stops
    the run; the frames before it are kept."""
    from . import SimulationError

    rec = world.record(every=every) if record else None
    advance = capture.step if capture is not None else world.step
    chunk = max(1, steps // 100)
    done, wall, error = 0, 0.0, None
    bar = _Bar(progress, steps) if progress is not None else None
    try:
        while done < steps:
            n = min(chunk, steps - done)
            t0 = time.perf_counter()
            advance(n)
            wall += time.perf_counter() - t0
            done += n
            if bar is not None:
                bar(done)
    except SimulationError as e:
        error = str(e)
    except KeyboardInterrupt:
        error = f"interrupted after {world.steps} steps"
    finally:
        if progress is not None:
            progress.write("\n")
        if rec is not None:
            rec.detach()
    return rec, wall, error


def write(world: Any, rec: Any, path: Path, extras: Any = None) -> None:
    import rigidrs as rr

    kind = KINDS[path.suffix.lower()]
    if kind == "recording":
        if extras is not None:
            extras.save(path, rec)
        else:
            rec.save(path)
    elif kind in ("picture", "video"):
        rr.render(world, rec, path)
    elif kind == "glTF":
        rr.export_gltf(world, rec, path)
    else:
        rr.export_usd(world, rec, path)


def run(scene: str, *, seconds: float = 5.0, dt: float | None = None, every: int | None = None,
        outputs: list[str] | None = None, view: bool = False, port: int = 8080, progress: bool = True,
        energies: bool = False, contacts: bool = False, out: TextIO | None = None) -> int:
    """The ``rigidrs run`` command; returns the exit code (0 done, 1 the simulation
    failed part-way (what was recorded is still written), 2 bad arguments or scene).
    ``energies``/``contacts``: capture them per frame (:mod:`rigidrs.view.extras`) into
    the ``.npz`` recording."""
    out = out or sys.stdout
    err = sys.stderr
    try:
        if not (seconds >= 0 and seconds < float("inf")):
            raise RunError(f"--seconds must be a non-negative number, got {seconds!r}")
        if every is not None and every < 1:
            raise RunError(f"--every must be a positive number of steps, got {every!r}")
        paths = check_outputs(outputs or [])
        world = load(scene, dt)
    except RunError as e:
        err.write(f"rigidrs run: {e}\n")
        return 2
    steps = int(round(seconds / world.dt))
    steps0, time0 = world.steps, world.time
    k = every or max(1, int(round(1.0 / (FRAMES_PER_SECOND * world.dt))))
    e0 = world.kinetic_energy() + world.potential_energy()
    out.write(f"{scene}: {len(world.bodies)} bodies, {len(world.particles)} particles, {len(world.joints)} joints; "
              f"{steps} steps of {world.dt:.6g} s ({seconds:g} s), integrator {world.integrator!r}\n")
    bar = err if progress and err.isatty() else None
    capture = None
    if energies or contacts:
        from .view.extras import Capture

        capture = Capture(world, k, energies=energies, contacts=contacts)
    rec, wall, error = simulate(world, steps, k, bool(paths) or view, bar, capture)
    extras = capture.extras if capture is not None else None
    e1 = world.kinetic_energy() + world.potential_energy()
    taken, simulated = world.steps - steps0, world.time - time0
    rate = f"{taken / wall:,.0f} steps/s, {simulated / wall:,.1f}x real time" if wall > 0 else "no steps"
    change = f"{e1 - e0:+.4g} J" + (f" ({(e1 - e0) / abs(e0):+.2e} of the start)" if e0 != 0 else "")
    out.write(f"simulated {simulated:g} s in {wall:.2f} s of stepping: {rate}; "
              f"energy (kinetic + potential) change {change}\n")
    if error:
        err.write(f"rigidrs run: stopped: {error}\n")
    if rec is not None:
        out.write(f"recorded {len(rec)} frames, every {k} steps ({rec.nbytes / 1e3:,.1f} kB in memory)\n")
    for p in paths:
        t0 = time.perf_counter()
        try:
            write(world, rec, p, extras)
        except (OSError, ValueError, ImportError) as e:
            err.write(f"rigidrs run: {p}: {e}\n")
            return 2
        size = f", {os.path.getsize(p) / 1e3:,.1f} kB" if p.is_file() else ""
        out.write(f"wrote {p} ({KINDS[p.suffix.lower()]}{size}, {time.perf_counter() - t0:.2f} s)\n")
    if view:
        from .view import view as open_view

        open_view(world, rec, port=port)
    return 1 if error else 0
