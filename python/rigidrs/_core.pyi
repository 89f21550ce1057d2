"""Typed interface of the compiled core. SI units; quaternions (x, y, z, w)."""
import os
from os import PathLike
from typing import Any, Mapping, Sequence, TypeAlias, final

import numpy as np
import numpy.typing as npt
from numpy.typing import ArrayLike
from typing_extensions import disjoint_base

_F64: TypeAlias = npt.NDArray[np.float64]

__all__ = [
    "ARTICULATION_INTEGRATORS",
    "Batch",
    "BatchBodies",
    "Bodies",
    "Box",
    "Capsule",
    "Compound",
    "Cone",
    "ConvexHull",
    "Cylinder",
    "Drive",
    "INTEGRATORS",
    "Joints",
    "MassProperties",
    "Particles",
    "Plane",
    "Recording",
    "RigidError",
    "Scene",
    "Shape",
    "ShapeError",
    "SimulationError",
    "Snapshot",
    "Sphere",
    "StateError",
    "TriMesh",
    "World",
    "__version__",
    "load",
    "mass_properties",
    "polar_decomposition",
]

__version__: str
INTEGRATORS: dict[str, int]
"""Integrator names accepted by ``Scene.build(integrator=...)`` -> nominal order."""
ARTICULATION_INTEGRATORS: dict[str, int]
"""Names accepted by ``Scene.build(articulation_integrator=...)`` -> nominal order:
``"leapfrog"`` (2, default), ``"euler"`` (1), ``"rk4"`` (4)."""

class RigidError(ValueError):
    """Invalid input; the message names the body or field."""

class ShapeError(RigidError):
    """A degenerate shape: no volume, an open mesh, too few points."""

class StateError(RigidError):
    """A world's state, written through a view, is invalid at the next step."""

class SimulationError(StateError, RuntimeError):
    """A step diverged (a body or particle position, velocity or orientation not finite
    after it) or failed inside (an internal error). The message names the body or
    particle, the stage and the time; the world is as it was before that step (time
    included) and can step on. A ``StateError`` (what a blow-up raised before) and a
    ``RuntimeError``."""

@disjoint_base
class Shape:
    """Base class of every shape."""

    def volume(self) -> float:
        """Volume (m³); raises for a Plane."""
    def mass_properties(self, density: float) -> MassProperties:
        """Mass properties for a uniform ``density`` (kg/m³), in this shape's frame."""

@final
class Sphere(Shape):
    """A ball of ``radius`` (m)."""

    def __new__(cls, radius: float) -> Sphere: ...
    @property
    def radius(self) -> float: ...

@final
class Box(Shape):
    """A box with ``half_extents`` (3,) along local x, y, z (m)."""

    def __new__(cls, half_extents: ArrayLike) -> Box: ...
    @property
    def half_extents(self) -> tuple[float, float, float]: ...

@final
class Capsule(Shape):
    """A capsule along local z: a segment of length 2·half_height (m) swept by radius (m)."""

    def __new__(cls, radius: float, half_height: float) -> Capsule: ...
    @property
    def radius(self) -> float: ...
    @property
    def half_height(self) -> float: ...

@final
class Cylinder(Shape):
    """A solid cylinder along local z: radius (m), length 2·half_height (m)."""

    def __new__(cls, radius: float, half_height: float) -> Cylinder: ...
    @property
    def radius(self) -> float: ...
    @property
    def half_height(self) -> float: ...

@final
class Cone(Shape):
    """A solid cone along local z: base of radius (m) at z = −half_height, apex at +half_height (m)."""

    def __new__(cls, radius: float, half_height: float) -> Cone: ...
    @property
    def radius(self) -> float: ...
    @property
    def half_height(self) -> float: ...

@final
class ConvexHull(Shape):
    """The convex hull of ``points`` (N, 3) (m): at least 4 points spanning a volume."""

    def __new__(cls, points: ArrayLike) -> ConvexHull: ...
    @classmethod
    def from_file(cls, path: str | PathLike[str], scale: float = 1.0) -> ConvexHull:
        """The convex hull of the vertices of an STL, OBJ, PLY, OFF or GLB/glTF file
        (needs ``rigidrs[io]``), times ``scale`` (m per file unit, default 1). A flat
        mesh is a ``ShapeError``; errors name the file."""

@final
class TriMesh(Shape):
    """A triangle mesh: ``vertices`` (V, 3) (m), ``triangles`` (T, 3) vertex indices,
    counter-clockwise seen from outside. Closed to carry mass. A mesh collides only on
    the side its triangles run counter-clockwise from: an open one (a terrain, a bowl)
    must face the bodies (``Scene.build`` warns of a dynamic body that starts behind a
    fixed or kinematic mesh; ``triangles[:, ::-1]`` turns a mesh round)."""

    def __new__(cls, vertices: ArrayLike, triangles: ArrayLike) -> TriMesh: ...
    @classmethod
    def from_file(cls, path: str | PathLike[str], scale: float = 1.0, fix: bool = False) -> TriMesh:
        """A mesh from an STL, OBJ, PLY, OFF or GLB/glTF file (needs ``rigidrs[io]``;
        a file of several meshes is flattened with their transforms), vertices times
        ``scale`` (m per file unit, default 1). ``fix=True`` repairs winding, normals
        and holes with trimesh first (default False). A dynamic body needs it closed
        and outward-oriented; else use ``ConvexHull.from_file`` or ``Compound.from_file``."""

@final
class Plane(Shape):
    """The half-space ``normal · x <= offset`` (normal (3,), offset in m); fixed bodies only."""

    def __new__(cls, normal: ArrayLike | None = None, offset: float = 0.0) -> Plane: ...

@final
class Compound(Shape):
    """A union of convex parts: ``parts`` is a sequence of ``(shape, position)`` or
    ``(shape, position, orientation)`` in this shape's frame (m; x, y, z, w). Parts
    may not be meshes, planes or compounds."""

    def __new__(cls, parts: Any) -> Compound: ...
    @classmethod
    def from_file(
        cls,
        path: str | PathLike[str],
        scale: float = 1.0,
        decompose: str = "coacd",
        threshold: float = 0.05,
        max_parts: int = -1,
    ) -> Compound:
        """Convex parts of a (non-convex) mesh file, for a dynamic body (needs
        ``rigidrs[io]``): ``decompose="coacd"`` (CoACD convex decomposition; ``threshold``
        concavity allowed per part, default 0.05; ``max_parts``, default -1: no limit)
        or ``"hull"`` (one part, the convex hull). ``scale`` as in ``TriMesh.from_file``."""

@final
class MassProperties:
    """Mass, centre of mass and inertia of a body, and their principal form."""

    def __new__(cls, mass: float, center_of_mass: ArrayLike | None = None, inertia: ArrayLike | None = None) -> MassProperties:
        """Given directly: ``mass`` (kg), ``center_of_mass`` (3,) (m, default the origin),
        ``inertia`` (3,) principal moments or (3, 3) tensor about the centre of mass
        (kg·m², required). Raises ``RigidError`` for a non-positive mass, a non-finite
        centre, or an inertia that is not symmetric positive definite."""

    @property
    def mass(self) -> float:
        """Mass (kg)."""
    @property
    def center_of_mass(self) -> _F64:
        """(3,) centre of mass in the source frame (m)."""
    @property
    def inertia(self) -> _F64:
        """(3, 3) inertia about the centre of mass, source-frame axes (kg·m²)."""
    @property
    def principal_moments(self) -> _F64:
        """(3,) principal moments (kg·m²)."""
    @property
    def principal_axes(self) -> _F64:
        """(3, 3) rotation whose column k is the axis of principal moment k."""
    @property
    def principal_orientation(self) -> _F64:
        """(4,) the principal axes as a quaternion (x, y, z, w)."""

def mass_properties(points: ArrayLike, volumes: ArrayLike, densities: ArrayLike) -> MassProperties:
    """Mass properties of a body of varying density from samples: ``points`` (N, 3) (m),
    ``volumes`` (N,) or scalar (m³), ``densities`` (N,) or scalar (kg/m³).
    Point quadrature of m = ∫ρ, c = ∫ρx/m, I0 = ∫ρ(rᵀr·Id − r rᵀ)."""

def polar_decomposition(
    m: ArrayLike, method: str = "svd", *, initial: ArrayLike | None = None
) -> tuple[_F64, _F64]:
    """Polar decomposition ``M = R S`` of one matrix (3, 3) or a batch (N, 3, 3).

    ``R`` is the proper rotation nearest to ``M`` (det +1, orthonormal to ~1e-15;
    for an inverted ``M``, det < 0, the reflection goes to the smallest singular
    value), ``S = Rᵀ M`` (symmetric; positive semi-definite when det M ≥ 0).
    ``method``: ``"svd"`` (one-sided Jacobi SVD, default), ``"higham"`` (scaled Newton
    iteration; SVD for singular input) or ``"muller"`` (Müller et al. 2016, iterative).
    ``initial``: warm start of ``"muller"``, a rotation matrix (3, 3) for all or
    (N, 3, 3), e.g. the previous ``R``; default identity. Returns arrays shaped as ``M``.
    Raises ``RigidError`` (a ``ValueError``) for a non-finite entry, naming ``M[k]``."""

@final
class Drive:
    """A joint drive for ``Scene.add_joint(drive=...)``.

    ``mode``: ``"position"`` (force ``stiffness·(target − q) − damping·q̇``) or
    ``"velocity"`` (force ``damping·(target − q̇)``; stiffness must be 0).
    ``target``: hinge angle (rad) or prismatic slide (m) for position drives,
    their rates (rad/s, m/s) for velocity drives, default 0; for a spherical joint
    a quaternion (x, y, z, w) of body a relative to its build pose (position) or an
    angular velocity (3,) in a's frame (rad/s, velocity). ``stiffness`` N·m/rad or
    N/m, ``damping`` N·m·s/rad or N·s/m (default 0 each), ``max_force`` N·m or N
    (default inf: no limit). Solved implicitly: stable at any stiffness."""

    def __new__(
        cls,
        mode: str = "position",
        target: ArrayLike | None = None,
        stiffness: float = 0.0,
        damping: float = 0.0,
        max_force: float = ...,
    ) -> Drive: ...
    @property
    def mode(self) -> str: ...
    @property
    def target(self) -> list[float]: ...
    @property
    def stiffness(self) -> float: ...
    @property
    def damping(self) -> float: ...
    @property
    def max_force(self) -> float: ...

@final
class Scene:
    """A description of what to simulate. ``gravity`` (3,) m/s², default (0, 0, −9.81)."""

    def __new__(cls, gravity: ArrayLike | None = None) -> Scene: ...
    @property
    def gravity(self) -> tuple[float, float, float]: ...
    def __len__(self) -> int: ...
    def __copy__(self) -> Scene:
        """An independent copy; so are ``copy.deepcopy`` and ``pickle`` round trips."""
    def __deepcopy__(self, memo: Any) -> Scene: ...
    def __reduce__(self) -> tuple[Any, tuple[bytes], Any]: ...
    def __setstate__(self, state: Any) -> None: ...
    @property
    def import_report(self) -> Any:
        """What the file an importer read had that was dropped or approximated, and why: a
        ``rigidrs.io.ImportReport`` (a list of ``ReportEntry``; ``print`` it to read it);
        empty for a scene built by hand. Writable (any object, or None)."""
    @import_report.setter
    def import_report(self, report: Any) -> None: ...
    @classmethod
    def from_urdf(
        cls,
        path: str | PathLike[str],
        package_map: Mapping[str, str | PathLike[str]] | None = None,
        fixed_base: bool = True,
        *,
        drives: Any = None,
        self_collision: bool = False,
        friction: float = 0.5,
        gravity: ArrayLike | None = None,
    ) -> Scene:
        """The robot of a URDF file (needs ``pip install 'rigidrs[io]'``); see
        ``rigidrs.io.urdf.from_urdf`` for the parameters."""
    @classmethod
    def from_mjcf(cls, path: str | PathLike[str], *, drives: Any = None, self_collision: bool = False) -> Scene:
        """The model of an MJCF file (needs ``pip install 'rigidrs[mjcf]'``); see
        ``rigidrs.io.mjcf.from_mjcf`` for the parameters."""
    def add_body(
        self,
        shape: Shape | None = None,
        *,
        density: float | None = None,
        mass: float | None = None,
        inertia: ArrayLike | None = None,
        mass_properties: MassProperties | None = None,
        position: ArrayLike | None = None,
        orientation: ArrayLike | None = None,
        linear_velocity: ArrayLike | None = None,
        angular_velocity: ArrayLike | None = None,
        fixed: bool = False,
        kinematic: bool = False,
        friction: float = 0.5,
        static_friction: float | None = None,
        restitution: float = 0.0,
        ccd: bool = False,
        collision_group: int = 1,
        collision_mask: int = 4294967295,
        name: str | None = None,
    ) -> int:
        """Adds a body; returns its index.

        Mass from exactly one of: ``shape`` + ``density`` (kg/m³); ``shape`` + ``mass``
        (kg, uniform density); ``mass`` + ``inertia`` ((3,) principal moments or (3, 3)
        tensor about the centre of mass, kg·m²); ``mass_properties``. ``position`` (m)
        and ``orientation`` (x, y, z, w) place the shape's (or the mass properties')
        frame, default origin and identity; the body's state is its centre of mass
        and principal frame. ``linear_velocity`` (m/s, of the centre of mass) and
        ``angular_velocity`` (rad/s), world frame, default 0. ``fixed`` bodies never move;
        ``kinematic`` bodies move with the velocities you give them and have infinite mass.

        Contact material of the shape: ``friction`` μk (default 0.5), ``static_friction``
        μs ≥ μk (default μk), ``restitution`` e in [0, 1] (default 0). Two materials
        combine by the geometric mean of friction and the maximum of restitution.
        ``ccd``: continuous collision detection for a fast body. Two shapes may touch iff
        ``group_a & mask_b`` and ``group_b & mask_a`` are both non-zero
        (``collision_group`` default 1, ``collision_mask`` default all bits).
        """
    def add_joint(
        self,
        kind: str,
        body_a: int,
        body_b: int | None = None,
        *,
        anchor: ArrayLike | None = None,
        anchor_b: ArrayLike | None = None,
        axis: ArrayLike | None = None,
        compliance: float = 0.0,
        angular_compliance: float = 0.0,
        limits: ArrayLike | None = None,
        rest_length: float | None = None,
        name: str | None = None,
        solver: str = "auto",
        drive: Drive | None = None,
        damping: float = 0.0,
        armature: float = 0.0,
        friction: float = 0.0,
        cone_limit: float | None = None,
        twist_limits: ArrayLike | None = None,
    ) -> int:
        """Adds a joint between ``body_a`` and ``body_b`` (``None``: the world); returns its index.

        ``solver``: ``"auto"`` (default: the joint becomes part of an articulation in
        reduced coordinates where the joint graph is a tree, else XPBD), ``"xpbd"`` or
        ``"articulation"`` (an error at build if it cannot be one). Articulation-only
        controls (hinge, prismatic, spherical): ``drive`` (a ``Drive``), ``damping``
        (N·m·s/rad or N·s/m, default 0), ``armature`` (kg·m² or kg, added to the joint's
        inertia, default 0), ``friction`` (Coulomb, N·m or N, default 0); for spherical
        joints ``cone_limit`` (rad in (0, π]: largest swing of ``axis`` from its build
        direction) and ``twist_limits`` (lo, hi) (rad, about ``axis``). ``name``: for
        ``World.joints.names`` (unique; default none).

        ``kind``: ``"spherical"`` (anchors coincide), ``"hinge"`` (anchors coincide, axes
        aligned), ``"fixed"`` (anchors coincide, relative orientation kept), ``"prismatic"``
        (relative orientation kept, a's anchor slides along the axis through b's) or
        ``"distance"`` (anchors ``rest_length`` apart, or within ``limits``). Points and
        directions are world-frame at the bodies' initial poses: ``anchor`` (3,) (m), the
        joined point on a, default a's centre of mass; ``anchor_b`` (3,) (m), the joined
        point on b, default ``anchor``; ``axis`` (3,) hinge or slide axis, any non-zero
        length, default (0, 0, 1). ``compliance`` (m/N, default 0: rigid) softens the
        positional constraints, ``angular_compliance`` (rad/(N·m), default 0) the angular
        ones. ``limits`` (lo, hi), hard: hinge angle of a relative to b about the axis
        (rad, −π ≤ lo ≤ hi ≤ π, 0 at build, right hand), prismatic slide (m), distance
        range (m, 0 ≤ lo ≤ hi; (0, L) is a rope); default none. ``rest_length`` (m,
        distance joints only, not with ``limits``), default the anchors' initial distance.
        Jointed bodies never collide with each other, nor do links of one articulation.
        Raises ``RigidError`` naming the
        joint and field (unknown kind, bad index, the same body twice, no dynamic body,
        negative or non-finite compliance, zero axis, bad limits); the scene is then
        unchanged."""
    @property
    def joint_count(self) -> int:
        """Number of joints added."""
    @property
    def build_settings(self) -> dict[str, Any]:
        """``Scene.build`` keyword arguments kept with the scene and written to its file
        (the file's ``build`` table): values None, bool, int, float or str; default
        empty. ``scene.build(**scene.build_settings)`` builds with them."""
    @build_settings.setter
    def build_settings(self, settings: dict[str, Any]) -> None: ...
    def _recipe(self) -> dict[str, Any]:
        """The calls that filled the scene, as given (what ``to_dict`` writes)."""
    def to_dict(self) -> dict[str, Any]:
        """The scene as plain JSON-able data (dicts, lists, str, float, int, bool):
        every call that filled it, as given, keys at their default left out, floats
        exact, infinities as ``"inf"``. ``Scene.from_dict`` rebuilds a scene that
        steps bit for bit the same. Schema: ``docs/scene_format.md``."""
    @classmethod
    def from_dict(cls, data: Any, base_dir: str | PathLike[str] | None = None) -> Scene:
        """A new scene from ``to_dict`` data; ``base_dir``: folder that mesh ``file``
        entries are relative to (default the current directory). Errors name the
        path inside the data (``bodies[3].density: must be positive and finite, got -1``);
        nothing is built on error."""
    def save(self, path: str | PathLike[str]) -> None:
        """Writes ``to_dict()`` to ``path``, ``.toml`` or ``.json`` (through a temporary
        file renamed over it); ``rigidrs.load_scene`` reads it back."""
    def shapes(self) -> list[dict[str, Any] | None]:
        """The bodies' shapes as ``World.shapes()`` will give them."""
    def build(
        self,
        dt: float,
        integrator: str = "strang",
        substeps: int | None = None,
        iterations: int = 1,
        *,
        sleep: bool = True,
        restitution_threshold: float | None = None,
        slop: float = 0.005,
        contact_hertz: float | None = None,
        contact_damping_ratio: float = 10.0,
        max_push_velocity: float = 3.0,
        sleep_linear: float = 0.05,
        sleep_angular: float = 0.05,
        sleep_time: float = 0.5,
        articulations: bool = True,
        articulation_integrator: str = "leapfrog",
        articulation_substeps: int | None = None,
        max_rotation_angle: float | None = None,
        threads: int | None = None,
    ) -> World:
        """Compiles the scene.

        ``dt`` (s) per step; ``integrator`` from ``INTEGRATORS`` (default "strang");
        ``substeps`` per step (default: 1 without contacts, 4 with them, and with particle
        distance links at least enough that, in each linked structure, a particle moving at
        √(2·|g|·ℓ) (ℓ its bounding-box diagonal, or its fastest initial speed if faster) travels
        at most 0.1 of the structure's shortest link per substep, up to 1024; ``World.substeps``
        tells what was chosen; unless given, a step with contacts takes substeps of at most
        1/960 s (16 at 60 Hz) while a slow body rocks on its supports in a settling scene, see
        ``World.last_substeps``); ``iterations`` contact-solver and joint iterations per substep
        (default 1; a step of a settling pile, where support contacts meet contacts between
        moving bodies beside them, takes at least 2 contact iterations). Contacts: ``restitution_threshold``
        (m/s, approach speed below which nothing bounces, 0 allowed; default None: twice the
        speed gravity gives in a contact substep, ``2 |g| dt / substeps``, 0.08 m/s at 60 Hz and
        4 substeps, 0 without gravity: a resting contact does not bounce, a landing does), ``slop``
        (m, the linear slop: contacts are predicted this far ahead, on top of what the bodies
        close in a step; resting penetration stays within it; default 0.005), ``contact_hertz`` (Hz,
        how fast penetration beyond the rest depth is pushed out, default None: 30; capped at a
        quarter of the substep rate, with a ``UserWarning`` at build when a rate given here is
        capped in a world with contacts), ``contact_damping_ratio`` (default 10),
        ``max_push_velocity`` (m/s, fastest push-out of penetration, default 3: the
        relative speed at each contact, so bodies pushed out of a chain of overlaps add up their
        contacts' speeds). Sleeping:
        ``sleep`` (default True); an island sleeps after ``sleep_time`` s (0.5) with every
        body below ``sleep_linear`` m/s (0.05) and ``sleep_angular`` rad/s (0.05).
        ``iterations`` is also the number of XPBD constraint passes per substep (each a
        Gauss–Seidel sweep forward and back over the particle constraints, then the contacts);
        with XPBD joints ``substeps`` defaults to at least half the joints of the largest
        jointed system (at most 64). Articulations: ``articulations`` (default True; False keeps
        every joint XPBD), ``articulation_integrator`` from ``ARTICULATION_INTEGRATORS``
        (default "leapfrog"), ``articulation_substeps`` per step (default None: chosen
        before every substep so that h·ω ≤ 0.25, ω the fastest joint rate or link tension
        mode of the state). An articulation with a link in contact steps inside the contact
        substeps instead (semi-implicit, like the bodies in contact): that step the world
        takes ``max(substeps, articulation_substeps or the count h·ω ≤ 0.25 asks)`` of them,
        at most 256. Fast spinners: ``max_rotation_angle`` (rad, default None: the
        integrator's own, 0.2 for strang, 0.5 for yoshida4, 0.6 for suzuki4, 0.03 for rk4) is
        the largest angle a body may turn by per rotation substep, taken at the largest
        ``|ω|`` of its free orbit; an asymmetric body that would turn more per step takes that
        many more rotation substeps, alone (stage ``rotate_fast``; inside the ``rk4`` stage
        for rk4); euler, symplectic_euler and implicit_gyro never subdivide; ``math.inf``
        never subdivides (the bare method). Threads: ``threads`` (≥ 1, default None: every
        core) worker threads for the world's own parallel work; every count gives the same
        bits."""
    @property
    def particle_count(self) -> int:
        """Number of particles added so far."""
    @property
    def constraint_count(self) -> int:
        """Number of particle constraints added so far (the length of ``World.constraint_forces()``)."""
    @property
    def cluster_count(self) -> int:
        """Number of shape-matching clusters added so far."""
    def add_particle(
        self,
        position: ArrayLike,
        *,
        mass: float = 1.0,
        radius: float = 0.0,
        velocity: ArrayLike | None = None,
        fixed: bool = False,
        friction: float = 0.5,
        collision_group: int = 1,
        collision_mask: int = 4294967295,
    ) -> int:
        """Adds a particle; returns its index in ``World.particles``.

        ``position`` (3,) (m), ``velocity`` (3,) (m/s, default 0), ``mass`` (kg, default 1),
        ``radius`` (m, default 0: a point, which collides with rigid colliders but not with
        other particles), ``friction`` μ, static and dynamic, against rigid colliders and other
        particles (default 0.5, combined with the other side's by the geometric mean).
        ``fixed=True`` pins it (inverse mass 0). ``collision_group``/``collision_mask``: the
        collision filter against rigid colliders and other particles, as in ``add_body``
        (default group 1, every mask bit)."""
    def add_distance_constraint(
        self, p: int, q: int, *, compliance: float = 0.0, damping: float = 0.0, rest_length: float | None = None
    ) -> int:
        """``C = |x_p − x_q| − L``; returns the constraint index.

        ``rest_length`` L (m, default: the current distance), ``compliance`` α (m/N, default 0:
        rigid), ``damping`` β (N·s/m, default 0; acts only with α > 0). Its force λ/h² (N) is
        negative when the link is stretched."""
    def add_bending_constraint(
        self, p0: int, p1: int, p2: int, p3: int, *, compliance: float = 0.0, damping: float = 0.0
    ) -> int:
        """Dihedral bending over the edge p0–p1 of triangles (p0, p1, p2) and (p1, p0, p3):
        ``C = θ − θ0`` (rad; θ0 the current angle). ``compliance`` in rad/(N·m), ``damping`` in
        N·m·s/rad; the force λ/h² is the bending moment (N·m)."""
    def add_volume_constraint(self, particles: Sequence[int], *, compliance: float = 0.0, damping: float = 0.0) -> int:
        """Volume of the tetrahedron of 4 particles, ``C = V − V0`` (m³; V0 the current volume).
        ``compliance`` in m³/Pa, ``damping`` in Pa·s/m³; the force λ/h² is a pressure (Pa)."""
    def add_mesh_volume_constraint(
        self, triangles: Any, *, compliance: float = 0.0, damping: float = 0.0, pressure: float = 1.0
    ) -> int:
        """Volume enclosed by a closed mesh of particles (``triangles`` (T, 3) particle indices,
        counter-clockwise from outside): ``C = V − pressure·V0`` (m³). Units as for a tetrahedron."""
    def add_attachment(
        self,
        particle: int,
        body: int,
        *,
        point: ArrayLike | None = None,
        rest_length: float = 0.0,
        compliance: float = 0.0,
        damping: float = 0.0,
    ) -> int:
        """Attaches ``particle`` to the point ``point`` (3,) (m, world, at build; default the
        particle's position) of ``body``, which moves with the body: ``C = |x − a| − rest_length``.
        The body takes its share through its generalized inverse mass (fixed, kinematic and
        sleeping bodies do not move). Units as for a distance constraint."""
    def add_shape_matching(
        self,
        particles: Sequence[int],
        *,
        mode: str = "linear",
        stiffness: float = 1.0,
        beta: float = 0.5,
        preserve_volume: bool = True,
        plastic_yield: float | None = None,
        plastic_creep: float = 0.0,
        plastic_max: float = ...,
    ) -> int:
        """A shape-matching cluster (Müller et al. 2005) over distinct ``particles``; returns its index.

        ``mode``: "rigid" (≥ 3 non-collinear particles), "linear" or "quadratic" (spanning a
        volume; ≥ 4 and ≥ 10). ``stiffness`` in [0, 1]: fraction of the way to the goal per substep
        (default 1). ``beta`` in [0, 1]: deformable (1) vs rigid (0) goal (default 0.5).
        ``preserve_volume``: linear goals scaled to det 1 (default True). Plasticity (off unless
        ``plastic_yield`` is given): beyond the elastic strain ``plastic_yield`` (‖S − I‖_F) the
        rest shape flows at ``plastic_creep`` (1/s) up to ``plastic_max`` (‖Sp − I‖_F, default
        unbounded), keeping its volume. Overlapping clusters share their particles' mass."""
    def add_rope(
        self,
        start: ArrayLike,
        end: ArrayLike,
        segments: int,
        *,
        mass: float = 1.0,
        radius: float = 0.0,
        friction: float = 0.5,
        compliance: float = 0.0,
        damping: float = 0.0,
        pinned: Sequence[int] = ...,
        collision_group: int = 1,
        collision_mask: int = 4294967295,
    ) -> range:
        """A rope from ``start`` to ``end`` (m): ``segments + 1`` particles sharing ``mass`` (kg,
        total) joined by ``segments`` distance constraints (added in order). ``pinned``: local
        indices (0 = start) of pinned particles. ``collision_group``/``collision_mask``: every
        particle's filter (see ``add_particle``). Returns the particles' index range."""
    def add_cloth(
        self,
        origin: ArrayLike,
        u: ArrayLike,
        v: ArrayLike,
        resolution: tuple[int, int],
        *,
        mass: float = 1.0,
        radius: float = 0.0,
        friction: float = 0.5,
        compliance: float = 0.0,
        damping: float = 0.0,
        bending_compliance: float | None = None,
        bending_damping: float | None = None,
        pinned: Sequence[int] = ...,
        collision_group: int = 1,
        collision_mask: int = 4294967295,
    ) -> range:
        """A cloth of ``resolution = (nu, nv)`` particles at ``origin + i/(nu−1)·u + j/(nv−1)·v``
        (m), local index ``j·nu + i``, sharing ``mass`` (kg, total). Distance constraints on every
        triangle edge (compliance m/N, ``damping`` N·s/m), then dihedral bending on every interior
        edge if ``bending_compliance`` (rad/(N·m)) is given, with the dashpot ``bending_damping``
        (N·m·s/rad; default 0.05 s / ``bending_compliance``: damping proportional to the bending
        stiffness, ratio π·f·0.05 s for a bending mode of f Hz, so a dropped cloth comes to rest;
        0 for none). ``collision_group``/``collision_mask``: every particle's filter (see
        ``add_particle``). Returns the particles' index range."""
    def add_soft_box(
        self,
        center: ArrayLike,
        half_extents: ArrayLike,
        cells: tuple[int, int, int],
        *,
        mass: float = 1.0,
        radius: float = 0.0,
        friction: float = 0.5,
        compliance: float = 0.0,
        damping: float = 0.0,
        volume_compliance: float | None = None,
        collision_group: int = 1,
        collision_mask: int = 4294967295,
    ) -> range:
        """An axis-aligned box (m) of ``cells`` cubes, each split into six tetrahedra: distance
        constraints on every tetrahedron edge, then a volume constraint per tetrahedron if
        ``volume_compliance`` (m³/Pa) is given. ``collision_group``/``collision_mask``: every
        particle's filter (see ``add_particle``). Returns the particles' index range."""
    def add_shape_matched_body(
        self,
        source: Shape | ArrayLike,
        *,
        spacing: float | None = None,
        position: ArrayLike | None = None,
        orientation: ArrayLike | None = None,
        mass: float = 1.0,
        radius: float = 0.0,
        friction: float = 0.5,
        mode: str = "linear",
        stiffness: float = 1.0,
        beta: float = 0.5,
        preserve_volume: bool = True,
        plastic_yield: float | None = None,
        plastic_creep: float = 0.0,
        plastic_max: float = ...,
        cluster_size: float | None = None,
        collision_group: int = 1,
        collision_mask: int = 4294967295,
    ) -> tuple[range, list[int]]:
        """A shape-matched body: particles at the points (N, 3) of ``source``, or filling the shape
        ``source`` on a grid of ``spacing`` (m; a mesh adds its vertices), placed by ``position``
        and ``orientation`` (x, y, z, w). One cluster over all of them, or overlapping clusters of
        edge ``2·cluster_size`` (m) on a grid of that spacing. It collides through its particles.
        Returns (particle range, cluster indices); cluster parameters as in ``add_shape_matching``;
        ``collision_group``/``collision_mask``: every particle's filter (see ``add_particle``)."""

@final
class Bodies:
    """NumPy views of a world's bodies; each view keeps the world alive."""

    def __len__(self) -> int: ...
    @property
    def names(self) -> list[str]:
        """The bodies' names ("" where none was given)."""
    @property
    def sleeping(self) -> npt.NDArray[np.bool_]:
        """(N,) whether each body is asleep; read-only."""
    @property
    def position(self) -> _F64:
        """(N, 3) centre of mass, world (m); writable."""
    @property
    def orientation(self) -> _F64:
        """(N, 4) principal-frame quaternion (x, y, z, w); writable."""
    @property
    def linear_velocity(self) -> _F64:
        """(N, 3) centre-of-mass velocity, world (m/s); writable."""
    @property
    def angular_velocity(self) -> _F64:
        """(N, 3) angular velocity, world (rad/s); writable."""
    @property
    def force(self) -> _F64:
        """(N, 3) applied force at the centre of mass, world (N); writable, persists."""
    @property
    def torque(self) -> _F64:
        """(N, 3) applied torque, world (N·m); writable, persists."""
    @property
    def mass(self) -> _F64:
        """(N,) mass (kg), inf for fixed bodies; read-only."""
    @property
    def inverse_mass(self) -> _F64:
        """(N,) 1/mass (1/kg), 0 for fixed bodies; read-only."""
    @property
    def inertia(self) -> _F64:
        """(N, 3) principal moments, body frame (kg·m²); read-only."""
    @property
    def inverse_inertia(self) -> _F64:
        """(N, 3) inverse principal moments (1/(kg·m²)); read-only."""
    @property
    def rotation(self) -> _F64:
        """(N, 3, 3) rotation matrix of each body; read-only, refreshed by each step."""
    @property
    def inertia_world(self) -> _F64:
        """(N, 3, 3) world inertia R I0 Rᵀ (kg·m²); read-only, refreshed by each step."""
    @property
    def angular_momentum(self) -> _F64:
        """(N, 3) spin angular momentum I ω, world (kg·m²/s); read-only, refreshed by each step."""

@final
class Joints:
    """NumPy views of a world's joints, (J,) each; each view keeps the world alive."""

    def __len__(self) -> int: ...
    @property
    def position(self) -> _F64:
        """(J,) hinge angle (rad) or prismatic slide (m) of body a relative to body b since
        build; NaN for other kinds. Read-only, refreshed by each step."""
    @property
    def velocity(self) -> _F64:
        """(J,) its rate (rad/s or m/s); NaN for other kinds. Read-only."""
    @property
    def target(self) -> _F64:
        """(J,) 1-dof drive targets (rad, m, rad/s or m/s by the drive's mode); writable,
        read at the next step; ignored for joints without a 1-dof drive."""
    @property
    def force(self) -> _F64:
        """(J,) generalized force of the joint's drive, damping, friction and limits on body a,
        averaged over the last step (N·m or N); XPBD hinges and slides: the constraint couple
        or force along the axis; NaN for joints without a single coordinate. Read-only."""
    @property
    def names(self) -> list[str]:
        """The joints' names ("" where none was given)."""

@final
class Particles:
    """NumPy views of a world's particles; each view keeps the world alive."""

    def __len__(self) -> int: ...
    @property
    def position(self) -> _F64:
        """(M, 3) positions, world (m); writable."""
    @property
    def velocity(self) -> _F64:
        """(M, 3) velocities, world (m/s); writable."""
    @property
    def inverse_mass(self) -> _F64:
        """(M,) 1/mass (1/kg), 0 for pinned particles; read-only."""
    @property
    def mass(self) -> _F64:
        """(M,) mass (kg), also of pinned particles; read-only."""
    @property
    def radius(self) -> _F64:
        """(M,) collision radius (m); read-only."""

@final
class Recording:
    """Body and particle trajectories captured while stepping (``World.record``) or loaded
    from a file (``Recording.load``). Each array is a copy made on access: ``times`` (T,)
    (s), ``steps`` (T,), ``position`` (T, N, 3) (m), ``orientation`` (T, N, 4) (x, y, z, w)
    as in ``world.bodies``, ``particle_position`` (T, P, 3) (m; P = 0 without particles).
    Memory: 8·(2 + 7·N + 3·P) bytes per frame (``nbytes``); while recording the buffers grow
    by doubling, so up to twice that may be reserved."""

    def __len__(self) -> int:
        """Number of frames T."""
    @property
    def times(self) -> _F64:
        """(T,) simulated time of each frame (s)."""
    @property
    def steps(self) -> npt.NDArray[np.int64]:
        """(T,) the world's step count at each frame."""
    @property
    def position(self) -> _F64:
        """(T, N, 3) body positions (centre of mass, world, m)."""
    @property
    def orientation(self) -> _F64:
        """(T, N, 4) body orientations (x, y, z, w), as ``world.bodies.orientation``."""
    @property
    def particle_position(self) -> _F64:
        """(T, P, 3) particle positions (world, m); P = 0 without particles."""
    @property
    def every(self) -> int:
        """Steps between frames."""
    @property
    def attached(self) -> bool:
        """Whether the world's steps are still being captured."""
    @property
    def nbytes(self) -> int:
        """Bytes held by the frames: 8·T·(2 + 7·N + 3·P)."""
    def detach(self) -> None:
        """Stops capturing; the frames so far stay. Idempotent."""
    def save(self, path: str | os.PathLike[str], compress: bool = False) -> None:
        """Writes the frames to ``path`` (the name is kept as given) with ``numpy.savez``, or
        ``numpy.savez_compressed`` with ``compress=True`` (default False; smaller when bodies
        rest, slower), through a temporary file and a rename: on failure (missing directory,
        no permission) ``OSError`` and no file left behind."""
    @staticmethod
    def load(path: str | os.PathLike[str]) -> Recording:
        """Reads a file written by ``save``: ``FileNotFoundError`` if there is none,
        ``ValueError`` if it is not a recording or is damaged."""

@final
class World:
    """A compiled scene: state arrays and the pipeline of stages the scene needs."""

    def record(self, every: int = 1) -> Recording:
        """Attaches a new ``Recording`` and returns it: the current state is its first frame,
        then every ``every``-th step (default 1; each step of ``step(n)`` counts) adds one,
        until ``rec.detach()``. Several may be attached at once. While one is attached,
        ``step(n)`` runs its steps one by one (same results, bit for bit)."""
    def shapes(self) -> list[dict[str, Any] | None]:
        """Per body (None for a body without a shape): ``kind`` ("Sphere", "Box", "Capsule",
        "Cylinder", "Cone", "ConvexHull", "TriMesh", "Plane", "Compound"), ``position`` (3,)
        (m) and ``orientation`` (4,) (x, y, z, w) of the shape's frame in the body frame of
        ``bodies.position``/``orientation`` (principal frame at the centre of mass), and its
        dimensions in its own frame (m): ``radius``, ``half_height`` (axial shapes, axis z),
        ``half_extents`` (3,), ``points`` (K, 3) plus the hull's ``vertices`` (V, 3) and
        ``triangles`` (F, 3) (ConvexHull), ``vertices`` and ``triangles`` (TriMesh),
        ``normal`` (3,) and ``offset`` (Plane: normal·x ≤ offset), ``parts`` (Compound:
        dicts like these, posed in the compound's frame)."""
    def step(self, n: int = 1) -> None:
        """Advances ``n`` steps (GIL released). Raises ``StateError`` naming the body if a
        view was given an invalid state; then nothing moves. A step after which a body or
        particle is not finite, or that fails inside, is undone: ``SimulationError`` naming
        the body or particle, the stage and the time, the world as before that step. Ctrl-C
        (checked every 20 ms) stops at a step boundary with ``KeyboardInterrupt``; the steps
        before it are kept."""
    @property
    def bodies(self) -> Bodies: ...
    @property
    def threads(self) -> int:
        """Worker threads the world's parallel stages use (the build argument ``threads``,
        every core by default); settable (≥ 1). Every count gives the same bits. Parallel
        today: the free rotation of 4096 or more bodies of one class; the contact solve,
        island by island and group by group, when the last step had two islands of support
        blocks or more with 128 blocks between them; in such a step, or after 8192 contact
        pairs or more, the narrow phase and contact-constraint build."""
    @threads.setter
    def threads(self, n: int) -> None: ...
    @property
    def joints(self) -> Joints:
        """The joints, as NumPy views."""
    def set_joint_positions(self, positions: ArrayLike, velocities: ArrayLike | None = None) -> None:
        """Poses articulated hinges and slides: ``positions`` (J,) angle (rad) or slide (m) per
        joint, NaN to keep one; ``velocities`` (J,) likewise (rad/s, m/s; default 0 for the
        joints given a position). Raises ``RigidError`` naming the joint (XPBD, not 1-dof,
        outside its limits, infinite) and leaves the world unchanged."""
    def articulations(self) -> list[dict[str, Any]]:
        """Per articulation: ``bodies`` (root first), ``joints`` (−1: a floating root's free
        joint), ``dofs`` and the ``substeps`` its last step took (the contact substeps when
        one of its links was in contact)."""
    @property
    def time(self) -> float:
        """Simulated time (s)."""
    @property
    def steps(self) -> int: ...
    @property
    def dt(self) -> float:
        """Time step (s)."""
    @property
    def integrator(self) -> str: ...
    @property
    def stages(self) -> list[str]:
        """Names of the stages one (sub)step runs now, in order. ``rotate_fast`` is listed
        while some body turns too fast for one split of its rotation per step (see
        ``max_rotation_angle`` of ``Scene.build``); ``articulation_contact``: the kick and
        the drift of the articulations in contact, around the contact solve."""
    def profile(self, reset: bool = True) -> dict[str, Any]:
        """Seconds per stage since the last reset, and ``"steps"``: the steps covered."""
    @property
    def profiling(self) -> bool: ...
    @profiling.setter
    def profiling(self, on: bool) -> None: ...
    def kinetic_energy(self) -> float:
        """Kinetic energy (J)."""
    def potential_energy(self) -> float:
        """Gravitational potential energy −Σ m g·p (J)."""
    def linear_momentum(self) -> _F64:
        """(3,) total linear momentum (kg·m/s)."""
    def angular_momentum(self) -> _F64:
        """(3,) total angular momentum about the origin (kg·m²/s)."""
    def apply_force(self, body: int, force: ArrayLike, point: ArrayLike | None = None) -> None:
        """Adds ``force`` (3,) (N) to ``body``; with ``point`` (3,) (m) also the torque
        (point − p) × force. Persists until changed or cleared."""
    def apply_torque(self, body: int, torque: ArrayLike) -> None:
        """Adds ``torque`` (3,) (N·m) to ``body``; persists until cleared."""
    def clear_forces(self) -> None:
        """Zeroes every applied force and torque."""
    def contacts(self) -> dict[str, Any]:
        """This step's contact points (K of them): ``body_a``, ``body_b`` (K,) int64;
        ``point`` (K, 3) world (m); ``normal`` (K, 3) from a to b; ``depth`` (K,)
        penetration (m; negative: predicted, not yet touching); ``normal_impulse`` (K,)
        and ``friction_impulse`` (K, 3) over the step (N·s)."""
    @property
    def substeps(self) -> int:
        """Substeps per step."""
    @property
    def last_substeps(self) -> int:
        """Contact substeps the last step took: ``substeps``, or enough for substeps of at most
        1/960 s (16 at 60 Hz) while a slow body rocks on its supports (some points of a face let go while others push) and for 0.5 s after,
        unless ``substeps`` was given at build; or more if an articulation in contact asked
        for them."""
    def joint_forces(self) -> _F64:
        """(J, 3) force (N, world) each joint applied to its body a over the last
        substep (λ/h² of its positional constraints); body b received the opposite."""
    def joint_torques(self) -> _F64:
        """(J, 3) couple (N·m, world) of each joint's angular constraints on body a over
        the last substep: with the force, the wrench about a's anchor."""
    @property
    def particles(self) -> Particles:
        """The particles, as NumPy views."""
    def constraint_forces(self) -> _F64:
        """(C,) λ/h² of every particle constraint at the last substep, by constraint index: the
        generalized force along the constraint's gradient (N, N·m or Pa)."""
    def clusters(self) -> dict[str, Any]:
        """Shape-matching clusters at the last substep (K of them): ``center`` (K, 3) (m),
        ``rotation`` (K, 3, 3), ``plastic`` (K, 3, 3) the plastic deformation Sp."""
    def snapshot(self) -> Snapshot:
        """A copy of everything a step reads: state, applied forces, time, contact manifolds
        and warm starts, friction patches, sleep timers and islands, joint and particle
        multipliers, articulation state, plastic rest shapes. ``restore`` makes stepping on
        from it bitwise what would have followed."""
    def restore(self, snap: Snapshot) -> None:
        """Makes this world ``snap`` again. Views taken before stay valid and show the
        restored values. ``snap`` must have this world's numbers of bodies, particles and
        joints (a snapshot of it, or of a world built from the same scene); otherwise
        ``RigidError`` and nothing changes."""
    def save(self, path: str | PathLike[str]) -> None:
        """Writes the world's snapshot to the file ``path`` (to a temporary name beside it,
        then renamed over it, so a crash never leaves half a file); ``load(path)`` reads
        it back. Raises ``OSError`` (naming the path) when the file cannot be written."""
    def __copy__(self) -> World:
        """An independent world in the same state; so is ``copy.deepcopy``."""
    def __deepcopy__(self, memo: Any) -> World: ...
    def __reduce__(self) -> tuple[Any, tuple[bytes]]:
        """Pickles as its snapshot bytes."""

@final
class Snapshot:
    """Everything a step of a world reads, frozen (``World.snapshot``). Pickles as its bytes."""

    @property
    def time(self) -> float:
        """Simulated time at the snapshot (s)."""
    @property
    def steps(self) -> int:
        """Steps taken at the snapshot."""
    def to_bytes(self) -> bytes:
        """The snapshot as bytes: a header (``RIGIDRS\\0``, kind, format version, engine
        version, length, CRC-32), then the state."""
    @staticmethod
    def from_bytes(data: bytes) -> Snapshot:
        """The snapshot in ``data``. Data that is foreign, truncated, corrupted, or written
        by another rigidrs version raises ``RigidError`` (a ``ValueError``) saying which."""
    def __reduce__(self) -> tuple[Any, tuple[bytes]]: ...

def load(path: str | PathLike[str]) -> World:
    """The world saved by ``World.save`` in the file ``path``. A missing file raises
    ``FileNotFoundError``; a file that is not a snapshot of this rigidrs version, or is
    truncated or corrupted, ``RigidError`` (a ``ValueError``) naming the path and what
    is wrong."""

@final
class BatchBodies:
    """(B, N, ·) NumPy views of a batch's bodies; each view keeps the batch alive. Writes
    take effect at the next ``Batch.step``."""

    def __len__(self) -> int: ...
    @property
    def position(self) -> _F64:
        """(B, N, 3) centre of mass of each body of each copy, world (m); writable."""
    @property
    def orientation(self) -> _F64:
        """(B, N, 4) orientation quaternion (x, y, z, w); writable."""
    @property
    def linear_velocity(self) -> _F64:
        """(B, N, 3) centre-of-mass velocity, world (m/s); writable."""
    @property
    def angular_velocity(self) -> _F64:
        """(B, N, 3) angular velocity, world (rad/s); writable."""

@final
class Batch:
    """B worlds of one layout stepped in parallel; copy ``i`` is bitwise the world
    ``scene.build(dt, ...)`` stepped alone (with its parameters and written states).

    ``Batch(scene, copies=B, dt=..., **build)``: B copies of one scene; or
    ``Batch([scene, ...], dt=..., **build)``: one copy per scene, which must have equal
    numbers of bodies, joints and particles (``RigidError`` names the first difference).
    ``build``: the keyword arguments of ``Scene.build`` (``threads``: the worker threads
    stepping the copies, default every core)."""

    def __new__(cls, scene: Scene | list[Scene], copies: int | None = None, *, dt: float, **build: Any) -> Batch: ...
    def step(self, n: int = 1) -> None:
        """Advances every copy ``n`` steps, in parallel with the GIL released. A state written
        through the views that no step can take raises ``StateError`` naming the copy and the
        body; nothing moves. A copy that diverges raises ``SimulationError`` naming the copy,
        the body, the stage and the time; every copy is put back as it was before that copy's
        failing step (the message would list a copy that could not be). Ctrl-C stops every copy at
        the same step boundary (``KeyboardInterrupt``). A state written through the views by
        another thread while the steps run is kept, as if written after the call, and checked by
        the next call."""
    def set(self, name: str, values: ArrayLike) -> None:
        """Per-copy parameter ``name``, ``values`` of shape (B,) (every body of a copy) or
        (B, N) (per body): "friction" (dynamic and static, –), "static_friction",
        "restitution", "mass" (kg, dynamic bodies; inertia scaled with it), "mass_scale"
        (factor on mass and inertia); "gravity" (B, 3) (m/s²). Each copy is built again from
        its scene with the value, keeping the views' states and the time (contact warm starts
        and sleep timers start afresh: set parameters before stepping for copies bitwise equal
        to worlds built with them). Unknown name or wrong shape: error; nothing changes."""
    def world(self, i: int) -> World:
        """Copy ``i`` as a world of its own (stepping it leaves the batch alone)."""
    @property
    def bodies(self) -> BatchBodies: ...
    @property
    def copies(self) -> int:
        """Number of copies B."""
    def __len__(self) -> int: ...
    @property
    def threads(self) -> int:
        """Worker threads stepping the copies."""
    @property
    def time(self) -> float:
        """Simulated time of every copy (s)."""
    @property
    def steps(self) -> int:
        """Steps every copy has taken."""
    @property
    def dt(self) -> float:
        """Time step (s)."""
