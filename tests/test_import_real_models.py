"""Real models nobody here wrote, from PyPI: robots of ``example-robot-data`` (URDF with
meshes) and models of ``dm-control``'s suite (MJCF). Each loads, is held by position
drives under gravity, and sags by what its own weight asks: the static deflection of
joint j is Q_j / k, with Q_j the generalized gravity force at the file's pose, computed
here from the file (URDF: link masses and frames composed here; MJCF: MuJoCo's own
``qfrc_bias``), not by rigidrs. Both packages are in the test extra."""
from __future__ import annotations

import importlib.metadata
import importlib.util
from pathlib import Path

import numpy as np
import pytest

import rigidrs as rr

G = 9.81


def robots_dir() -> Path:
    try:
        dist = importlib.metadata.distribution("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        pytest.skip("example-robot-data is not installed (it is in the test extra: pip install '.[test]')")
    d = Path(str(dist.locate_file("cmeel.prefix/share/example-robot-data/robots")))
    if not d.is_dir():
        pytest.skip(f"example-robot-data installed without its robots directory ({d})")
    return d


def suite_file(name: str) -> Path:
    spec = importlib.util.find_spec("dm_control")
    if spec is None or not spec.submodule_search_locations:
        pytest.skip("dm-control is not installed (it is in the test extra: pip install '.[test]')")
    return Path(list(spec.submodule_search_locations)[0]) / "suite" / name


def home(robot: object) -> dict[str, float]:
    """The pose a robot is held in: 0, or the nearest limit where 0 is outside them
    (the panda's 4th joint has limits [-3.07, -0.07])."""
    out = {}
    for j in robot.joints:  # type: ignore[attr-defined]
        if j.type in ("revolute", "prismatic") and j.limit is not None and j.limit.lower is not None:
            out[j.name] = float(np.clip(0.0, j.limit.lower, j.limit.upper))
        elif j.type in ("revolute", "continuous", "prismatic"):
            out[j.name] = 0.0
    return out


def urdf_gravity_forces(path: Path) -> tuple[dict[str, float], dict[str, float]]:
    """Q_j = n_j · Σ_{links below j} (c_i − a_j) × m_i g for hinges (m_i g · n_j for slides),
    at the home pose, from the URDF's own numbers (yourdfpy's forward kinematics), and
    that pose."""
    yourdfpy = pytest.importorskip("yourdfpy")
    urdf = yourdfpy.URDF.load(str(path), build_scene_graph=True, load_meshes=False)
    robot = urdf.robot
    cfg = home(robot)
    urdf.update_cfg(cfg)
    links = {l.name: l for l in robot.links}

    def frame(name: str) -> np.ndarray:
        return np.asarray(urdf.get_transform(name, urdf.base_link))

    def below(name: str) -> list[str]:
        return [name] + [n for j in robot.joints if j.parent == name for n in below(j.child)]

    g = np.array([0, 0, -G])
    out = {}
    for j in robot.joints:
        if j.type not in ("revolute", "continuous", "prismatic"):
            continue
        t = frame(j.child)
        n, a = t[:3, :3] @ np.asarray(j.axis, float), t[:3, 3]
        q = 0.0
        for name in below(j.child):
            ine = links[name].inertial
            if ine is None or not ine.mass:
                continue
            c = (frame(name) @ (np.eye(4) if ine.origin is None else ine.origin))[:3, 3]
            q += n @ (ine.mass * g) if j.type == "prismatic" else n @ np.cross(c - a, ine.mass * g)
        out[j.name] = q
    return out, cfg


def hold(scene: rr.Scene, seconds: float, dt: float, pose: dict[str, float] | None = None) -> tuple[rr.World, np.ndarray]:
    """Poses the model (joint name -> q), targets that pose, steps; the joints' change."""
    world = scene.build(dt=dt, sleep=False)  # asleep, it would stop short of balance
    if pose:
        q = np.array([pose.get(n, np.nan) for n in world.joints.names])
        world.set_joint_positions(q)
        world.joints.target[:] = np.where(np.isnan(q), world.joints.target, q)
    q0 = np.array(world.joints.position)
    world.step(round(seconds / dt))
    return world, np.array(world.joints.position) - q0


def limit_room(path: Path, names: list[str], pose: dict[str, float]) -> tuple[np.ndarray, np.ndarray]:
    """How far each joint may move from the pose before a limit (inf: none)."""
    yourdfpy = pytest.importorskip("yourdfpy")
    joints = {j.name: j for j in yourdfpy.URDF.load(str(path), build_scene_graph=False, load_meshes=False).robot.joints}
    lo, hi = np.full(len(names), -np.inf), np.full(len(names), np.inf)
    for i, n in enumerate(names):
        lim = joints[n].limit
        if joints[n].type in ("revolute", "prismatic") and lim is not None and lim.lower is not None \
                and lim.upper - lim.lower < 2 * np.pi:
            lo[i], hi[i] = lim.lower - pose[n], lim.upper - pose[n]
    return lo, hi


# (file under robots/, stiffness N·m/rad, mass-lever scale for the coupling bar)
ARMS_AND_LEGS = [("ur_description/urdf/ur5_robot.urdf", 2e4),
                 ("panda_description/urdf/panda.urdf", 2e4),
                 ("solo_description/robots/solo12.urdf", 200.0),
                 ("anymal_b_simple_description/robots/anymal.urdf", 2e3)]


@pytest.mark.parametrize("file,k", ARMS_AND_LEGS, ids=[f.split("/")[0] for f, _ in ARMS_AND_LEGS])
def test_robot_hangs_held_by_drives(file: str, k: float) -> None:
    path = robots_dir() / file
    scene = rr.Scene.from_urdf(path, drives=rr.Drive(stiffness=k, damping=0.05 * k))
    assert len(scene.import_report) > 0
    expected, pose = urdf_gravity_forces(path)
    world, dq = hold(scene, 1.0, 1 / 240, pose)
    names = world.joints.names
    q_pred = np.array([expected[n] / k if n in expected else 0.0 for n in names])
    # A joint held at a limit (the panda's 4th) cannot sag past it.
    q_pred = np.clip(q_pred, *limit_room(path, names, pose))
    moving = np.isfinite(dq)
    # Linear statics: q = Q(q)/k with Q(q) = Q(0) + O(M g ℓ |q|): the deflections move the
    # loads by a fraction M g ℓ / k of themselves (< 10 % for these stiffnesses), and the
    # damped drives (ζ ≥ 0.5 for links of ≥ 0.01 kg m²) settle within 1 s to 1e-4 of the
    # step. Bar: 10 % of the largest predicted deflection plus 1e-5 rad.
    bar = 0.1 * np.abs(q_pred[moving]).max() + 1e-5
    err = np.abs(dq[moving] - q_pred[moving])
    assert err.max() < bar, dict(zip(np.array(names)[moving], np.round(err, 6)))
    assert np.abs(q_pred).max() > 1e-4  # the robots do carry weight at their zero pose


def mjcf_gravity_forces(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """MuJoCo's generalized gravity force −qfrc_bias at qpos0, qvel 0, per hinge/slide joint
    (its qpos address), and the joint indices."""
    mujoco = pytest.importorskip("mujoco")
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    joints = [j for j in range(model.njnt) if model.jnt_type[j] in (2, 3)]
    return np.array([-data.qfrc_bias[model.jnt_dofadr[j]] for j in joints]), np.array(joints)


@pytest.mark.parametrize("name,k", [("acrobot.xml", 1e3), ("cartpole.xml", 1e3)])
def test_suite_model_held_by_drives(name: str, k: float) -> None:
    path = suite_file(name)
    scene = rr.Scene.from_mjcf(path, drives=rr.Drive(stiffness=k, damping=0.1 * k))
    world, dq = hold(scene, 1.0, 1 / 240)
    q_force, _ = mjcf_gravity_forces(path)
    q_pred = q_force / k
    bar = 0.1 * np.abs(q_pred).max() + 1e-5
    assert np.abs(dq - q_pred).max() < bar, (dq, q_pred)


def foot_gap(path: Path) -> float:
    """Height of the model's lowest point above the floor at qpos0 (capsules and spheres),
    from MuJoCo's geometry."""
    mujoco = pytest.importorskip("mujoco")
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    low = np.inf
    for g in range(model.ngeom):
        if model.geom_bodyid[g] == 0:
            continue
        c, r = data.geom_xpos[g], model.geom_size[g][0]
        half = abs(data.geom_xmat[g].reshape(3, 3)[2, 2] * model.geom_size[g][1]) if model.geom_type[g] == 3 else 0.0
        low = min(low, c[2] - half - r)
    return low


def test_humanoid_lands_and_stands_held_by_drives() -> None:
    path = suite_file("humanoid.xml")
    k = 3e3
    scene = rr.Scene.from_mjcf(path, drives=rr.Drive(stiffness=k, damping=0.05 * k))
    motors = [e for e in scene.import_report if e.element == "actuator" and e.action == "dropped"]
    assert len(motors) == 21  # its motors have no drive counterpart, and are listed
    world = scene.build(dt=1 / 240, sleep=False)
    torso = world.bodies.names.index("torso")
    z0 = world.bodies.position[torso, 2]
    q0 = np.array(world.joints.position)
    world.step(120)
    z_half = world.bodies.position[torso, 2]
    world.step(120)
    dq = np.array(world.joints.position) - q0
    mass = world.bodies.mass[np.isfinite(world.bodies.mass)].sum()
    # Standing on its feet, a joint carries at most the whole weight at a lever of the
    # body's height (1.5 m): |Δq| ≤ M g 1.5 / k (0.2 rad here; measured 0.004).
    assert np.nanmax(np.abs(dq)) < mass * G * 1.5 / k
    # It falls by the gap under its feet (0.214 m in the file) and stays up: the torso's
    # height within the contact slop (5 mm) plus the legs' sag (knee ~ M g 0.2 / k = 27 mm
    # of a 0.4 m shin at most), and still over the last half second.
    z = world.bodies.position[torso, 2]
    assert abs((z0 - z) - foot_gap(path)) < 0.005 + mass * G * 0.2 / k * 0.4
    assert abs(z - z_half) < 1e-3


def test_arm_joint_follows_the_second_order_step_response() -> None:
    """UR5's vertical shoulder_pan joint, the rest held stiff: a step of its target is the
    closed-form response of J q̈ + c q̇ + k q = k·step, with J the arm's inertia about the
    pan axis summed here from the bodies' masses and inertias (the joint sees no gravity).
    The drive is implicit (backward Euler on the control), first order in ωn·dt:
    README's bar, max error ≤ ωn·dt of the step (measured 0.62 ωn·dt), and halving dt
    about halves it."""
    path = robots_dir() / "ur_description/urdf/ur5_robot.urdf"
    k, zeta, step = 300.0, 0.3, 0.5
    errors = []
    for dt in (1 / 240, 1 / 960):
        probe = rr.Scene.from_urdf(path).build(dt=dt)
        moving = np.isfinite(probe.bodies.mass)
        m, p = probe.bodies.mass[moving], probe.bodies.position[moving]
        J = float(np.sum(probe.bodies.inertia_world[moving][:, 2, 2] + m * (p[:, 0] ** 2 + p[:, 1] ** 2)))
        c = 2 * zeta * np.sqrt(k * J)
        scene = rr.Scene.from_urdf(path, drives={"shoulder_pan_joint": rr.Drive(stiffness=k, damping=c),
                                                 "*": rr.Drive(stiffness=1e6, damping=2e4)})
        world = scene.build(dt=dt, sleep=False)
        pan = world.joints.names.index("shoulder_pan_joint")
        world.joints.target[pan] = step
        wn = np.sqrt(k / J)
        wd = wn * np.sqrt(1 - zeta**2)
        err = 0.0
        for _ in range(round(1.5 / dt)):
            world.step()
            t = world.time
            ref = step * (1 - np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta * wn / wd * np.sin(wd * t)))
            err = max(err, abs(world.joints.position[pan] - ref))
        assert err / step < wn * dt, (dt, err / step, wn * dt)
        errors.append(err)
    assert 3.0 < errors[0] / errors[1] < 5.0  # first order: 4× smaller for a 4× smaller step


def test_legged_robot_stands_on_the_ground() -> None:
    """solo12 with a floating base, dropped 0.1 m (from its lowest link's centre) onto a
    plane, legs held by drives: after 1.5 s its feet carry its weight (the contacts' normal
    impulses sum to M g dt), it is at rest, level, and each leg joint has sagged by at most
    a quarter of the weight at the leg's reach (0.35 m) over k."""
    path = robots_dir() / "solo_description/robots/solo12.urdf"
    k = 200.0
    scene = rr.Scene.from_urdf(path, fixed_base=False, drives=rr.Drive(stiffness=k, damping=0.05 * k))
    low = float(np.min(scene.build(dt=1 / 240).bodies.position[:, 2]))
    scene.add_body(rr.Plane(offset=low - 0.1), fixed=True, friction=0.8)
    dt = 1 / 240
    world = scene.build(dt=dt, sleep=False)
    q0 = np.array(world.joints.position)
    base0 = world.bodies.orientation[0].copy()
    world.step(360)
    mass = world.bodies.mass[np.isfinite(world.bodies.mass)].sum()
    support = world.contacts()["normal_impulse"].sum() / (mass * G * dt)
    assert support == pytest.approx(1.0, abs=0.01)
    assert np.abs(world.bodies.linear_velocity[:-1]).max() < 1e-2
    turn = 2 * np.arccos(min(1.0, abs(float(base0 @ world.bodies.orientation[0]))))
    assert turn < 1e-2
    assert np.abs(np.array(world.joints.position) - q0).max() < mass * G / 4 * 0.35 / k
