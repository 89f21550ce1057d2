"""Pictures without a display: a small software rasterizer in NumPy.

``render(world, rec, "run.mp4")`` draws each frame of a recording (or the world's
current state) with flat Lambert shading under a directional light plus ambient,
a z-buffer, a checkered ground where the scene has a plane, the bodies' shadows
projected on it, and fog towards the horizon as a depth cue. No OpenGL, no display.
PNG needs nothing beyond NumPy; GIF and MP4 need ``pip install "rigidrs[video]"``.
"""
from __future__ import annotations

import os
import struct
import tempfile
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
import numpy.typing as npt

from .mesh import F64, I64, quat_matrix, shape_mesh, unit_sphere

SKY_TOP = np.array([0.55, 0.70, 0.90])
"""Sky colour at the top of the picture (RGB, 0..1); it fades to ``SKY_HORIZON``."""
SKY_HORIZON = np.array([0.90, 0.93, 0.97])
PALETTE = np.array([
    [0.90, 0.30, 0.25], [0.25, 0.55, 0.85], [0.95, 0.70, 0.20], [0.35, 0.70, 0.40],
    [0.60, 0.40, 0.75], [0.95, 0.50, 0.65], [0.30, 0.75, 0.75], [0.75, 0.55, 0.35],
])
"""Body colours by index (cycled); fixed bodies are grey."""
FIXED = np.array([0.62, 0.62, 0.62])
PARTICLE = np.array([0.92, 0.92, 0.95])
AMBIENT = 0.35
DIFFUSE = 0.65
FORMATS = (".png", ".gif", ".mp4")


@dataclass
class Camera:
    """A pinhole camera: ``eye`` and ``target`` (3,) (m, world), ``up`` (3,) (default z),
    ``fov`` vertical field of view (degrees, default 40)."""

    eye: Sequence[float]
    target: Sequence[float]
    up: Sequence[float] = (0.0, 0.0, 1.0)
    fov: float = 40.0

    def basis(self) -> tuple[F64, F64, F64, F64]:
        eye = np.asarray(self.eye, dtype=float)
        fwd = np.asarray(self.target, dtype=float) - eye
        if not np.all(np.isfinite(fwd)) or np.linalg.norm(fwd) == 0:
            raise ValueError(f"camera eye {self.eye} and target {self.target} must differ and be finite")
        fwd /= np.linalg.norm(fwd)
        right = np.cross(fwd, np.asarray(self.up, dtype=float))
        if np.linalg.norm(right) < 1e-9:  # looking along up: any right will do
            right = np.cross(fwd, [1.0, 0.0, 0.0] if abs(fwd[0]) < 0.9 else [0.0, 1.0, 0.0])
        right /= np.linalg.norm(right)
        return eye, fwd, right, np.cross(right, fwd)


def _camera(camera: Camera | Mapping[str, Any] | None, lo: F64, hi: F64, aspect: float) -> Camera:
    if isinstance(camera, Camera):
        return camera
    if camera is not None:
        return Camera(**dict(camera))
    # Frames the bodies' bounding box (planes excluded) seen from the front-right,
    # 25° above: the camera backs off until every corner of the box is inside the
    # picture with a margin (the sphere around the box would leave it small).
    centre = (lo + hi) / 2
    fov = 40.0
    az, el = np.radians(-60.0), np.radians(25.0)
    direction = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    cam = Camera(eye=tuple(centre + direction), target=tuple(centre), fov=fov)
    _, fwd, right, up = cam.basis()
    tan_v = np.tan(np.radians(fov) / 2) * 0.9
    tan_h = tan_v * aspect
    span = np.maximum(hi - lo, 1e-3)
    corners = centre + (np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]) * span)
    rel = corners - centre
    # Corner c is inside when |c·right| ≤ tan_h (dist + c·back) and likewise up: solve for dist.
    need = np.maximum(np.abs(rel @ right) / tan_h, np.abs(rel @ up) / tan_v) + rel @ fwd
    dist = max(float(need.max()), 1.05 * float(np.linalg.norm(span)) / 2)
    return Camera(eye=tuple(centre - dist * fwd), target=tuple(centre), fov=fov)


class _Scene:
    """What is drawn, prepared once: one mesh per body (body frame), planes, particles."""

    def __init__(self, shapes: Sequence[Mapping[str, Any] | None], fixed: npt.NDArray[np.bool_],
                 colors: Any, particle_radius: F64, detail: int) -> None:
        verts, tris, owner, planes = [], [], [], []
        self.color = body_colors(fixed, colors)
        offset = 0
        for i, d in enumerate(shapes):
            if d is None:
                continue
            if d["kind"] == "Plane":
                planes.append((i, np.asarray(d["normal"], float), float(d["offset"]),
                               np.asarray(d["position"], float), np.asarray(d["orientation"], float)))
                continue
            v, t = shape_mesh(d, detail)
            verts.append(v)
            tris.append(t + offset)
            owner.append(np.full(len(v), i))
            offset += len(v)
        self.verts = np.concatenate(verts) if verts else np.zeros((0, 3))
        self.tris = np.concatenate(tris) if tris else np.zeros((0, 3), np.int64)
        self.owner = np.concatenate(owner) if owner else np.zeros(0, np.int64)
        self.tri_body = self.owner[self.tris[:, 0]] if len(self.tris) else np.zeros(0, np.int64)
        self.two_sided = np.array([shapes[b] is not None and shapes[b]["kind"] == "TriMesh"  # type: ignore[index]
                                   for b in self.tri_body], dtype=bool)
        self.planes = planes
        self.particle_radius = particle_radius
        self.ball = unit_sphere(1 if detail >= 2 else 0)

    def triangles(self, pos: F64, quat: F64, particles: F64 | None) -> tuple[F64, I64, F64, npt.NDArray[np.bool_]]:
        """World vertices (V, 3), triangles (T, 3) into them, colour (T, 3), two-sidedness (T,)."""
        rot = quat_matrix(quat)
        w = np.einsum("vij,vj->vi", rot[self.owner], self.verts) + pos[self.owner]
        tris, color, two = self.tris, self.color[self.tri_body], self.two_sided
        if particles is not None and len(particles):
            bv, bt = self.ball
            r = self.particle_radius[:, None, None]
            pv = (particles[:, None, :] + r * bv[None]).reshape(-1, 3)  # (P·V, 3)
            pt = (bt[None] + len(w) + len(bv) * np.arange(len(particles))[:, None, None]).reshape(-1, 3)
            w = np.concatenate([w, pv])
            tris = np.concatenate([tris, pt])
            color = np.concatenate([color, np.tile(PARTICLE, (len(pt), 1))])
            two = np.concatenate([two, np.zeros(len(pt), bool)])
        return w, tris, color, two

    def plane_world(self, pos: F64, quat: F64) -> list[tuple[F64, float]]:
        """Each plane's (unit normal, offset) in world coordinates for these body poses."""
        out = []
        for i, n, off, p, q in self.planes:
            rq = quat_matrix(quat[i]) @ quat_matrix(q)
            origin = quat_matrix(quat[i]) @ p + pos[i]
            nw = rq @ n
            out.append((nw, float(nw @ origin + off)))
        return out


def body_colors(fixed: npt.NDArray[np.bool_], colors: Any = None) -> F64:
    """(N, 3) RGB in 0..1 per body: ``colors`` as :func:`render` takes it ((3,), (N, 3) or
    {body: (3,)}, 0..1 or 0..255), default the palette with fixed bodies grey."""
    n = len(fixed)
    base = np.array([FIXED if fixed[i] else PALETTE[i % len(PALETTE)] for i in range(n)]).reshape(n, 3)
    if colors is not None:
        if isinstance(colors, Mapping):
            for i, c in colors.items():
                if not 0 <= int(i) < n:
                    raise ValueError(f"colors: body {i} is out of range (the scene has {n} bodies)")
                base[int(i)] = _color(c)
        else:
            c = np.asarray(colors, dtype=float)
            if c.ndim == 2 and len(c) != n:
                raise ValueError(f"colors must be (3,), ({n}, 3) or a dict {{body: colour}}, got shape {c.shape}")
            base[:] = _color(c) if c.ndim == 1 else np.array([_color(x) for x in c]).reshape(n, 3)
    return base


def _color(c: Any) -> F64:
    a = np.asarray(c, dtype=float).reshape(-1)[:3]
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ValueError(f"a colour must be 3 numbers (RGB, 0..1 or 0..255), got {c!r}")
    return np.asarray(a / 255.0 if a.max() > 1.0 else a)


def _rasterize(xy: F64, iz: F64, width: int, height: int,
               chunk: int = 1 << 21) -> tuple[I64, F64, I64]:
    """Pixels covered by screen triangles ``xy`` (T, 3, 2) (pixel units, y down): flat
    pixel index, interpolated 1/depth (``iz`` (T, 3), affine in screen space) and
    triangle index of each fragment. Pixel centres at (i + 0.5, j + 0.5)."""
    x, y = xy[..., 0], xy[..., 1]
    xlo = np.minimum(np.minimum(x[:, 0], x[:, 1]), x[:, 2])
    xhi = np.maximum(np.maximum(x[:, 0], x[:, 1]), x[:, 2])
    ylo = np.minimum(np.minimum(y[:, 0], y[:, 1]), y[:, 2])
    yhi = np.maximum(np.maximum(y[:, 0], y[:, 1]), y[:, 2])
    x0 = np.clip(np.ceil(xlo - 0.5), 0, width).astype(np.int64)
    x1 = np.clip(np.floor(xhi - 0.5), -1, width - 1).astype(np.int64)
    y0 = np.clip(np.ceil(ylo - 0.5), 0, height).astype(np.int64)
    y1 = np.clip(np.floor(yhi - 0.5), -1, height - 1).astype(np.int64)
    w = np.maximum(x1 - x0 + 1, 0)
    h = np.maximum(y1 - y0 + 1, 0)
    area = (x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0]) - (x[:, 2] - x[:, 0]) * (y[:, 1] - y[:, 0])
    keep = np.nonzero((w * h > 0) & (np.abs(area) > 1e-12))[0]
    x, y, iz, area = x[keep], y[keep], iz[keep], area[keep]
    x0, y0, w, h = x0[keep], y0[keep], w[keep], h[keep]
    # Edge functions e_k = A_k px + B_k py + C_k, positive inside; as barycentric
    # weights (divided by the area) they also give 1/depth as a plane in (px, py).
    s = (np.sign(area) / np.abs(area))[:, None]
    xa, ya = x[:, [1, 2, 0]], y[:, [1, 2, 0]]
    xb, yb = x[:, [2, 0, 1]], y[:, [2, 0, 1]]
    A = -(yb - ya) * s
    B = (xb - xa) * s
    C = ((yb - ya) * xa - (xb - xa) * ya) * s
    ZA, ZB, ZC = (A * iz).sum(1), (B * iz).sum(1), (C * iz).sum(1)
    edges = [(np.ascontiguousarray(A[:, k]), np.ascontiguousarray(B[:, k]), np.ascontiguousarray(C[:, k]))
             for k in range(3)]
    pix, depth, owner = [], [], []
    counts = w * h
    ends = np.cumsum(counts)
    start = 0
    while start < len(keep):
        # Chunks of about `chunk` fragments bound the memory for huge triangles.
        stop = int(np.searchsorted(ends, (ends[start - 1] if start else 0) + chunk, side="right"))
        stop = max(stop, start + 1)
        cnt = counts[start:stop]
        tri = np.repeat(np.arange(start, stop), cnt)
        local = np.arange(len(tri)) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        ww = w[tri]
        py = local // ww
        px = x0[tri] + (local - py * ww)
        py += y0[tri]
        fx, fy = px + 0.5, py + 0.5
        inside = np.ones(len(tri), bool)
        for a, b, c in edges:
            inside &= a[tri] * fx + b[tri] * fy + c[tri] >= -1e-9
        tri, px, py, fx, fy = tri[inside], px[inside], py[inside], fx[inside], fy[inside]
        pix.append(py * width + px)
        depth.append(ZA[tri] * fx + ZB[tri] * fy + ZC[tri])
        owner.append(keep[tri])
        start = stop
    if not pix:
        return np.zeros(0, np.int64), np.zeros(0), np.zeros(0, np.int64)
    return np.concatenate(pix), np.concatenate(depth), np.concatenate(owner)


class Renderer:
    """Draws frames of one scene from one camera; reuse it for many frames."""

    def __init__(self, shapes: Sequence[Mapping[str, Any] | None], fixed: npt.NDArray[np.bool_], *,
                 bounds: tuple[F64, F64], size: tuple[int, int] = (640, 480),
                 camera: Camera | Mapping[str, Any] | None = None, colors: Any = None,
                 particle_radius: F64 | None = None, shadows: bool = True, fog: bool = True,
                 detail: int = 2, first_pose: tuple[F64, F64] | None = None) -> None:
        width, height = int(size[0]), int(size[1])
        if width < 1 or height < 1:
            raise ValueError(f"size must be two positive integers (width, height), got {size}")
        self.width, self.height = width, height
        pr = np.zeros(0) if particle_radius is None else np.asarray(particle_radius, float)
        self.scene = _Scene(shapes, fixed, colors, pr, detail)
        self.camera = _camera(camera, *bounds, width / height)
        self.eye, self.fwd, self.right, self.up = self.camera.basis()
        self.focal = 0.5 * height / np.tan(np.radians(self.camera.fov) / 2)
        self.near = 1e-3 * max(float(np.linalg.norm(bounds[1] - bounds[0])), 1e-3)
        sun = -0.5 * self.right - 0.35 * self.fwd + np.array([0.0, 0.0, 1.0])
        self.light = -sun / np.linalg.norm(sun)  # the direction light travels
        self.shadows, self.fog = shadows, fog
        self.fog_far = 4.0 * float(np.linalg.norm(self.eye - np.asarray(self.camera.target, float))) + 1e-9
        self._background_key: Any = None
        self._bg: tuple[F64, F64, npt.NDArray[np.bool_], F64 | None] = (np.zeros(0), np.zeros(0), np.zeros(0, bool), None)
        self._bg_u8 = np.zeros((0, 3), np.uint8)

    # Screen space: x right, y down, in pixels; depth along the view direction.
    def project(self, p: F64) -> tuple[F64, F64]:
        rel = p - self.eye
        d = rel @ self.fwd
        safe = np.where(d > self.near, d, self.near)
        x = self.width / 2 + self.focal * (rel @ self.right) / safe
        y = self.height / 2 - self.focal * (rel @ self.up) / safe
        return np.stack([x, y], axis=-1), d

    def _fogged(self, rgb: F64, depth: F64) -> F64:
        if not self.fog:
            return rgb
        a = np.clip(depth / self.fog_far, 0.0, 1.0)[..., None] ** 1.5
        return rgb * (1 - a) + SKY_HORIZON * a

    def _background(self, planes: list[tuple[F64, float]]) -> tuple[F64, F64, npt.NDArray[np.bool_], F64 | None]:
        """Sky and the (first) ground plane per pixel: colour (H·W, 3), 1/depth (0 for sky),
        ground mask, and the ground's (normal, offset) used for shadows."""
        key = tuple((tuple(n), o) for n, o in planes)
        if key == self._background_key:
            return self._bg
        h, w = self.height, self.width
        jj, ii = np.mgrid[0:h, 0:w]
        u = (ii + 0.5 - w / 2) / self.focal
        v = -(jj + 0.5 - h / 2) / self.focal
        ray = self.fwd + u[..., None] * self.right + v[..., None] * self.up  # depth 1 along fwd
        ray = ray.reshape(-1, 3)
        elev = np.clip(ray[:, 2] / np.linalg.norm(ray, axis=1), 0.0, 1.0)[:, None]
        rgb = SKY_HORIZON * (1 - elev) ** 2 + SKY_TOP * (1 - (1 - elev) ** 2)
        iz = np.zeros(h * w)
        ground = np.zeros(h * w, bool)
        best = np.full(h * w, np.inf)
        main = None
        for n, off in planes:
            side = float(n @ self.eye) - off
            if side <= 0:  # the eye is inside the solid: this plane hides nothing we see
                continue
            denom = ray @ n
            t = np.where(denom < -1e-12, -side / np.where(denom < -1e-12, denom, -1.0), np.inf)
            hit = t < best
            if not hit.any():
                continue
            if main is None:
                main = (n, off)
            best = np.where(hit, t, best)
            p = self.eye + t[hit, None] * ray[hit]
            a = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
            a /= np.linalg.norm(a)
            b = np.cross(n, a)
            tile = self._tile
            checker = (np.floor(p @ a / tile) + np.floor(p @ b / tile)).astype(np.int64) & 1
            base = np.where(checker[:, None] == 1, 0.80, 0.68) * np.ones(3)
            shade = AMBIENT + DIFFUSE * max(0.0, float(-(n @ self.light)))
            rgb[hit] = self._fogged(base * shade, t[hit])
            iz[hit] = 1.0 / t[hit]
            ground |= hit
        self._background_key = key
        self._bg = (rgb, iz, ground, None if main is None else np.concatenate([main[0], [main[1]]]))
        self._bg_u8 = _u8(rgb)
        return self._bg

    def frame(self, pos: F64, quat: F64, particles: F64 | None = None) -> npt.NDArray[np.uint8]:
        """One picture (H, W, 3) uint8 of the bodies at ``pos`` (N, 3), ``quat`` (N, 4)."""
        h, w = self.height, self.width
        rgb, zbuf, ground, plane = self._background(self.scene.plane_world(pos, quat))
        # The picture is assembled in bytes: the background's bytes, then the shadowed
        # ground and the bodies' pixels converted alone (a float frame costs more).
        img = self._bg_u8.copy()
        verts, tris, color, two = self.scene.triangles(pos, quat, particles)
        if len(tris) == 0:
            return img.reshape(h, w, 3)
        vxy, vd = self.project(verts)
        tri = verts[tris]
        normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
        facing = np.einsum("ij,ij->i", normal, tri[:, 0] - self.eye) < 0
        normal = np.where((two & ~facing)[:, None], -normal, normal)
        if plane is not None and self.shadows:
            self._shadow(img, rgb, ground, verts, tris, normal, plane)
        front = vd > self.near
        sel = np.nonzero((facing | two) & front[tris[:, 0]] & front[tris[:, 1]] & front[tris[:, 2]])[0]
        t = tris[sel]
        lit = AMBIENT + DIFFUSE * np.clip(-(normal[sel] @ self.light), 0.0, 1.0)
        shade = color[sel] * lit[:, None]
        pix, iz, k = _rasterize(vxy[t], 1.0 / vd[t], w, h)
        best = zbuf.copy()
        np.maximum.at(best, pix, iz)
        win = iz >= best[pix]
        win &= iz > zbuf[pix] * (1 + 1e-9)  # in front of the ground (and sky: 0)
        # Fog per pixel, from its own depth: a large triangle shows no seam.
        img[pix[win]] = _u8(self._fogged(shade[k[win]], 1.0 / iz[win]))
        return img.reshape(h, w, 3)

    def _shadow(self, img: npt.NDArray[np.uint8], rgb: F64, ground: npt.NDArray[np.bool_], verts: F64, tris: I64, normal: F64,
                plane: F64) -> None:
        """Darkens the ground where the bodies' triangles that face the light project onto it."""
        n, off = plane[:3], plane[3]
        along = float(n @ self.light)
        if along >= -1e-6:  # light grazing or from below the ground: no shadow
            return
        height_above = verts @ n - off
        flat = verts - (height_above / along)[:, None] * self.light
        xy, d = self.project(flat)
        ok = (d > self.near) & (height_above > -1e-9)
        t = tris[((normal @ self.light) < 0) & ok[tris[:, 0]] & ok[tris[:, 1]] & ok[tris[:, 2]]]
        pix, _, _ = _rasterize(xy[t], np.ones(t.shape), self.width, self.height)
        mask = np.zeros(len(rgb), bool)
        mask[pix] = True
        mask &= ground
        img[mask] = _u8(rgb[mask] * (0.55 + 0.45 * AMBIENT))

    @property
    def _tile(self) -> float:
        span = float(np.linalg.norm(self.eye - np.asarray(self.camera.target, float)))
        return float(10 ** np.floor(np.log10(max(span / 4, 1e-6))))


def _u8(rgb: F64) -> npt.NDArray[np.uint8]:
    return np.asarray(np.clip(rgb * 255 + 0.5, 0, 255).astype(np.uint8))


def write_png(path: str | os.PathLike[str], image: npt.ArrayLike) -> None:
    """Writes an (H, W, 3) uint8 image as a PNG (zlib, no other dependency), through a
    temporary file and a rename."""
    img = np.ascontiguousarray(image, dtype=np.uint8)
    if img.ndim != 3 or img.shape[2] != 3:
        raise ValueError(f"image must be (H, W, 3) uint8, got shape {img.shape}")
    h, w = img.shape[:2]
    raw = np.concatenate([np.zeros((h, 1), np.uint8), img.reshape(h, w * 3)], axis=1).tobytes()

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))
    _atomic(Path(path), lambda tmp: tmp.write_bytes(png))


def _writable_folder(path: Path) -> Path:
    """The folder ``path`` would be written in, after checking that it exists and is
    writable (so a bad path fails before anything is drawn or encoded)."""
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise FileNotFoundError(f"cannot write {path}: the directory {folder} does not exist")
    if not os.access(folder, os.W_OK):
        raise PermissionError(f"cannot write {path}: the directory {folder} is not writable")
    return folder


def _atomic(path: Path, write: Any) -> None:
    """Calls ``write(tmp)`` for a temporary file next to ``path`` (same suffix), then renames
    it to ``path``; on any failure the temporary file is removed and ``OSError`` names the path."""
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise FileNotFoundError(f"cannot write {path}: the directory {folder} does not exist")
    try:
        fd, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=path.suffix, dir=folder)
    except OSError as e:
        raise OSError(f"cannot write {path}: {e}") from e
    os.close(fd)
    tmp = Path(name)
    try:
        write(tmp)
        # mkstemp makes the file private (0600); give it the permissions a plain open() would.
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(tmp, 0o666 & ~mask)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def _imageio() -> Any:
    try:
        import imageio.v2 as iio
    except ImportError as e:
        raise ImportError('writing GIF or MP4 needs imageio: pip install "rigidrs[video]"') from e
    return iio


def _source(obj: Any) -> tuple[Any, Any]:
    """(world, shapes) of a World or a Scene (a scene is built once, to read its state)."""
    from .. import Scene, World

    if isinstance(obj, World):
        return obj, obj.shapes()
    if isinstance(obj, Scene):
        world = obj.build(dt=0.01)
        return world, world.shapes()
    raise TypeError(f"render needs a rigidrs World or Scene, got {type(obj).__name__}")


def _bounds(shapes: Sequence[Mapping[str, Any] | None], pos: F64, quat: F64, particles: F64 | None) -> tuple[F64, F64]:
    """Bounding box over the frames of every finite shape and particle (planes excluded)."""
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for i, d in enumerate(shapes):
        if d is None or d["kind"] == "Plane":
            continue
        v, _ = shape_mesh(d, 0)
        local_lo, local_hi = v.min(0), v.max(0)
        r = float(np.linalg.norm(local_hi - local_lo)) / 2
        c = (local_lo + local_hi) / 2
        centres = pos[:, i] + np.einsum("tij,j->ti", quat_matrix(quat[:, i]), c)
        lo = np.minimum(lo, centres.min(0) - r)
        hi = np.maximum(hi, centres.max(0) + r)
    if particles is not None and particles.size:
        lo = np.minimum(lo, particles.reshape(-1, 3).min(0))
        hi = np.maximum(hi, particles.reshape(-1, 3).max(0))
    if not np.all(np.isfinite(lo)):
        lo, hi = np.full(3, -1.0), np.full(3, 1.0)
    return lo, hi


def render(source: Any, rec: Any = None, path: str | os.PathLike[str] | None = None, *,
           size: tuple[int, int] = (640, 480), camera: Camera | Mapping[str, Any] | None = None,
           fps: float = 30.0, speed: float = 1.0, frame: int = -1, colors: Any = None,
           shadows: bool = True, fog: bool = True, detail: int = 2, antialias: int = 1) -> Any:
    """Draws ``source`` (a World or Scene) at the states of ``rec`` (a Recording), or its
    current state (a Scene: its initial state) without one.

    ``path`` decides the output (a temporary file renamed at the end: on failure none is
    left): ``.png`` one picture (frame ``frame`` of the recording, default the last), or
    one PNG per frame when the name holds a ``{}`` field (``"out/f{:04d}.png"``); ``.gif``
    and ``.mp4`` an animation (``pip install "rigidrs[video]"``). Without ``path`` the
    picture (H, W, 3) uint8 is returned. ``render(world, "x.png")`` also works.
    ``size`` (width, height) in pixels, default (640, 480) (MP4 wants even numbers).
    ``camera``: a :class:`Camera` or a dict of its fields; default: frames the bounding
    box of the bodies over the recording (planes excluded). ``fps`` frames per second of
    an animation (default 30); ``speed`` simulated seconds per second of video (default 1):
    recording frames are picked to match, each used at most once. ``colors``: (3,) for every
    body, (N, 3), or {body: (3,)}, RGB in 0..1 or 0..255; default a palette, fixed bodies
    grey. ``shadows`` projects the bodies on the ground plane (the scene's first plane seen
    from above); ``fog`` fades distant things to the horizon colour; ``detail`` (0..3,
    default 2) subdivides spheres, cylinders, cones and capsules; ``antialias`` (1..4,
    default 1) renders that many samples per pixel along each axis and averages them
    (costs its square in time). Identical consecutive GIF frames are merged by the GIF
    writer (their durations add up). Returns the path written.
    """
    if isinstance(rec, (str, os.PathLike)) and path is None:
        rec, path = None, rec
    if path is not None:
        path = Path(path)
        suffix = path.suffix.lower()
        if suffix not in FORMATS:
            raise ValueError(f"cannot write {path}: unknown format {path.suffix!r}; use one of {', '.join(FORMATS)}")
        if suffix in (".gif", ".mp4"):
            iio = _imageio()
            if suffix == ".mp4":
                try:
                    import imageio_ffmpeg  # type: ignore[import-untyped]  # noqa: F401
                except ImportError as e:
                    raise ImportError('writing MP4 needs imageio-ffmpeg: pip install "rigidrs[video]"') from e
        _writable_folder(path)
    if antialias not in (1, 2, 3, 4):
        raise ValueError(f"antialias must be 1, 2, 3 or 4, got {antialias!r}")
    if not (fps > 0 and np.isfinite(fps)) or not (speed > 0 and np.isfinite(speed)):
        raise ValueError(f"fps and speed must be positive, got fps={fps}, speed={speed}")
    world, shapes = _source(source)
    n = len(shapes)
    if rec is None:
        pos = np.array(world.bodies.position)[None]
        quat = np.array(world.bodies.orientation)[None]
        parts = np.array(world.particles.position)[None]
        times = np.zeros(1)
    else:
        from .. import Recording

        if not isinstance(rec, Recording):
            raise TypeError(f"rec must be a rigidrs Recording or None, got {type(rec).__name__}")
        pos, quat, parts, times = rec.position, rec.orientation, rec.particle_position, rec.times
        if pos.shape[1] != n or parts.shape[1] != len(world.particles.position):
            raise ValueError(f"the recording does not match the scene: {pos.shape[1]} bodies and "
                             f"{parts.shape[1]} particles recorded, the scene has {n} and "
                             f"{len(world.particles.position)}")
        if len(times) == 0:
            raise ValueError("the recording has no frames")
    has_particles = parts.shape[1] > 0
    fixed = ~(np.asarray(world.bodies.inverse_mass) > 0)
    r = Renderer(shapes, fixed, bounds=_bounds(shapes, pos, quat, parts if has_particles else None),
                 size=(int(size[0]) * antialias, int(size[1]) * antialias), camera=camera, colors=colors,
                 particle_radius=np.array(world.particles.radius) if has_particles else None,
                 shadows=shadows, fog=fog, detail=detail)

    def draw(k: int) -> npt.NDArray[np.uint8]:
        img = r.frame(pos[k], quat[k], parts[k] if has_particles else None)
        if antialias == 1:
            return img
        a, h, w = antialias, r.height // antialias, r.width // antialias
        return np.asarray(img.reshape(h, a, w, a, 3).mean(axis=(1, 3)).round().astype(np.uint8))

    if path is None:
        return draw(frame)
    if suffix == ".png":
        if "{" in path.name:
            for k in range(len(times)):
                write_png(path.with_name(path.name.format(k)), draw(k))
        else:
            write_png(path, draw(frame))
        return path
    picks = _picks(times, fps, speed)
    frames = [draw(k) for k in picks]
    if suffix == ".gif":
        _atomic(path, lambda tmp: iio.mimsave(tmp, frames, format="GIF", duration=1000.0 / fps, loop=0))
    else:
        _atomic(path, lambda tmp: iio.mimsave(tmp, frames, format="FFMPEG", fps=fps, codec="libx264",
                                              macro_block_size=2, quality=7))
    return path


def _picks(times: F64, fps: float, speed: float) -> list[int]:
    """Recording frames to show at ``fps`` frames per second of video, ``speed`` simulated
    seconds per second: the first frame at or after each video time."""
    t = np.asarray(times, float)
    if len(t) == 1:
        return [0]
    want = t[0] + np.arange(0.0, t[-1] - t[0] + 1e-12, speed / fps)
    picks = np.unique(np.clip(np.searchsorted(t, want - 1e-9), 0, len(t) - 1))
    return [int(k) for k in picks]
