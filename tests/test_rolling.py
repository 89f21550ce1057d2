"""Rolling on a rounded surface: a cylinder or a capsule lying on the ground, and
an articulated cart on cylinder wheels.

A rigid body rolling on a flat floor without slipping keeps its height (its axis
stays a radius above the floor), its speed and its energy: nothing but the
contact, which does no work, acts across gravity. Down an incline of angle θ it
accelerates at ``a = g sin θ / (1 + I / (m r²))`` (I about the rolling axis).

A contact point on a rounded surface is where the surfaces meet, not a material
point: as a cylinder rolls, the point of it touching the floor changes. Followed
as a material point through the substeps of a step, it rose ``r (1 − cos ω h)``
a substep; at dt = 1/60 a cylinder or capsule of radius 0.1 m rolling at 1 m/s
(10 rad/s) sank 0.78 mm into the floor and bounced off it at 0.1 m/s, at 3 m/s
3.3 mm (the regression these tests guard; a ball was already exact).

Bars: the body rests at the rest depth (1 µm, see README "Contacts"), so its
height stays within 2 µm of ``r``; no vertical speed beyond round-off (1e-9 m/s);
energy kept to 1e-9 and speed to 1e-5 (no rolling resistance in the model; resting
1 µm deep, a body rolls on a radius 1e-5 shorter). On the
incline, the velocity after 1 s: constant acceleration, which the substeps'
kick-then-drift gives exactly in the velocity, so within 1e-4 of ``a t``.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rigidrs as rr
from test_mesh_floor_friction import floor as mesh_floor

G = 9.81
R = 0.1
DT = 1.0 / 60.0
# Local z (a cylinder's and a capsule's axis) turned onto world y: lying down.
LYING = (math.sin(math.pi / 4), 0.0, 0.0, math.cos(math.pi / 4))
SHAPES = {
    "cylinder": lambda: rr.Cylinder(radius=R, half_height=0.2),
    "capsule": lambda: rr.Capsule(radius=R, half_height=0.2),
}


def lying(shape, *, normal=(0.0, 0.0, 1.0), v=0.0, spin=None, friction=0.5):
    """A body of ``shape`` lying on a plane through the origin with ``normal``
    (tilted about y), rolling at ``v`` along +x on the slope (spin ``v / R`` unless
    given); returns the world, the body, the normal and that direction."""
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(normal=normal, offset=0.0), fixed=True, friction=friction)
    n = np.asarray(normal, float)
    ahead = np.array([n[2], 0.0, -n[0]])  # along the slope, toward +x
    w = v / R if spin is None else spin
    body = scene.add_body(SHAPES[shape](), density=1000.0, position=tuple(n * R), orientation=LYING,
                          linear_velocity=tuple(ahead * v), angular_velocity=(0.0, w, 0.0), friction=friction)
    return scene.build(dt=DT, sleep=False), body, n, ahead


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("v,spin", [(1.0, None), (3.0, None), (0.0, 10.0)], ids=["roll 1 m/s", "roll 3 m/s", "spin in place"])
def test_a_cylinder_or_capsule_rolling_on_the_ground_does_not_sink(shape, v, spin):
    world, body, _, _ = lying(shape, v=v, spin=spin, friction=0.0 if spin else 0.5)
    e0 = world.kinetic_energy()
    low = high = R
    vz = 0.0
    for _ in range(180):
        world.step(1)
        z = float(world.bodies.position[body, 2])
        low, high = min(low, z), max(high, z)
        vz = max(vz, abs(float(world.bodies.linear_velocity[body, 2])))
    assert R - low <= 2e-6, f"sank {1e3 * (R - low):.3f} mm"
    assert high - R <= 2e-6
    assert vz <= 1e-9
    assert abs(world.kinetic_energy() / e0 - 1) <= 1e-9
    # Resting 1 µm deep, it rolls on a radius shorter by 1e-5 of itself: the
    # linear speed settles within that of v0 (measured 1.7e-6 of it).
    assert abs(float(world.bodies.linear_velocity[body, 0]) - v) <= 1e-5 * v + 1e-12


@pytest.mark.parametrize("shape", SHAPES)
def test_a_cylinder_or_capsule_rolls_down_an_incline_at_the_rolling_acceleration(shape):
    theta = math.radians(20.0)
    # The plane rises toward +x: downhill is -ahead.
    world, body, n, ahead = lying(shape, normal=(-math.sin(theta), 0.0, math.cos(theta)), friction=0.8)
    # Moment of inertia about the rolling axis (local z, lying along world y).
    i_axis = float(world.bodies.inertia_world[body][1, 1])
    m = float(world.bodies.mass[body])
    a = G * math.sin(theta) / (1 + i_axis / (m * R**2))
    world.step(60)
    v = world.bodies.linear_velocity[body]
    assert abs(float(-v @ ahead) / (a * 1.0) - 1) <= 1e-4
    assert abs(float(v @ n)) <= 1e-9  # rolling on the slope, not off or into it
    # Rolling without slipping: the contact point is at rest, but for the body's
    # 1 µm rest depth (its centre is a radius less 1 µm above the slope).
    w = world.bodies.angular_velocity[body]
    assert np.linalg.norm(v + np.cross(w, -n * R)) <= 2e-6 * np.linalg.norm(w)


@pytest.mark.parametrize("wheel", ["cylinder", "sphere"])
def test_an_articulated_cart_rolls_on_its_wheels_without_sinking_or_braking(wheel):
    # A chassis on four wheels hinged to it (an articulation in reduced
    # coordinates, the default for a tree of joints), rolling at 1 m/s. The
    # wheels' contacts act on the articulation at their points; with a
    # cylinder's read as material points they acted where the wheel had turned
    # to: its axles sank 5.9 mm, bounced at 0.16 m/s and the cart slowed to
    # 0.61 m/s in 3 s. Bars: axles at the rest depth (2 µm), no rolling
    # resistance in the model (speed within 1e-4, measured 1e-5), vertical
    # speeds far below the defect's (1e-5 m/s, measured 8e-7).
    v = 1.0
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True)
    chassis = scene.add_body(rr.Box((0.3, 0.15, 0.03)), density=300.0, position=(0.0, 0.0, R), linear_velocity=(v, 0.0, 0.0))
    wheels = []
    for x in (-0.25, 0.25):
        for y in (-0.25, 0.25):
            shape = rr.Cylinder(radius=R, half_height=0.03) if wheel == "cylinder" else rr.Sphere(R)
            body = scene.add_body(shape, density=500.0, position=(x, y, R), orientation=LYING,
                                  linear_velocity=(v, 0.0, 0.0), angular_velocity=(0.0, v / R, 0.0))
            scene.add_joint("hinge", chassis, body, anchor=(x, y, R), axis=(0.0, 1.0, 0.0))
            wheels.append(body)
    world = scene.build(dt=DT, sleep=False)
    assert "articulation" in world.stages
    low, vz = R, 0.0
    for _ in range(180):
        world.step(1)
        low = min(low, float(np.min(world.bodies.position[wheels, 2])))
        vz = max(vz, float(np.max(np.abs(world.bodies.linear_velocity[wheels, 2]))))
    assert R - low <= 2e-6, f"axles sank {1e3 * (R - low):.3f} mm"
    assert vz <= 1e-5
    assert abs(float(world.bodies.linear_velocity[chassis, 0]) - v) <= 1e-4 * v


def floor(scene, kind):
    """A fixed floor with its top at z = 0: a box, or a mesh of 200 triangles."""
    if kind == "box":
        scene.add_body(rr.Box((5.0, 5.0, 0.5)), fixed=True, position=(0.0, 0.0, -0.5))
    else:
        scene.add_body(mesh_floor(10), fixed=True)


@pytest.mark.parametrize("kind", ["box", "mesh"])
@pytest.mark.parametrize("shape", SHAPES)
def test_a_cylinder_or_capsule_rolling_on_a_box_or_a_mesh_does_not_sink(shape, kind):
    # On a box the contact has a third point under the axis (a face's point
    # for each corner it lacks); read as material points, the cylinder's sank
    # 1.5 mm at 20 rad/s and bounced at 0.12 m/s, on the box and on the mesh.
    # Bars: the rest depth (2 µm); over the mesh's seams speed and energy
    # within 1e-4 (measured 5e-6 and 3e-6).
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    floor(scene, kind)
    body = scene.add_body(SHAPES[shape](), density=1000.0, position=(0.03, 0.07, R), orientation=LYING,
                          linear_velocity=(2.0, 0.0, 0.0), angular_velocity=(0.0, 20.0, 0.0))
    world = scene.build(dt=DT, sleep=False)
    e0, low = world.kinetic_energy(), R
    for _ in range(120):
        world.step(1)
        low = min(low, float(world.bodies.position[body, 2]))
    assert R - low <= 2e-6, f"sank {1e3 * (R - low):.3f} mm"
    assert abs(world.kinetic_energy() / e0 - 1) <= 1e-4
    assert abs(float(world.bodies.linear_velocity[body, 0]) - 2.0) <= 2e-4


@pytest.mark.parametrize("kind", ["box", "mesh", "log"])
@pytest.mark.parametrize("shape", SHAPES)
def test_slow_rolling_at_240_hz_keeps_its_energy(shape, kind):
    # parry keeps a manifold's points while they have moved less than 1 mm,
    # turning them with the body: rolling at 0.05 m/s at 240 Hz (0.2 mm a
    # step) the points rose off the box, the body fell to them and bounced on
    # the manifold computed again, gaining speed: kinetic energy ×3.5 (capsule)
    # and ×6.8 (cylinder) in 2 s, ×1.07 for the capsule at 60 Hz. Same bars as
    # on the box above (rest depth, speed and energy to 1e-4). The log is a
    # fixed cylinder of radius 0.1 m lying across the body's path.
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    if kind == "log":
        along_x = (0.0, math.sin(math.pi / 4), 0.0, math.cos(math.pi / 4))
        scene.add_body(rr.Cylinder(radius=0.1, half_height=2.0), fixed=True, position=(0.0, 0.0, -0.1), orientation=along_x)
    else:
        floor(scene, kind)
    v = 0.05
    body = scene.add_body(SHAPES[shape](), density=1000.0, position=(0.03, 0.0, R), orientation=LYING,
                          linear_velocity=(v, 0.0, 0.0), angular_velocity=(0.0, v / R, 0.0))
    world = scene.build(dt=1 / 240, sleep=False)
    e0, low = world.kinetic_energy(), R
    for _ in range(480):
        world.step(1)
        low = min(low, float(world.bodies.position[body, 2]))
    assert R - low <= 2e-6, f"sank {1e3 * (R - low):.3f} mm"
    assert abs(world.kinetic_energy() / e0 - 1) <= 1e-4, f"kinetic energy x{world.kinetic_energy() / e0:.6f}"
    assert abs(float(world.bodies.linear_velocity[body, 0]) - v) <= v * 1e-4


@pytest.mark.parametrize("spin", [10.0, 30.0])
def test_a_cone_spinning_on_its_side_keeps_its_rim_on_the_ground(spin):
    # A cone lying on its side touches at its apex (a corner: a material
    # point) and at its rim (round). Spun about its own axis without friction
    # it turns in place (a principal axis, no torque). Read as a material point,
    # its rim point rose through the substeps and the cone sank 0.50 mm at
    # 10 rad/s and 2.1 mm at 30 rad/s (its rim 0.73 and 3.1 mm deep). Bar: the
    # rest depth (2 µm).
    r, half = 0.1, 0.15
    alpha = math.atan(r / (2 * half))
    tilt = math.pi / 2 + alpha  # local z (the axis) turned to lie along a generator
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True, friction=0.0)
    body = scene.add_body(rr.Cone(radius=r, half_height=half), density=1000.0, position=(0.0, 0.0, 0.2),
                          orientation=(0.0, math.sin(tilt / 2), 0.0, math.cos(tilt / 2)), friction=0.0)
    world = scene.build(dt=DT, sleep=False)
    world.step(240)  # dropped 2 cm, settled on its side
    z0 = float(world.bodies.position[body, 2])
    world.bodies.angular_velocity[body] = tuple(spin * world.bodies.rotation[body][:, 2])
    low = z0
    for _ in range(120):
        world.step(1)
        low = min(low, float(world.bodies.position[body, 2]))
    assert z0 - low <= 2e-6, f"sank {1e3 * (z0 - low):.3f} mm"
    assert float(np.max(world.contacts()["depth"])) <= 2e-6


@pytest.mark.parametrize("tilt", [0.3, 1.0])
def test_a_disk_spinning_on_a_tilted_rim_keeps_its_rim_at_the_rest_depth(tilt):
    # Euler's disk at 30 rad/s, frictionless. Its nearest rim point rolls
    # around the rim onto rim that lies lower: held at zero normal velocity,
    # the rim went 1.42 mm deep in 0.1 s tilted 57° and 0.55 mm tilted 17°
    # (7.1 and 8.2 mm read as material points); with the curve found once a
    # step, not before each substep's velocity pass, 29 and 23 µm. Bar: the
    # rest depth (2 µm).
    r, half = 0.2, 0.02
    axis = np.array([0.0, -math.sin(tilt), math.cos(tilt)])
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True, friction=0.0)
    scene.add_body(rr.Cylinder(radius=r, half_height=half), density=1000.0,
                   position=(0.0, 0.0, r * math.sin(tilt) + half * math.cos(tilt)),
                   orientation=(math.sin(tilt / 2), 0.0, 0.0, math.cos(tilt / 2)),
                   angular_velocity=tuple(30.0 * axis), friction=0.0)
    world = scene.build(dt=DT, sleep=False)
    deepest = 0.0
    for _ in range(6):
        world.step(1)
        deepest = max(deepest, float(np.max(world.contacts()["depth"])))
    assert deepest <= 2e-6, f"rim {1e3 * deepest:.3f} mm deep"


def wobbling_disk(spin, friction):
    """Euler's disk: a disk (r 0.2 m, 4 cm thick) on its rim tilted 57°, spun
    about its axis at ``spin``; returns the world, the disk and its shape."""
    r, half, tilt = 0.2, 0.02, 1.0
    axis = np.array([0.0, -math.sin(tilt), math.cos(tilt)])
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True, friction=friction)
    disk = scene.add_body(rr.Cylinder(radius=r, half_height=half), density=1000.0,
                          position=(0.0, 0.0, r * math.sin(tilt) + half * math.cos(tilt)),
                          orientation=(math.sin(tilt / 2), 0.0, 0.0, math.cos(tilt / 2)),
                          angular_velocity=tuple(spin * axis), friction=friction)
    return scene.build(dt=DT, sleep=False), disk, (r, half)


def rim_depth(world, disk, r, half):
    """How far (m) the disk's lowest point is below the floor: its centre's
    height less the half thickness and the radius, each along the vertical."""
    a = world.bodies.rotation[disk][:, 2]
    low = float(world.bodies.position[disk, 2]) - half * abs(a[2]) - r * math.sqrt(max(0.0, 1.0 - a[2] ** 2))
    return -low


@pytest.mark.parametrize("friction", [0.0, 0.5])
@pytest.mark.parametrize("spin", [5.0, 10.0, 30.0])
def test_a_disk_wobbling_on_its_rim_stays_within_the_slop(spin, friction):
    # The nearest rim point rolls around the rim as the disk wobbles, onto rim
    # that lies lower: each substep the rim sank by the separation's curvature
    # while the pass held its rate at zero, and the soft push-out undid it at
    # 9 /s. Over 2 s at the defaults the rim went 10.4 / 6.7 / 2.3 mm deep
    # without friction at 5 / 10 / 30 rad/s, 0.7 / 10.4 / 12.3 mm with it:
    # beyond the 5 mm slop. Now 0.027 / 0.011 / 0.003 mm and 0.16 / 0.044 /
    # 0.058 mm.
    # Bar: the slop, the depth a contact is allowed at rest.
    world, disk, (r, half) = wobbling_disk(spin, friction)
    deepest = 0.0
    for _ in range(120):
        world.step(1)
        deepest = max(deepest, rim_depth(world, disk, r, half))
    assert deepest <= 0.005, f"rim {1e3 * deepest:.2f} mm deep"


@pytest.mark.parametrize("spin", [10.0, 30.0])
def test_friction_on_a_wobbling_disk_neither_sinks_nor_lifts_its_rim(spin):
    # With μ = 0.5 the rim point rolls: friction turns the disk within the
    # pass, and the rim's curve over the substep (asked for at the turn the
    # normal found) changed under it. Over 2 s the rim sank 0.94 / 1.69 mm at
    # 10 / 30 rad/s and chattered, lifting off by 0.11 / 0.06 mm; with the
    # normal solved again after its friction (impulse.rs, close_gaps) 0.044 /
    # 0.058 mm deep and 4 / 2 µm off. Bars: a rolling point does no work, so
    # friction should not drive the rim in: 0.1 mm, a fiftieth of the slop
    # and a tenth of what it sank; a disk held down by gravity stays on the
    # floor: 10 µm, five rest depths.
    world, disk, (r, half) = wobbling_disk(spin, 0.5)
    depths = []
    for _ in range(120):
        world.step(1)
        depths.append(rim_depth(world, disk, r, half))
    assert max(depths) <= 1e-4, f"rim {1e3 * max(depths):.3f} mm deep"
    assert -min(depths) <= 1e-5, f"rim {1e3 * -min(depths):.3f} mm off the floor"


def test_a_frictionless_disk_wobbling_on_its_rim_keeps_its_energy():
    # No friction: the floor's force is normal and does no work at a point
    # that does not sink. Spun at 30 rad/s the disk wobbles on its rim for 2 s
    # without landing flat. Losing 3.0e-3 of its energy (the rim sinking
    # 2.3 mm, the push-out's work taken back) it now keeps it within 2.2e-4.
    # Bar: 1e-3, a third of what the sinking cost.
    world, disk, (r, half) = wobbling_disk(30.0, 0.0)
    energy = lambda: world.kinetic_energy() + world.potential_energy()
    e0 = energy()
    world.step(120)
    assert abs(rim_depth(world, disk, r, half)) <= 0.005
    assert abs(energy() / e0 - 1.0) <= 1e-3, f"energy {energy() / e0 - 1:+.2e}"
