"""MJCF in: small models written here, run by rigidrs and by MuJoCo itself.

References: the large-amplitude period of a physical pendulum 4 K(k²)/ω0 (SciPy's
``ellipk``, k = sin(θ0/2), ω0² = m g L / I_pivot with I_pivot from the sphere formula
2/5 m r² + m L², computed here, not read from either engine), free fall g t²/2, and
MuJoCo's own run of the same file (``mujoco`` is in the test extra)."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipk

import rigidrs as rr
from test_articulation import hermite_crossings

mujoco = pytest.importorskip("mujoco", reason="mujoco is in the test extra: pip install '.[test]'")

G, L, R, RHO = 9.81, 1.0, 0.05, 1000.0
THETA0 = 0.5

PENDULUM = f"""<mujoco model="pendulum">
  <option timestep="0.001" integrator="RK4" gravity="0 0 -{G}"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1" pos="0 0 -3"/>
    <body name="bob" pos="0 0 0">
      <joint name="swing" type="hinge" axis="0 1 0" pos="0 0 0" range="-120 120"/>
      <geom name="ball" type="sphere" size="{R}" pos="0 0 -{L}" density="{RHO}"/>
    </body>
  </worldbody>
</mujoco>
"""

FALLING = """<mujoco model="drop">
  <option timestep="0.002"/>
  <worldbody>
    <body name="box" pos="0 0 10">
      <freejoint name="free"/>
      <geom type="box" size="0.1 0.2 0.3" mass="2"/>
    </body>
  </worldbody>
</mujoco>
"""


def write(tmp_path: Path, text: str, name: str = "model.xml") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def crossings(t: np.ndarray, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Times where x falls through 0 (cubic Hermite between steps, error O(h⁴))."""
    return np.array(hermite_crossings(list(t), list(x), list(v)))


def exact_period() -> float:
    m = RHO * 4 / 3 * math.pi * R**3
    i_pivot = 0.4 * m * R**2 + m * L**2
    w0 = math.sqrt(m * G * L / i_pivot)
    return 4 * ellipk(math.sin(THETA0 / 2) ** 2) / w0, w0


def run_rigidrs(path: Path, dt: float, seconds: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    world = rr.Scene.from_mjcf(path).build(dt=dt)
    world.set_joint_positions([THETA0])
    t, q, v = [0.0], [THETA0], [0.0]
    for _ in range(round(seconds / dt)):
        world.step()
        t.append(world.time), q.append(world.joints.position[0]), v.append(world.joints.velocity[0])
    return np.array(t), np.array(q), np.array(v)


def run_mujoco(path: Path, seconds: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    data.qpos[0] = THETA0
    t, q, v = [0.0], [THETA0], [0.0]
    for _ in range(round(seconds / model.opt.timestep)):
        mujoco.mj_step(model, data)
        t.append(data.time), q.append(data.qpos[0]), v.append(data.qvel[0])
    return np.array(t), np.array(q), np.array(v)


def test_pendulum_matches_the_elliptic_period_and_mujoco(tmp_path: Path) -> None:
    path = write(tmp_path, PENDULUM)
    T, w0 = exact_period()
    dt, seconds = 1 / 240, 4 * T
    tr, qr, vr = run_rigidrs(path, dt, seconds)
    tm, qm, vm = run_mujoco(path, seconds)
    period_rr = np.diff(crossings(tr, qr, vr)).mean()
    period_mj = np.diff(crossings(tm, qm, vm)).mean()
    # Leapfrog (Störmer–Verlet) on a pendulum: period error (ω h)²/24 at small amplitude
    # (7.1e-6 here); MuJoCo's RK4 at 1 ms: O((ωh)⁴) ~ 1e-11. Bars: 3× the leapfrog
    # estimate (the amplitude adds a few per cent to the effective ω), 1e-8 for RK4.
    bar_rr = 3 * (w0 * dt) ** 2 / 24
    assert abs(period_rr / T - 1) < bar_rr, (period_rr, T)
    assert abs(period_mj / T - 1) < 1e-8, (period_mj, T)
    # Trajectories, MuJoCo's interpolated at rigidrs's steps: a relative period error e
    # shifts the phase by 2π e per period, so after 4 periods
    # |Δθ| ≤ θ0 · 2π · 4 · (e_rr + e_mj), with e at the bars above.
    qm_at = np.interp(tr, tm, qm)
    interp = (w0 * 1e-3) ** 2 / 8 * THETA0  # linear interpolation of MuJoCo's 1 ms samples
    bound = THETA0 * 2 * math.pi * 4 * (bar_rr + 1e-8) + interp
    assert np.max(np.abs(qr - qm_at)) < bound, (np.max(np.abs(qr - qm_at)), bound)


def test_inertia_and_mass_equal_mujocos_inference(tmp_path: Path) -> None:
    path = write(tmp_path, PENDULUM)
    scene = rr.Scene.from_mjcf(path)
    world = scene.build(dt=1 / 240)
    m = RHO * 4 / 3 * math.pi * R**3
    bob = world.bodies.names.index("bob")
    # Mass from the sphere's volume and density, the same formula MuJoCo applies.
    assert world.bodies.mass[bob] == pytest.approx(m, rel=1e-12)
    assert np.allclose(np.sort(world.bodies.inertia[bob]), [0.4 * m * R**2] * 3, rtol=1e-12)
    assert np.allclose(world.bodies.position[bob], [0, 0, -L], atol=1e-15)


def test_free_fall_matches_g_t2_and_mujoco(tmp_path: Path) -> None:
    path = write(tmp_path, FALLING)
    world = rr.Scene.from_mjcf(path).build(dt=0.002)
    world.step(500)
    t = world.time
    exact = 10 - G * t**2 / 2
    # Constant acceleration: the split integrator's drift-kick is exact to round-off.
    assert world.bodies.position[0, 2] == pytest.approx(exact, abs=1e-9)
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    for _ in range(500):
        mujoco.mj_step(model, data)
    # MuJoCo's semi-implicit Euler: z_n = z0 − g h² n(n+1)/2, ahead of g t²/2 by g h t / 2.
    lag = G * 0.002 * t / 2
    assert data.qpos[2] == pytest.approx(exact - lag, abs=1e-9)
    assert abs(world.bodies.position[0, 2] - data.qpos[2]) == pytest.approx(lag, abs=1e-9)


def test_actuators_become_drives_and_hold_a_pose(tmp_path: Path) -> None:
    text = PENDULUM.replace("</worldbody>", """</worldbody>
  <actuator><position name="servo" joint="swing" kp="40" kv="4"/></actuator>
  <sensor><jointpos name="angle" joint="swing"/></sensor>""")
    scene = rr.Scene.from_mjcf(write(tmp_path, text))
    mapped = [e for e in scene.import_report if e.element == "actuator"]
    assert mapped and mapped[0].action == "mapped" and "k = 40" in mapped[0].reason
    assert any(e.element == "sensor" and e.action == "dropped" for e in scene.import_report)
    world = scene.build(dt=1 / 240, sleep=False)  # asleep, it would stop short of balance
    world.joints.target[0] = 0.3
    world.step(2400)
    # Static balance k (target − q) = m g L sin q: solve for q and compare.
    m = RHO * 4 / 3 * math.pi * R**3
    q = brentq(lambda q: 40 * (0.3 - q) - m * G * L * math.sin(q), 0, 0.3)
    assert world.joints.position[0] == pytest.approx(q, abs=1e-6)


def test_report_lists_what_has_no_counterpart(tmp_path: Path) -> None:
    text = PENDULUM.replace('<geom name="ball"', '<geom name="look" type="ellipsoid" size="0.1 0.05 0.02" contype="0" conaffinity="0"/>\n      <geom name="ball"')
    text = text.replace("</worldbody>", "</worldbody>\n  <tendon><fixed name=\"t\"><joint joint=\"swing\" coef=\"1\"/></fixed></tendon>")
    scene = rr.Scene.from_mjcf(write(tmp_path, text))
    rep = scene.import_report
    visual = [e for e in rep if e.name == "look"]
    assert visual and visual[0].action == "dropped" and visual[0].line == 7
    assert any(e.element == "tendon" for e in rep.dropped())
    assert "tendon" in str(rep) and "look" in str(rep)


def test_bad_files_raise_naming_file_and_line(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="missing.xml"):
        rr.Scene.from_mjcf(tmp_path / "missing.xml")
    bad = write(tmp_path, PENDULUM.replace('type="hinge"', 'type="hinje"'), "bad.xml")
    with pytest.raises(rr.io.ModelError, match=r"bad\.xml.*hinje.*line 6"):
        rr.Scene.from_mjcf(bad)
    broken = write(tmp_path, PENDULUM.replace("</body>", ""), "broken.xml")
    with pytest.raises(rr.io.ModelError, match="broken.xml"):
        rr.Scene.from_mjcf(broken)


SLIDE = """<mujoco>
  <worldbody>
    <body name="cart" pos="0 0 1">
      <joint name="lift" type="slide" axis="0 0.6 0.8" ref="0.1"/>
      <geom type="box" size="0.1 0.1 0.1" mass="2"/>
    </body>
  </worldbody>
  <actuator><position name="p" joint="lift" kp="200" kv="40"/></actuator>
</mujoco>
"""


def test_slide_with_ref_and_servo_settles_where_mujoco_does(tmp_path: Path) -> None:
    path = write(tmp_path, SLIDE)
    world = rr.Scene.from_mjcf(path).build(dt=1 / 240, sleep=False)
    world.step(1200)
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    for _ in range(3000):
        mujoco.mj_step(model, data)
    # Balance along the slide: kp (ctrl − q) = m g · 0.8, ctrl 0, so q = −m g 0.8 / kp in
    # MuJoCo's coordinate; rigidrs reads q − ref. Both settled (ζ = 1, ωn = 10 rad/s, 5 s): to 1e-9.
    q = -2 * G * 0.8 / 200
    assert data.qpos[0] == pytest.approx(q, abs=1e-9)
    assert world.joints.position[0] == pytest.approx(q - 0.1, abs=1e-9)


SWING = """<mujoco>
  <option timestep="0.0002" integrator="RK4"/>
  <worldbody>
    <body name="bob" pos="0 0 0">
      {joints}
      <geom type="capsule" fromto="0 0 0 0.3 0.1 -0.8" size="0.04" density="800"/>
      <geom type="box" pos="0.3 0.1 -0.8" size="0.1 0.05 0.03" density="800"/>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize("joints", ['<joint name="jx" type="hinge" axis="1 0 0"/><joint name="jy" type="hinge" axis="0 1 0"/>',
                                    '<joint name="b" type="ball"/>'], ids=["two hinges in one body", "ball"])
def test_body_with_two_hinges_or_a_ball_swings_as_in_mujoco(tmp_path: Path, joints: str) -> None:
    """A capsule-and-box pendulum released off the vertical, on two hinges of one body (a
    chain through a frame of negligible mass here) or on a ball joint: the far end after 1 s
    against MuJoCo's RK4 at 0.2 ms (its own error ~1e-12 m). rigidrs's leapfrog is second
    order: the gap must fall ~4× per halving of dt, and at 1/480 s stay under 1e-5 m
    ((ω h)² ≈ 5e-5 of the 0.3 m swing, measured 1.7e-6)."""
    path = write(tmp_path, SWING.format(joints=joints))
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    for _ in range(5000):
        mujoco.mj_step(model, data)
    end = np.array([0.3, 0.1, -0.8])
    end_mj = data.xpos[1] + data.xmat[1].reshape(3, 3) @ end
    gaps = []
    for dt in (1 / 240, 1 / 480):
        world = rr.Scene.from_mjcf(path).build(dt=dt, sleep=False)
        b = world.bodies.names.index("bob")
        local = world.bodies.rotation[b].T @ (end - world.bodies.position[b])
        world.step(round(1.0 / dt))
        gaps.append(np.linalg.norm(world.bodies.position[b] + world.bodies.rotation[b] @ local - end_mj))
    assert 3.0 < gaps[0] / gaps[1] < 5.0, gaps
    assert gaps[1] < 1e-5, gaps
