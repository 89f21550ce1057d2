"""URDF in: small robots written here. References: the elliptic period of a physical
pendulum from the file's own mass and inertia (computed here), the file's inertia
tensors rotated by their ``rpy`` (computed here), and errors for bad files."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipk

import rigidrs as rr
from test_articulation import hermite_crossings

pytest.importorskip("yourdfpy", reason="yourdfpy is in the test extra: pip install '.[test]'")

G, L, M, IYY = 9.81, 0.8, 2.0, 0.03
THETA0 = 0.5


def pendulum(extra_link: str = "", extra_joint: str = "", rpy: str = "0 0 0",
             inertia: str = f'ixx="0.01" ixy="0" ixz="0" iyy="{IYY}" iyz="0" izz="0.02"') -> str:
    return f"""<?xml version="1.0"?>
<robot name="pendulum">
  <link name="world"/>
  <link name="base">
    <inertial><origin xyz="0 0 0"/><mass value="5"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>
  </link>
  <joint name="anchor" type="fixed"><parent link="world"/><child link="base"/><origin xyz="0 0 2"/></joint>
  <link name="arm">
    <inertial><origin xyz="0 0 -{L}" rpy="{rpy}"/><mass value="{M}"/><inertia {inertia}/></inertial>
    <visual><geometry><sphere radius="0.1"/></geometry></visual>
    <collision><origin xyz="0 0 -{L}"/><geometry><sphere radius="0.1"/></geometry></collision>
    <collision><origin xyz="0 0 -0.4"/><geometry><cylinder radius="0.02" length="0.8"/></geometry></collision>
  </link>
  <joint name="swing" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="50" velocity="3"/><dynamics damping="0" friction="0"/>
  </joint>
  {extra_link}
  {extra_joint}
  <transmission name="t1"><type>transmission_interface/SimpleTransmission</type></transmission>
  <gazebo reference="arm"><mu1>0.5</mu1></gazebo>
</robot>
"""


def write(tmp_path: Path, text: str, name: str = "robot.urdf") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def crossings(t: np.ndarray, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Times where x falls through 0 (cubic Hermite between steps, error O(h⁴))."""
    return np.array(hermite_crossings(list(t), list(x), list(v)))


def test_pendulum_has_the_analytic_period(tmp_path: Path) -> None:
    scene = rr.Scene.from_urdf(write(tmp_path, pendulum()))
    dt = 1 / 240
    world = scene.build(dt=dt)
    assert world.joints.names == ["swing"]
    world.set_joint_positions([THETA0])
    t, q, v = [0.0], [THETA0], [0.0]
    for _ in range(4 * 240):
        world.step()
        t.append(world.time), q.append(world.joints.position[0]), v.append(world.joints.velocity[0])
    # I about the pivot from the file: iyy + m L² (the link's inertial sits L below the joint).
    w0 = math.sqrt(M * G * L / (IYY + M * L**2))
    T = 4 * ellipk(math.sin(THETA0 / 2) ** 2) / w0
    period = np.diff(crossings(np.array(t), np.array(q), np.array(v))).mean()
    # Leapfrog's period error (ωh)²/24 (≈1e-5 here), 3× for the amplitude's effect.
    assert abs(period / T - 1) < 3 * (w0 * dt) ** 2 / 24, (period, T)


def test_inertia_tensor_equals_the_files(tmp_path: Path) -> None:
    rpy = (0.3, -0.2, 0.7)
    full = 'ixx="0.05" ixy="0.004" ixz="-0.003" iyy="0.04" iyz="0.002" izz="0.03"'
    scene = rr.Scene.from_urdf(write(tmp_path, pendulum(rpy=" ".join(map(str, rpy)), inertia=full)))
    world = scene.build(dt=1 / 240)
    arm = world.bodies.names.index("arm")
    tensor = np.array([[0.05, 0.004, -0.003], [0.004, 0.04, 0.002], [-0.003, 0.002, 0.03]])
    r, p, y = rpy  # URDF rpy: R = Rz(y) Ry(p) Rx(r)
    rx = np.array([[1, 0, 0], [0, math.cos(r), -math.sin(r)], [0, math.sin(r), math.cos(r)]])
    ry = np.array([[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]])
    rz = np.array([[math.cos(y), -math.sin(y), 0], [math.sin(y), math.cos(y), 0], [0, 0, 1]])
    rot = rz @ ry @ rx
    # Round-off of the principal decomposition and back: 1e-12 of the largest moment.
    assert np.allclose(world.bodies.inertia_world[arm], rot @ tensor @ rot.T, atol=1e-13)
    assert world.bodies.mass[arm] == M
    assert np.allclose(world.bodies.position[arm], [0, 0, 2 - L], atol=1e-15)


def test_report_and_merging(tmp_path: Path) -> None:
    tool = '<link name="tool"><inertial><origin xyz="0 0 -0.1"/><mass value="1"/><inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial></link>'
    weld = '<joint name="weld" type="fixed"><parent link="arm"/><child link="tool"/><origin xyz="0 0 -0.9"/></joint>'
    scene = rr.Scene.from_urdf(write(tmp_path, pendulum(tool, weld)))
    rep = scene.import_report
    kinds = {(e.element, e.action) for e in rep}
    assert {("transmission", "dropped"), ("gazebo", "dropped"), ("visual", "dropped"),
            ("joint.limit.velocity", "dropped"), ("joint", "mapped")} <= kinds
    assert [e.line for e in rep if e.element == "transmission"] == [20]
    world = scene.build(dt=1 / 240)
    # The tool merges into the arm: mass 2 + 1, centre of mass between them.
    arm = world.bodies.names.index("arm")
    assert world.bodies.names == ["world", "arm"]
    assert world.bodies.mass[arm] == pytest.approx(3.0, rel=1e-15)
    assert world.bodies.position[arm, 2] == pytest.approx(2 - (2 * L + 1 * 1.0) / 3, abs=1e-14)
    assert "transmission" in str(rep)


def test_drives_hold_the_pose_against_gravity(tmp_path: Path) -> None:
    k = 500.0
    scene = rr.Scene.from_urdf(write(tmp_path, pendulum()), drives=rr.Drive(stiffness=k, damping=20.0))
    assert any(e.element == "joint.limit.effort" for e in scene.import_report)
    world = scene.build(dt=1 / 240, sleep=False)  # asleep, it would stop short of balance
    world.joints.target[0] = 0.4
    world.step(480)
    # Static balance: k (target − q) = M g L sin q.
    q = brentq(lambda q: k * (0.4 - q) - M * G * L * math.sin(q), 0.0, 0.4)
    assert world.joints.position[0] == pytest.approx(q, abs=1e-5)


def test_floating_base_falls_freely(tmp_path: Path) -> None:
    text = pendulum().replace('<link name="world"/>', "").replace(
        '<joint name="anchor" type="fixed"><parent link="world"/><child link="base"/><origin xyz="0 0 2"/></joint>', "")
    world = rr.Scene.from_urdf(write(tmp_path, text), fixed_base=False).build(dt=1 / 240)
    z0 = world.bodies.position[:, 2].copy()
    world.step(240)
    # No contact, no drive: every link falls g t²/2 with the system's centre of mass.
    masses = world.bodies.mass
    com = (masses @ world.bodies.position[:, 2] - masses @ z0) / masses.sum()
    assert com == pytest.approx(-G / 2, abs=1e-9)


def test_meshes_through_package_paths(tmp_path: Path) -> None:
    trimesh = pytest.importorskip("trimesh")
    pkg = tmp_path / "share" / "my_robot"
    (pkg / "meshes").mkdir(parents=True)
    trimesh.creation.box((0.1, 0.2, 0.3)).export(pkg / "meshes" / "part.stl")
    text = pendulum().replace('<sphere radius="0.1"/></geometry></collision>',
                              '<mesh filename="package://my_robot/meshes/part.stl" scale="2 1 1"/></geometry></collision>')
    (pkg / "urdf").mkdir()
    path = write(pkg / "urdf", text)
    # Found from the directories around the file, and through package_map from elsewhere.
    for scene in (rr.Scene.from_urdf(path),
                  rr.Scene.from_urdf(write(tmp_path, text), package_map={"my_robot": str(pkg)})):
        parts = scene.shapes()[1]
        assert any(e.element == "collision.mesh" for e in scene.import_report.approximated())
        assert parts is not None
    with pytest.raises(rr.io.ModelError, match=r"mesh file not found.*nothing\.stl"):
        rr.Scene.from_urdf(write(tmp_path, text.replace("part.stl", "nothing.stl"), "b.urdf"),
                           package_map={"my_robot": str(pkg)})


def test_bad_files_raise_and_build_nothing(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="absent.urdf"):
        rr.Scene.from_urdf(tmp_path / "absent.urdf")
    with pytest.raises(rr.io.ModelError, match=r"broken\.urdf, line \d+: malformed XML"):
        rr.Scene.from_urdf(write(tmp_path, pendulum().replace("</link>", "</lnk>", 1), "broken.urdf"))
    missing = pendulum().replace('<child link="arm"/>', '<child link="hand"/>')
    with pytest.raises(rr.io.ModelError, match=r"line 15: <joint> 'swing'.*'hand' is not a <link>"):
        rr.Scene.from_urdf(write(tmp_path, missing, "missing.urdf"))
    loop = pendulum('<link name="b2"/>', '<joint name="back" type="revolute"><parent link="arm"/><child link="base"/>'
                    '<axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>')
    with pytest.raises(rr.io.ModelError, match=r"<joint> 'back'.*loop"):
        rr.Scene.from_urdf(write(tmp_path, loop, "loop.urdf"))


def test_report_travels_with_copies_and_pickles(tmp_path: Path) -> None:
    import copy
    import pickle

    scene = rr.Scene.from_urdf(write(tmp_path, pendulum()))
    n = len(scene.import_report)
    assert n > 0
    for other in (copy.copy(scene), copy.deepcopy(scene), pickle.loads(pickle.dumps(scene))):
        assert len(other.import_report) == n and str(other.import_report) == str(scene.import_report)
    hand_made = rr.Scene()
    assert len(hand_made.import_report) == 0 and "nothing" in str(hand_made.import_report)


def test_mass_properties_given_directly() -> None:
    mp = rr.MassProperties(2.0, (0.1, 0, 0), [[0.02, 0.001, 0], [0.001, 0.03, 0], [0, 0, 0.04]])
    assert mp.mass == 2.0 and np.allclose(mp.center_of_mass, [0.1, 0, 0])
    with pytest.raises(rr.RigidError, match="mass"):
        rr.MassProperties(-1.0, None, (1, 1, 1))
    with pytest.raises(rr.RigidError, match="triangle"):
        rr.MassProperties(1.0, None, (1, 1, 3))


SIBLINGS = """<robot name="siblings">
  <link name="base"/>
  <link name="left"><inertial><mass value="1"/><inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial>
    <collision><origin xyz="0.2 0 0"/><geometry><box size="0.4 0.1 0.1"/></geometry></collision></link>
  <link name="right"><inertial><mass value="1"/><inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial>
    <collision><origin xyz="0.2 0 0"/><geometry><box size="0.4 0.1 0.1"/></geometry></collision></link>
  <joint name="a" type="continuous"><parent link="base"/><child link="left"/><axis xyz="0 1 0"/></joint>
  <joint name="b" type="continuous"><parent link="base"/><child link="right"/><origin xyz="0 0.05 0"/><axis xyz="0 1 0"/></joint>
</robot>
"""


def test_self_collision_is_off_unless_asked(tmp_path: Path) -> None:
    # Two sibling links, not tied by a joint, whose boxes overlap by 0.05 m across y at build:
    # a contact between them exists only with self_collision=True.
    path = write(tmp_path, SIBLINGS, "siblings.urdf")
    pairs = []
    for self_collision in (False, True):
        world = rr.Scene.from_urdf(path, self_collision=self_collision).build(dt=1 / 240)
        world.step(1)
        c = world.contacts()
        pairs.append({tuple(sorted((int(a), int(b)))) for a, b in zip(c["body_a"], c["body_b"])})
    assert world.bodies.names == ["base", "left", "right"]
    assert (1, 2) not in pairs[0]
    assert (1, 2) in pairs[1]


def test_package_found_through_ros_package_path(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    trimesh = pytest.importorskip("trimesh")
    share = tmp_path / "ws" / "share"
    (share / "kit" / "meshes").mkdir(parents=True)
    trimesh.creation.icosphere(radius=0.1).export(share / "kit" / "meshes" / "ball.stl")
    text = pendulum().replace('<sphere radius="0.1"/></geometry></collision>',
                              '<mesh filename="package://kit/meshes/ball.stl"/></geometry></collision>')
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    path = write(elsewhere, text)
    with pytest.raises(rr.io.ModelError, match="mesh file not found"):
        rr.Scene.from_urdf(path)
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(share))
    assert rr.Scene.from_urdf(path).shapes()[1]["kind"] == "Compound"
