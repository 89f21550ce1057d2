"""``rigidrs run``: a scene given as a Python file (or a scene file, when this rigidrs
has ``load_scene``) simulated for some seconds, with the outputs chosen by extension
read back and checked against the exact trajectory; bad arguments fail before any
simulation and leave no file."""
from __future__ import annotations

import sys
import textwrap
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import rigidrs as rr
from rigidrs import cli

G = 9.81
SCENE_PY = """
import rigidrs as rr

dt = 1 / 120

def make_scene():
    s = rr.Scene()
    s.add_body(rr.Sphere(0.1), density=1000.0, position=(0, 0, 10), linear_velocity=(3, 0, 5), name="ball")
    s.add_body(rr.Box((0.1, 0.2, 0.3)), density=500.0, position=(2, 0, 10), angular_velocity=(0, 0, 2))
    return s
"""


def scene_file(tmp_path: Path, text: str = SCENE_PY) -> Path:
    path = tmp_path / "scene.py"
    path.write_text(textwrap.dedent(text))
    return path


def exact_ball(t: np.ndarray) -> np.ndarray:
    """The thrown ball's parabola, (T, 3)."""
    return np.stack([3.0 * t, 0.0 * t, 10.0 + 5.0 * t - 0.5 * G * t * t], axis=1)


def test_python_file_writes_every_output(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    out.mkdir()
    files = {k: out / f"run.{k}" for k in ("npz", "gif", "glb", "usda", "png")}
    code = cli.main(["run", str(scene_file(tmp_path)), "--seconds", "0.5", "--every", "6",
                     "--record", str(files["npz"]), "--video", str(files["gif"]), "--gltf", str(files["glb"]),
                     "--usd", str(files["usda"]), "-o", str(files["png"]), "--no-progress"])
    assert code == 0
    printed = capsys.readouterr().out
    assert "2 bodies" in printed and "60 steps of 0.00833333 s" in printed and "steps/s" in printed
    for path in files.values():
        assert path.is_file() and f"wrote {path}" in printed
    assert sorted(p.name for p in out.iterdir()) == sorted(p.name for p in files.values())  # no temporaries
    rec = rr.Recording.load(files["npz"])
    # The file's dt (1/120 s) and --every 6: 11 frames at 20 per second.
    np.testing.assert_allclose(rec.times, np.arange(11) * 6 / 120, rtol=0, atol=1e-15)
    # Gravity alone: the default (Strang) integrator follows the parabola to rounding
    # (60 steps of a few ulps of 10 m: < 1e-12 m).
    np.testing.assert_allclose(rec.position[:, 0], exact_ball(rec.times), rtol=0, atol=1e-12)
    # Energy is conserved in free flight; the printed change is at rounding level.
    change = float(printed.split("change ")[1].split(" J")[0])
    assert abs(change) < 1e-9


def test_dt_and_default_every(tmp_path: Path) -> None:
    npz = tmp_path / "run.npz"
    assert cli.main(["run", str(scene_file(tmp_path)), "--seconds", "0.25", "--dt", "0.005",
                     "--record", str(npz), "--no-progress"]) == 0
    rec = rr.Recording.load(npz)
    # --dt overrides the file; default every: round(1 / (60 dt)) = 3 steps per frame.
    assert rec.every == 3 and len(rec) == 50 // 3 + 1
    np.testing.assert_allclose(np.diff(rec.times), 0.015, rtol=1e-12)


def test_view_plays_the_recording(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    seen: dict[str, Any] = {}

    def fake_view(world: Any, rec: Any, **kw: Any) -> None:  # the real one blocks until Ctrl-C
        seen.update(world=world, rec=rec, **kw)

    # rr.view (the function) shadows the subpackage's name in rigidrs; patch the subpackage.
    monkeypatch.setattr(sys.modules["rigidrs.view"], "view", fake_view)
    assert cli.main(["run", str(scene_file(tmp_path)), "--seconds", "0.1", "--view", "--port", "0",
                     "--no-progress"]) == 0
    # 12 steps of 1/120 s recorded at 60 frames per second: every 2nd step, 7 frames.
    assert seen["port"] == 0 and len(seen["rec"]) == 7 and seen["world"].steps == 12


@pytest.mark.parametrize("args,message", [
    (["--record", "run.mp4"], "--record run.mp4: the file name must end in .npz"),
    (["-o", "run.obj"], "unknown output format '.obj'"),
    (["-o", "missing/run.npz"], "does not exist"),
    (["--seconds", "-1"], "--seconds must be a non-negative number"),
    (["--every", "0"], "--every must be a positive number"),
])
def test_bad_arguments(tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch,
                       args: list[str], message: str) -> None:
    path = scene_file(tmp_path)
    monkeypatch.chdir(tmp_path)
    assert cli.main(["run", str(path), *args, "--no-progress"]) == 2
    assert message in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.py"]


@pytest.mark.parametrize("text,message", [
    ("x = 1\n", "defines neither `scene`"),
    ("scene = 42\n", "must be a rigidrs Scene or World, got int"),
    ("raise RuntimeError('boom')\n", "running it raised RuntimeError: boom"),
])
def test_bad_scene_files(tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str, message: str) -> None:
    assert cli.main(["run", str(scene_file(tmp_path, text)), "--no-progress"]) == 2
    assert message in capsys.readouterr().err
    assert cli.main(["run", str(tmp_path / "nope.py")]) == 2
    assert "no such scene file" in capsys.readouterr().err


def test_failing_step_keeps_what_was_recorded(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    text = """
    import rigidrs as rr
    scene = rr.Scene(gravity=(0, 0, 0))
    scene.add_body(rr.Sphere(0.1), density=1000.0, linear_velocity=(1e308, 0, 0))
    """
    npz = tmp_path / "run.npz"
    # x = 1e308 t overflows to inf at t = 1.797 s, step 216 (dt = 1/120 s).
    code = cli.main(["run", str(scene_file(tmp_path, text)), "--seconds", "3", "--record", str(npz),
                     "--every", "1", "--no-progress"])
    assert code == 1
    err = capsys.readouterr().err
    assert "stopped" in err and "body 0" in err
    rec = rr.Recording.load(npz)
    assert len(rec) == int(np.floor(np.finfo(float).max / 1e308 * 120)) + 1  # the finite steps and the start
    assert np.all(np.isfinite(rec.position))


def test_scene_file_form(tmp_path: Path) -> None:
    if getattr(rr, "load_scene", None) is None:
        pytest.skip("rigidrs.load_scene is not in this build (scene files come with the io branch)")
    ns: dict[str, Any] = {}
    exec(SCENE_PY, ns)
    scene = ns["make_scene"]()
    toml = tmp_path / "scene.toml"
    scene.save(toml)
    npz = tmp_path / "run.npz"
    assert cli.main(["run", str(toml), "--seconds", "0.5", "--dt", str(1 / 120), "--every", "6",
                     "--record", str(npz), "--no-progress"]) == 0
    rec = rr.Recording.load(npz)
    np.testing.assert_allclose(rec.position[:, 0], exact_ball(rec.times), rtol=0, atol=1e-12)
    # The same scene from the Python file gives the same bits.
    ref = tmp_path / "ref.npz"
    assert cli.main(["run", str(scene_file(tmp_path)), "--seconds", "0.5", "--every", "6",
                     "--record", str(ref), "--no-progress"]) == 0
    np.testing.assert_array_equal(rec.position, rr.Recording.load(ref).position)
    np.testing.assert_array_equal(rec.orientation, rr.Recording.load(ref).orientation)


def test_energies_and_contacts_go_into_the_recording_file(tmp_path: Path) -> None:
    from rigidrs.view.extras import Extras

    npz = tmp_path / "run.npz"
    assert cli.main(["run", str(scene_file(tmp_path)), "--seconds", "0.5", "--every", "6", "--record", str(npz),
                     "--energies", "--contacts", "--no-progress"]) == 0
    rec, ex = rr.Recording.load(npz), Extras.load(npz)
    np.testing.assert_array_equal(ex.steps, rec.steps)
    t = ex.times
    m_ball = 1000.0 * 4 / 3 * np.pi * 0.1**3
    m_box, iz_box = 500.0 * 0.2 * 0.4 * 0.6, 500.0 * 0.2 * 0.4 * 0.6 / 3 * (0.1**2 + 0.2**2)
    # Both in free flight (the box spins about its z axis, a principal axis, at 2 rad/s):
    # the velocities are exact under gravity, so is the kinetic energy, to rounding.
    exact = 0.5 * m_ball * (9.0 + (5.0 - G * t) ** 2) + 0.5 * m_box * (G * t) ** 2 + 0.5 * iz_box * 4.0
    np.testing.assert_allclose(ex.kinetic, exact, rtol=1e-12)
    assert np.ptp(ex.kinetic + ex.potential) < 1e-9 * ex.kinetic[0]
    assert ex.contact_start.tolist() == [0] * (len(rec) + 1)  # nothing touches


def test_view_command(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    seen: dict[str, Any] = {}

    def fake_view(world: Any, rec: Any, **kw: Any) -> None:  # the real one blocks until Ctrl-C
        seen.update(world=world, rec=rec, **kw)

    monkeypatch.setattr(sys.modules["rigidrs.view.viewer"], "view", fake_view)
    path = scene_file(tmp_path)
    npz = tmp_path / "run.npz"
    assert cli.main(["run", str(path), "--seconds", "0.1", "--record", str(npz), "--no-progress"]) == 0
    assert cli.main(["view", str(path), str(npz), "--port", "0", "--paused"]) == 0
    assert len(seen["rec"]) == 7 and seen["world"].steps == 0 and seen["playing"] is False
    assert cli.main(["view", str(path), "--speed", "0.5"]) == 0
    assert seen["rec"] is None and seen["speed"] == 0.5
    assert cli.main(["view", str(path), str(tmp_path / "missing.npz")]) == 2
    assert "missing.npz" in capsys.readouterr().err
