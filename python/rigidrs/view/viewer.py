"""Interactive viewer in the browser: ``rr.view(world_or_recording)`` (viser).

A viser server (``pip install "rigidrs[view]"``) serves a three.js page; this module
puts one mesh per shape in it (tessellated by :mod:`rigidrs.view.mesh`, as the
renderer and the glTF export draw them) and moves the meshes to the bodies' poses:

* a **recording** is played back: a frame slider, play/pause, a speed (simulated
  seconds per second), looping;
* a **live world** is stepped by the viewer: play/pause, one step, a target real-time
  factor; the achieved steps/s and real-time factor are shown. A step that fails
  (``SimulationError``) pauses the viewer and shows the message.

Clicking a body shows its name, mass, position and velocity. Nothing here needs a
display: the page is drawn by whatever browser connects (it works over SSH with a
forwarded port), so the viewer can be started, inspected and closed headless.
"""
from __future__ import annotations

import threading
import time
from typing import Any, Mapping, Sequence

import numpy as np

from .gltf import _ground
from .mesh import F64, quat_matrix, shape_mesh
from .render import _bounds, _camera, body_colors

TICK = 1.0 / 60.0
"""Seconds between two updates of the viewer loop (the page's frame rate at most)."""
STEP_BUDGET = 0.03
"""Seconds of stepping allowed per tick of a live world; a world slower than the target
real-time factor drops the rest (the achieved factor is shown)."""


def _viser() -> Any:
    try:
        import viser
    except ImportError as e:
        raise ImportError('rr.view needs viser: pip install "rigidrs[view]"') from e
    return viser


def _wxyz(q: F64) -> F64:
    """rigidrs quaternions are (x, y, z, w); viser's are (w, x, y, z)."""
    return np.asarray(q, dtype=np.float64)[..., [3, 0, 1, 2]]


class Viewer:
    """A running viewer (what :func:`view` returns): ``server`` (the ``viser.ViserServer``),
    ``port``, ``url``, ``meshes`` (per body its mesh node, None for a body without a
    shape), ``frame`` (recording frame shown), ``world`` and ``recording`` (either may be
    None). ``close()`` stops the server and the loop; also a context manager."""

    def __init__(self, world: Any, rec: Any, shapes: Sequence[Mapping[str, Any] | None], *,
                 host: str, port: int, playing: bool, speed: float, loop: bool,
                 colors: Any, detail: int, ground_size: float | None) -> None:
        viser = _viser()
        self.world, self.recording = world, rec
        self.frame = 0
        self.selected: int | None = None
        self._lock = threading.RLock()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._error: str | None = None
        self._clock = 0.0  # playback time (s) of a recording
        self._debt = 0.0  # simulated seconds still to step (live)
        self._rate = (0.0, 0.0)  # achieved (steps/s, real-time factor) of a live world
        self._step_cost = 1e-4  # running estimate of one step's wall time (s)
        pos, quat, parts = self._pose(0)
        self.server = viser.ViserServer(host=host, port=port, verbose=False)
        self.port = int(self.server.get_port())
        self.url = f"http://{'localhost' if host in ('0.0.0.0', '127.0.0.1') else host}:{self.port}"
        self.server.scene.set_up_direction("+z")
        lo, hi = _bounds(shapes, self._all_positions(), self._all_orientations(), None)
        self._add_meshes(shapes, pos, quat, colors, detail, ground_size, lo, hi)
        self._points = None
        if parts.shape[0]:
            radius = float(np.median(world.particles.radius)) if world is not None else 0.0
            if radius <= 0:  # no collision radius: 1 % of the scene's size
                radius = max(0.005 * float(np.max(hi - lo)), 1e-3)
            self._points = self.server.scene.add_point_cloud(
                "/particles", parts.astype(np.float32), (235, 235, 242), point_size=2 * radius,
                point_shape="circle", precision="float32")
        # The first view frames the bodies as they are at the start (the renderer's default
        # camera for that frame); the ground spans the whole recording.
        cam = _camera(None, *_bounds(shapes, pos[None], quat[None], None), 4 / 3)
        self.server.initial_camera.fov = float(np.radians(cam.fov))
        self.server.initial_camera.position = tuple(float(x) for x in cam.eye)
        self.server.initial_camera.look_at = tuple(float(x) for x in cam.target)
        self._build_gui(playing, speed, loop)

    # ------------------------------------------------------------------ state
    def _pose(self, k: int) -> tuple[F64, F64, F64]:
        """Body positions, orientations and particle positions shown at frame k (live: now)."""
        if self.recording is not None:
            return (self.recording.position[k], self.recording.orientation[k],
                    self.recording.particle_position[k])
        w = self.world
        return np.array(w.bodies.position), np.array(w.bodies.orientation), np.array(w.particles.position)

    def _all_positions(self) -> F64:
        return self.recording.position if self.recording is not None else self._pose(0)[0][None]

    def _all_orientations(self) -> F64:
        return self.recording.orientation if self.recording is not None else self._pose(0)[1][None]

    def _add_meshes(self, shapes: Sequence[Mapping[str, Any] | None], pos: F64, quat: F64, colors: Any,
                    detail: int, ground_size: float | None, lo: F64, hi: F64) -> None:
        fixed = (~(np.asarray(self.world.bodies.inverse_mass) > 0) if self.world is not None
                 else np.zeros(len(shapes), bool))
        rgb = body_colors(fixed, colors)
        size = ground_size if ground_size is not None else max(4.0, 4.0 * float(np.max(hi - lo)))
        centre = (lo + hi) / 2
        self.meshes: list[Any] = []
        for i, d in enumerate(shapes):
            if d is None:
                self.meshes.append(None)
                continue
            if d["kind"] == "Plane":
                v, t = _ground(d, quat_matrix(quat[i]).T @ (centre - pos[i]), size)
            else:
                v, t = shape_mesh(d, detail)
            plane = d["kind"] == "Plane"
            handle = self.server.scene.add_mesh_simple(
                f"/bodies/{i}", v.astype(np.float32), t.astype(np.uint32), color=tuple(float(c) for c in rgb[i]),
                flat_shading=True, side="double" if plane or d["kind"] == "TriMesh" else "front",
                receive_shadow=not plane, position=pos[i], wxyz=_wxyz(quat[i]))
            handle.on_click(lambda _event, i=i: self._select(i))
            self.meshes.append(handle)
            if plane:
                self._grid(i, d, v, size)

    def _grid(self, i: int, d: Mapping[str, Any], quad: F64, size: float) -> None:
        """Grid lines on a ground plane (a child of its body node): metric depth cues, and
        the bodies' shadows (the large plane itself does not take them: three.js's shadow
        map over it shows bands)."""
        n = quat_matrix(d["orientation"]) @ np.asarray(d["normal"], float)
        n /= np.linalg.norm(n)
        axis = np.cross([0.0, 0.0, 1.0], n)
        q = np.array([*axis, 1.0 + n[2]]) if n[2] > -1 + 1e-9 else np.array([1.0, 0.0, 0.0, 0.0])
        q /= np.linalg.norm(q)
        cell = float(10 ** np.floor(np.log10(max(size / 10, 1e-6))))  # 10 to 100 cells across
        self.server.scene.add_grid(
            f"/bodies/{i}/grid", size, size, plane="xy", cell_size=cell, section_size=10 * cell,
            shadow_opacity=0.3, position=quad.mean(axis=0) + 1e-4 * size * n, wxyz=_wxyz(q))

    # -------------------------------------------------------------------- GUI
    def _build_gui(self, playing: bool, speed: float, loop: bool) -> None:
        gui = self.server.gui
        self._play = gui.add_checkbox("Play", initial_value=playing)
        self._speed = gui.add_number("Speed (sim s / s)", initial_value=float(speed), min=1e-3, max=1e3, step=0.1)
        if self.recording is not None:
            last = max(len(self.recording) - 1, 1)
            self._slider = gui.add_slider("Frame", min=0, max=last, step=1, initial_value=0,
                                          disabled=len(self.recording) < 2)
            self._slider.on_update(lambda _e: self._slider_moved())
            self._loop = gui.add_checkbox("Loop", initial_value=loop)
        else:
            step = gui.add_button("Step")
            step.on_click(lambda _e: self.step(1))
        self._status = gui.add_markdown("")
        self._info = gui.add_markdown("Click a body to see it.")
        self._refresh_status()

    def _slider_moved(self) -> None:
        k = int(self._slider.value)
        if k != self.frame:
            self.show(k)

    def _select(self, i: int) -> None:
        self.selected = i
        self._refresh_info()

    def _refresh_status(self) -> None:
        if self.recording is not None:
            t = float(self.recording.times[self.frame]) if len(self.recording) else 0.0
            text = f"t = {t:.4f} s, frame {self.frame} of {len(self.recording)}"
        else:
            sps, rtf = self._rate
            text = (f"t = {self.world.time:.4f} s, {self.world.steps} steps; "
                    f"{sps:,.0f} steps/s, real-time factor {rtf:.2f}")
        if self._error:
            text += f"\n\n**Paused:** {self._error}"
        self._status.content = text

    def _refresh_info(self) -> None:
        i = self.selected
        if i is None:
            return
        pos, _, _ = self._pose(self.frame)
        names = self.world.bodies.names if self.world is not None else []
        name = (names[i] if i < len(names) else "") or f"body {i}"
        lines = [f"**{name}** (body {i})", f"position {np.round(pos[i], 4).tolist()} m"]
        if self.world is not None:
            lines.insert(1, f"mass {float(self.world.bodies.mass[i]):.4g} kg")
        if self.recording is None:
            lines.append(f"velocity {np.round(self.world.bodies.linear_velocity[i], 4).tolist()} m/s")
            lines.append(f"angular velocity {np.round(self.world.bodies.angular_velocity[i], 4).tolist()} rad/s")
        elif len(self.recording) > 1:
            # Velocity between the neighbouring frames (a difference quotient; not recorded).
            a, b = max(self.frame - 1, 0), min(self.frame + 1, len(self.recording) - 1)
            t = self.recording.times
            v = (self.recording.position[b, i] - self.recording.position[a, i]) / (t[b] - t[a])
            lines.append(f"velocity ≈ {np.round(v, 4).tolist()} m/s (between frames {a} and {b})")
        self._info.content = "\n\n".join(lines)

    # --------------------------------------------------------------- updating
    def _apply(self, pos: F64, quat: F64, parts: F64) -> None:
        # viser only sends a pose that differs from the last one beyond np.allclose
        # (relative 1e-5): a change below that is invisible anyway. One frame's updates
        # are applied together by the page (no half-moved frame).
        wxyz = _wxyz(quat)
        with self.server.atomic():
            for i, h in enumerate(self.meshes):
                if h is not None:
                    h.position = pos[i]
                    h.wxyz = wxyz[i]
            if self._points is not None:
                self._points.points = parts.astype(np.float32)

    def show(self, k: int) -> None:
        """Shows frame ``k`` of the recording (negative counts from the end)."""
        if self.recording is None:
            raise ValueError("show(k) needs a recording; a live world is moved by step(n)")
        n = len(self.recording)
        if not -n <= k < n:
            raise IndexError(f"frame {k} is out of range: the recording has {n} frames")
        with self._lock:
            self.frame = k % n
            self._clock = float(self.recording.times[self.frame] - self.recording.times[0])
            self._apply(*self._pose(self.frame))
            if int(self._slider.value) != self.frame:
                self._slider.value = self.frame
            self._refresh_status()
            self._refresh_info()

    def step(self, n: int = 1) -> None:
        """Steps a live world ``n`` times and shows the result (the viewer's loop does this
        while playing; stepping the world elsewhere meanwhile is not safe)."""
        if self.world is None or self.recording is not None:
            raise ValueError("step(n) needs a live world; a recording is moved by show(k)")
        from .. import SimulationError

        with self._lock:
            try:
                self.world.step(int(n))
            except SimulationError as e:
                self._error = str(e)
                self._play.value = False
            self._apply(*self._pose(0))
            self._refresh_status()
            self._refresh_info()

    def _tick(self, elapsed: float) -> None:
        if not self._play.value:
            return
        speed = float(self._speed.value)
        if self.recording is not None:
            times = self.recording.times
            span = float(times[-1] - times[0])
            clock = self._clock + elapsed * speed
            if clock > span:
                if not self._loop.value:
                    self._play.value = False
                    clock = span
                else:
                    clock = clock % span if span > 0 else 0.0
            k = int(np.clip(np.searchsorted(times - times[0], clock, side="right") - 1, 0, len(times) - 1))
            if k != self.frame:
                self.show(k)
            self._clock = clock
            return
        dt = self.world.dt
        self._debt += elapsed * speed
        want = int(self._debt / dt)
        if want == 0:
            return
        n = max(1, min(want, int(STEP_BUDGET / self._step_cost)))
        t0 = time.perf_counter()
        self.step(n)
        wall = max(time.perf_counter() - t0, 1e-9)
        self._step_cost = 0.8 * self._step_cost + 0.2 * wall / n
        self._debt = self._debt - want * dt if n == want else 0.0  # too slow: drop the backlog
        self._rate = (n / max(elapsed, wall), n * dt / max(elapsed, wall))

    def _run(self) -> None:
        last = time.perf_counter()
        while not self._stop.wait(TICK):
            now = time.perf_counter()
            try:
                self._tick(now - last)
            except Exception as e:  # noqa: BLE001  (a closed server or a bad value: stop, say why)
                self._error = f"{type(e).__name__}: {e}"
                return
            last = now

    def start(self) -> Viewer:
        """Runs the viewer loop in a background thread (``view(..., block=False)`` does this)."""
        if self._thread is None:
            self._thread = threading.Thread(target=self._run, name="rigidrs-view", daemon=True)
            self._thread.start()
        return self

    def wait(self) -> None:
        """Runs the viewer loop in this thread until Ctrl-C or ``close()``, then closes."""
        try:
            self._run()
        except KeyboardInterrupt:
            pass
        finally:
            self.close()
        if self._error:
            print(f"rigidrs viewer stopped: {self._error}", flush=True)

    def close(self) -> None:
        """Stops the loop and the server (idempotent)."""
        self._stop.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=5.0)
        if self.server is not None:
            self.server.stop()
            self.server = None

    def __enter__(self) -> Viewer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def view(source: Any, rec: Any = None, *, host: str = "127.0.0.1", port: int = 8080, block: bool = True,
         playing: bool = True, speed: float = 1.0, loop: bool = True, dt: float = 1.0 / 120.0,
         colors: Any = None, detail: int = 2, ground_size: float | None = None) -> Viewer:
    """Opens an interactive 3D view in the browser (``pip install "rigidrs[view]"``).

    ``source``: a World (stepped live by the viewer, or with ``rec`` a Recording of it
    played back), a Scene (built with time step ``dt``, s, default 1/120, and stepped
    live; with ``rec`` played back), or a Recording alone (no shapes are known then:
    each body is drawn as a small flat box, 0.05 × the bodies' spread).
    ``host`` (default ``127.0.0.1``; ``0.0.0.0`` to serve other machines) and ``port``
    (default 8080; the next free one is taken if busy, 0 for any: read ``.port``).
    ``block`` (default True): serve until Ctrl-C, then close; False: return the running
    :class:`Viewer` at once (its loop runs in a background thread; ``close()`` it).
    ``playing`` (default True) starts playing; ``speed`` simulated seconds per second of
    wall time (default 1; a live world steps as fast as that asks, or as it can);
    ``loop`` (default True) repeats a recording. ``colors``, ``detail`` (0..3) and
    ``ground_size`` (m) as in :func:`rigidrs.export_gltf`.
    Returns the :class:`Viewer` (closed already when ``block`` was True).
    """
    from .. import Recording, Scene, World

    if not (np.isfinite(speed) and speed > 0):
        raise ValueError(f"speed must be a positive number of simulated seconds per second, got {speed!r}")
    if detail not in (0, 1, 2, 3):
        raise ValueError(f"detail must be 0, 1, 2 or 3, got {detail!r}")
    if isinstance(source, Recording):
        if rec is not None:
            raise TypeError("view(recording) takes no second recording")
        world, rec, shapes = None, source, _axes_shapes(source)
    elif isinstance(source, Scene):
        world = source.build(dt=dt)
        shapes = world.shapes()
    elif isinstance(source, World):
        world, shapes = source, source.shapes()
    else:
        raise TypeError(f"view needs a rigidrs World, Scene or Recording, got {type(source).__name__}")
    if rec is not None:
        _check_recording(rec, world)
    _viser()
    v = Viewer(world, rec, shapes, host=host, port=port, playing=playing, speed=speed, loop=loop,
               colors=colors, detail=detail, ground_size=ground_size)
    if not block:
        return v.start()
    print(f"rigidrs viewer at {v.url} (Ctrl-C to stop)", flush=True)
    v.wait()
    return v


def _check_recording(rec: Any, world: Any) -> None:
    from .. import Recording

    if not isinstance(rec, Recording):
        raise TypeError(f"rec must be a rigidrs Recording or None, got {type(rec).__name__}")
    if len(rec) == 0:
        raise ValueError("the recording has no frames")
    if world is not None:
        n, m = len(world.bodies), len(world.particles)
        if rec.position.shape[1] != n or rec.particle_position.shape[1] != m:
            raise ValueError(f"the recording does not match the scene: {rec.position.shape[1]} bodies and "
                             f"{rec.particle_position.shape[1]} particles recorded, the scene has {n} and {m}")


def _axes_shapes(rec: Any) -> list[dict[str, Any] | None]:
    """Stand-in shapes for a recording viewed without its scene: a small box per body,
    sized 0.05 × the spread of the bodies over the recording (at least 1 cm)."""
    pos = rec.position
    spread = float(np.max(np.ptp(pos.reshape(-1, 3), axis=0))) if pos.size else 1.0
    h = max(0.05 * spread, 0.01)
    box = {"kind": "Box", "half_extents": np.array([h, h / 2, h / 4]), "position": np.zeros(3),
           "orientation": np.array([0.0, 0.0, 0.0, 1.0])}
    return [box] * pos.shape[1]
