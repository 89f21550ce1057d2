#!/usr/bin/env python
"""Articulations side by side (a benchmark, not a test): rigidrs, MuJoCo and
Rapier on issue 14's scenes, at equal accuracy, timed by CPU time.

Scenes (no collisions anywhere):

* ``pendulums``: 1000 independent pendulums, each a ball (r = 5 cm, 1 kg) on a
  hinge 1 m below its own pivot, released at rest from 0.5 rad, 10 s. Accuracy:
  the relative error of the period against 4 K(k²)/ω0 (pendulum 0; all are
  equal), from Hermite-interpolated down-crossings of the swing angle.
* ``chain``: 100 links of 2 cm and 10 g (section 4 mm) on hinges, the first to
  the world, released horizontally, 2 s (the tip whips at ~1900 rad/s).
  Accuracy: the largest energy change over M g L / 2, and the largest joint gap.

Each engine runs at a list of time steps (and its integrator options); a
row prints CPU seconds per simulated second (one ``step`` call per step from
Python, as in the other peer scripts), steps/s, and the accuracy. Equal accuracy
means: for each peer, the cheapest of its runs that is at least as accurate as
rigidrs' default at dt = 1/60; the ratio is then the peer's CPU time per
simulated second over rigidrs' (> 1: rigidrs faster).

    python benches/peers/articulation.py --engine rigidrs|mujoco|rapier3d --scene pendulums|chain
    python benches/peers/articulation.py --all          # every engine and scene (needs the peers venv)

MuJoCo and Rapier run from the peers' environment (``/work/peers-venv``); this
script imports only the engine it is asked for.
"""
from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import time

import numpy as np
from scipy.optimize import brentq
from scipy.special import ellipk

G = 9.81
N_PEND, L_PEND, R_PEND, M_PEND, TH0 = 1000, 1.0, 0.05, 1.0, 0.5
N_CHAIN, LINK, LINK_MASS, THICK = 100, 0.02, 0.01, 0.004


def exact_period() -> float:
    i_pivot = 0.4 * M_PEND * R_PEND**2 + M_PEND * L_PEND**2
    return 4 * ellipk(math.sin(TH0 / 2) ** 2) * math.sqrt(i_pivot / (M_PEND * G * L_PEND))


def period_error(t: list[float], x: list[float], v: list[float]) -> float:
    cross = []
    for k in range(1, len(x)):
        if x[k - 1] > 0 >= x[k]:
            h = t[k] - t[k - 1]

            def p(s: float, k: int = k, h: float = h) -> float:
                return ((2 * s**3 - 3 * s**2 + 1) * x[k - 1] + (s**3 - 2 * s**2 + s) * h * v[k - 1]
                        + (-2 * s**3 + 3 * s**2) * x[k] + (s**3 - s**2) * h * v[k])

            cross.append(t[k - 1] + h * brentq(p, 0.0, 1.0, xtol=1e-15))
    return (cross[-1] - cross[0]) / (len(cross) - 1) / exact_period() - 1


def pivots() -> np.ndarray:
    side = math.ceil(math.sqrt(N_PEND))
    return np.array([[3.0 * (i % side), 3.0 * (i // side), 0.0] for i in range(N_PEND)])


def box_inertia() -> np.ndarray:
    return LINK_MASS / 12 * np.array([LINK**2 + THICK**2, LINK**2 + THICK**2, 2 * THICK**2])


# --- rigidrs -----------------------------------------------------------------------


def rigidrs_pendulums(dt: float, option: str):
    import rigidrs as rr
    scene = rr.Scene(gravity=(0, 0, -G))
    for p in pivots():
        b = scene.add_body(rr.Sphere(R_PEND), mass=M_PEND, position=p + (math.sin(TH0), 0, -math.cos(TH0)),
                           collision_mask=0)
        scene.add_joint("hinge", b, None, anchor=p, axis=(0, 1, 0))
    world = scene.build(dt=dt, articulation_integrator=option)
    world.profiling = False

    def angle():
        q = world.joints.position[0]
        return TH0 - q, -world.joints.velocity[0]

    return world.step, angle


def rigidrs_chain(dt: float, option: str):
    import rigidrs as rr
    scene = rr.Scene(gravity=(0, 0, -G))
    bodies = [scene.add_body(rr.Box((THICK / 2, THICK / 2, LINK / 2)), mass=LINK_MASS, collision_mask=0,
                             position=((k + 0.5) * LINK, 0, 0), orientation=(0, math.sin(math.pi / 4), 0, math.cos(math.pi / 4)))
              for k in range(N_CHAIN)]
    for k, b in enumerate(bodies):
        scene.add_joint("hinge", b, None if k == 0 else bodies[k - 1], anchor=(k * LINK, 0, 0), axis=(0, 1, 0),
                        solver="xpbd" if option.startswith("xpbd") else "auto")
    substeps = int(option.split(":")[1]) if ":" in option else None
    world = scene.build(dt=dt, articulation_integrator="leapfrog" if option.startswith("xpbd") else option,
                        substeps=substeps)
    world.profiling = False

    def state():
        p, r = world.bodies.position, world.bodies.rotation
        ends = p + r @ np.array([0, 0, LINK / 2])
        starts = p - r @ np.array([0, 0, LINK / 2])
        gap = max(np.linalg.norm(starts[0]), np.linalg.norm(starts[1:] - ends[:-1], axis=1).max())
        return world.kinetic_energy() + world.potential_energy(), gap

    return world.step, state


# --- MuJoCo ------------------------------------------------------------------------


def mujoco_model(xml: str, dt: float, option: str):
    import mujoco
    model = mujoco.MjModel.from_xml_string(xml)
    model.opt.timestep = dt
    model.opt.integrator = {"euler": mujoco.mjtIntegrator.mjINT_EULER, "rk4": mujoco.mjtIntegrator.mjINT_RK4,
                            "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
                            "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST}[option]
    model.opt.enableflags |= mujoco.mjtEnableBit.mjENBL_ENERGY
    data = mujoco.MjData(model)
    return mujoco, model, data


def mujoco_pendulums(dt: float, option: str):
    bodies = "".join(
        f'<body pos="{p[0]} {p[1]} {p[2]}"><joint type="hinge" axis="0 1 0" ref="0"/>'
        f'<geom type="sphere" size="{R_PEND}" mass="{M_PEND}" pos="0 0 {-L_PEND}" contype="0" conaffinity="0"/></body>'
        for p in pivots())
    xml = f'<mujoco><option gravity="0 0 {-G}"/><worldbody>{bodies}</worldbody></mujoco>'
    mj, model, data = mujoco_model(xml, dt, option)
    data.qpos[:] = -TH0  # rotation about +y by −θ0 puts the ball at +x
    mj.mj_forward(model, data)

    def angle():
        return -data.qpos[0], -data.qvel[0]

    return (lambda: mj.mj_step(model, data)), angle


def mujoco_chain(dt: float, option: str):
    i = box_inertia()
    link = (f'<joint type="hinge" axis="0 1 0" pos="0 0 0"/>'
            f'<inertial pos="{LINK / 2} 0 0" mass="{LINK_MASS}" diaginertia="{2 * THICK**2 * LINK_MASS / 12} {i[0]} {i[0]}"/>')
    xml = ""
    for k in reversed(range(N_CHAIN)):
        inner = xml
        pos = "0 0 0" if k == 0 else f"{LINK} 0 0"
        xml = f'<body pos="{pos}">{link}{inner}</body>'
    xml = f'<mujoco><option gravity="0 0 {-G}"/><worldbody>{xml}</worldbody></mujoco>'
    mj, model, data = mujoco_model(xml, dt, option)
    mj.mj_forward(model, data)

    def state():
        return float(data.energy[0] + data.energy[1]), 0.0  # reduced coordinates: no gap

    return (lambda: mj.mj_step(model, data)), state


# --- Rapier -----------------------------------------------------------------------


def rapier_world(dt: float):
    import rapier3d as r
    w = r.PhysicsWorld(gravity=(0, 0, -G))
    w.integration_parameters.dt = dt
    w.set_num_threads(1)
    return r, w


def rapier_pendulums(dt: float, option: str):
    r, w = rapier_world(dt)
    multibody = option == "multibody"
    handles = []
    for p in pivots():
        anchor = w.add_body(r.RigidBody.fixed().translation(p.tolist()))
        x = p + (math.sin(TH0), 0, -math.cos(TH0))
        col = r.Collider.ball(R_PEND).mass(M_PEND).collision_groups(r.InteractionGroups.none())
        b = w.add_body(r.RigidBody.dynamic().translation(x.tolist()).can_sleep(False), [col])
        joint = r.RevoluteJointBuilder((0, 1, 0)).local_anchor1((0, 0, 0)).local_anchor2(
            (-math.sin(TH0), 0, math.cos(TH0))).build()
        (w.multibody_joints if multibody else w.impulse_joints).insert(anchor, b, joint)
        handles.append((b, p))
    body0, p0 = handles[0]

    def angle():
        rb = w.rigid_bodies[body0]
        x, v = np.array(rb.translation.to_tuple()) - p0, np.array(rb.linvel.to_tuple())
        return math.atan2(x[0], -x[2]), (-x[2] * v[0] + x[0] * v[2]) / (x[0] ** 2 + x[2] ** 2)

    return w.step, angle


def rapier_chain(dt: float, option: str):
    r, w = rapier_world(dt)
    multibody = option == "multibody"
    prev = w.add_body(r.RigidBody.fixed())
    bodies = []
    for k in range(N_CHAIN):
        col = r.Collider.cuboid(LINK / 2, THICK / 2, THICK / 2).mass(LINK_MASS).collision_groups(r.InteractionGroups.none())
        b = w.add_body(r.RigidBody.dynamic().translation(((k + 0.5) * LINK, 0, 0)).can_sleep(False), [col])
        a1 = (0, 0, 0) if k == 0 else (LINK / 2, 0, 0)
        joint = r.RevoluteJointBuilder((0, 1, 0)).local_anchor1(a1).local_anchor2((-LINK / 2, 0, 0)).build()
        (w.multibody_joints if multibody else w.impulse_joints).insert(prev, b, joint)
        bodies.append(b)
        prev = b

    def state():
        rbs = [w.rigid_bodies[h] for h in bodies]
        e = sum(rb.kinetic_energy() + LINK_MASS * G * rb.translation.to_tuple()[2] for rb in rbs)
        ends, starts = [], []
        for rb in rbs:
            c = np.array(rb.translation.to_tuple())
            half = np.array(rb.rotation.transform_vector((LINK / 2, 0, 0)).to_tuple())
            ends.append(c + half)
            starts.append(c - half)
        gap = max(np.linalg.norm(starts[0]), max(np.linalg.norm(s - e) for s, e in zip(starts[1:], ends[:-1])))
        return e, gap

    return w.step, state


BUILDERS = {
    ("rigidrs", "pendulums"): rigidrs_pendulums, ("rigidrs", "chain"): rigidrs_chain,
    ("mujoco", "pendulums"): mujoco_pendulums, ("mujoco", "chain"): mujoco_chain,
    ("rapier3d", "pendulums"): rapier_pendulums, ("rapier3d", "chain"): rapier_chain,
}
RUNS = {
    ("rigidrs", "pendulums"): [("leapfrog", 1 / 60), ("rk4", 1 / 60)],
    ("rigidrs", "chain"): [("leapfrog", 1 / 60), ("rk4", 1 / 60), ("xpbd", 1 / 60)],
    ("mujoco", "pendulums"): [("euler", 1 / 60), ("rk4", 1 / 60)],
    ("mujoco", "chain"): [(o, dt) for o in ("euler", "rk4", "implicit") for dt in (1 / 60, 1 / 240, 1 / 960, 1 / 3840)],
    ("rapier3d", "pendulums"): [(o, dt) for o in ("impulse", "multibody") for dt in (1 / 60, 1 / 120, 1 / 240)],
    ("rapier3d", "chain"): [(o, dt) for o in ("impulse", "multibody") for dt in (1 / 60, 1 / 240, 1 / 960)],
}


def run(engine: str, scene: str, option: str, dt: float) -> dict:
    step, read = BUILDERS[(engine, scene)](dt, option)
    seconds = 10.0 if scene == "pendulums" else 2.0
    steps = int(round(seconds / dt))
    out = {"engine": engine, "scene": scene, "option": option, "dt": dt}
    if scene == "pendulums":
        t, x, v = [], [], []
        cpu = 0.0
        for k in range(steps):
            c0 = time.process_time()
            step()
            cpu += time.process_time() - c0
            a, w = read()
            t.append((k + 1) * dt)
            x.append(a)
            v.append(w)
        try:
            out["period_error"] = period_error(t, x, v)
        except (IndexError, ValueError):
            out["period_error"] = float("nan")
    else:
        e0, _ = read()
        worst_e, worst_gap, cpu = 0.0, 0.0, 0.0
        scale = N_CHAIN * LINK_MASS * G * N_CHAIN * LINK / 2
        for k in range(steps):
            c0 = time.process_time()
            try:
                step()
            except Exception:  # rigidrs raises when a world blows up
                worst_e = float("nan")
                break
            cpu += time.process_time() - c0
            if k % 6 == 5 or k == steps - 1:
                e, gap = read()
                worst_e = max(worst_e, abs(e - e0) / scale) if math.isfinite(e) else float("nan")
                worst_gap = max(worst_gap, gap)
                if not math.isfinite(worst_e):
                    break
        out["energy_error"] = worst_e
        out["gap"] = worst_gap
    out["cpu_per_sim_s"] = cpu / seconds
    out["steps_per_s"] = steps / cpu if cpu > 0 else float("nan")
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--engine", choices=["rigidrs", "mujoco", "rapier3d"])
    ap.add_argument("--scene", choices=["pendulums", "chain"])
    ap.add_argument("--all", action="store_true")
    ap.add_argument("--peers-python", default="/work/peers-venv/bin/python")
    a = ap.parse_args()
    if a.all:
        rows = []
        for engine in ["rigidrs", "mujoco", "rapier3d"]:
            for scene in ["pendulums", "chain"]:
                py = sys.executable if engine == "rigidrs" else a.peers_python
                res = subprocess.run([py, __file__, "--engine", engine, "--scene", scene], capture_output=True, text=True)
                for line in res.stdout.splitlines():
                    if line.startswith("{"):
                        rows.append(json.loads(line))
                        print(line, flush=True)
                if res.returncode:
                    print(res.stderr[-2000:], file=sys.stderr)
        print(json.dumps({"summary": summarize(rows)}))
        return
    for option, dt in RUNS[(a.engine, a.scene)]:
        print(json.dumps(run(a.engine, a.scene, option, dt)), flush=True)


def summarize(rows: list[dict]) -> dict:
    """Equal accuracy: each peer's cheapest run at least as accurate as rigidrs' default
    (within 10 %); when no run of a peer is, its most accurate run, marked so."""
    out = {}
    for scene, key in (("pendulums", "period_error"), ("chain", "energy_error")):
        base = next(r for r in rows if r["engine"] == "rigidrs" and r["scene"] == scene and r["option"] == "leapfrog")
        for engine in ("mujoco", "rapier3d"):
            mine = [r for r in rows if r["engine"] == engine and r["scene"] == scene and math.isfinite(r[key])]
            ok = [r for r in mine if abs(r[key]) <= abs(base[key]) * 1.1]
            if ok:
                best, note = min(ok, key=lambda r: r["cpu_per_sim_s"]), "as accurate"
            elif mine:
                best, note = min(mine, key=lambda r: abs(r[key])), "never as accurate: its most accurate run"
            else:
                out[f"{scene}/{engine}"] = "no finite run"
                continue
            out[f"{scene}/{engine}"] = {"run": f"{best['option']} dt={best['dt']:.5f}", key: best[key], "note": note,
                                        "ratio": best["cpu_per_sim_s"] / base["cpu_per_sim_s"]}
    return out


if __name__ == "__main__":
    main()
