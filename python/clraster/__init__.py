"""clraster: a graphics pipeline written as OpenCL kernels, from Python.

Meshes and cameras in as numpy arrays (or anything that speaks DLPack), batches of pictures and
visibility buffers out as numpy arrays, on any OpenCL device (PoCL runs it on the CPU)::

    import clraster
    ctx = clraster.Context()
    mesh = clraster.load("model.glb")
    views = clraster.look_at(eyes, target=(0, 0, 0))             # (B, 4, 4)
    projection = clraster.perspective(45, 256 / 256, 0.1, 100)  # (4, 4)
    pictures = ctx.render(mesh, views, projection, size=(256, 256))  # uint8 (B, 256, 256, 4)

docs/python.md describes the API. Matrices are numpy's (row-major, ``clip = P @ V @ p``) with
OpenGL's conventions, as the command line's camera; pictures have row 0 at the top.
"""

import dataclasses
import operator
import os
import warnings

import numpy as np

from . import _clraster
from ._clraster import BuildError, Device, DeviceError, Error, InvalidArgument

__all__ = [
    "BuildError", "Context", "Device", "DeviceError", "Error", "InvalidArgument", "Mesh", "TrianglesDroppedWarning",
    "VisibilityBuffer", "devices", "interpolate", "load", "look_at", "perspective", "version",
]

for _exception in (Error, DeviceError, BuildError, InvalidArgument, Device):
    _exception.__module__ = __name__

__version__ = _clraster.version()

SHADINGS = ("normal", "lambert", "depth", "overdraw")
DEFAULT_MEMORY_CAP = 256 << 20


class TrianglesDroppedWarning(RuntimeWarning):
    """Triangles with a NaN or infinite value at a corner were left out; the rest is drawn."""


def version():
    """The library's version, "major.minor.patch"."""
    return _clraster.version()


def devices():
    """Every OpenCL device of every platform, in the order Context(device=N) counts them."""
    return _clraster.devices()


# ---- Arrays in: checked here, so that the extension only ever sees what it expects ----

def _as_array(name, value):
    """`value` as a numpy array without a copy: numpy arrays as they are, DLPack producers (JAX,
    torch, ...) through np.from_dlpack, anything else through np.asarray."""
    if isinstance(value, np.ndarray):
        return value
    if hasattr(value, "__dlpack__"):
        try:
            return np.from_dlpack(value)
        except (BufferError, RuntimeError, TypeError, ValueError) as error:
            raise ValueError(f"{name}: numpy cannot read this array in place (it must be in CPU memory): {error}") from None
    return np.asarray(value)


def _shape_text(shape):
    return "(" + ", ".join("N" if side is None else str(side) for side in shape) + ("," if len(shape) == 1 else "") + ")"


def _checked(name, value, dtypes, shape):
    """`value` as a numpy array of one of `dtypes` and of `shape` (None: any length), C-contiguous;
    else ValueError saying which of these it is not."""
    array = _as_array(name, value)
    if array.dtype not in dtypes:
        expected = " or ".join(np.dtype(d).name for d in dtypes)
        raise ValueError(f"{name} must be {expected}, got {array.dtype}")
    if array.ndim != len(shape) or any(want is not None and got != want for got, want in zip(array.shape, shape)):
        raise ValueError(f"{name} must have shape {_shape_text(shape)}, got {tuple(array.shape)}")
    if not array.flags.c_contiguous:
        raise ValueError(f"{name} must be C-contiguous (row-major, without strides); np.ascontiguousarray({name}) "
                         "makes such a copy")
    return array


def _matrices(name, value):
    """A (4, 4) or (B, 4, 4) array of finite numbers as float32 (B, 4, 4), and whether it was one."""
    array = _as_array(name, value)
    if not (np.issubdtype(array.dtype, np.floating) or np.issubdtype(array.dtype, np.integer)):
        raise ValueError(f"{name} must be an array of numbers, got {array.dtype}")
    if array.shape == (4, 4):
        array = array[None]
    elif array.ndim != 3 or array.shape[1:] != (4, 4) or array.shape[0] == 0:
        raise ValueError(f"{name} must have shape (4, 4) or (B, 4, 4) with B >= 1, got {tuple(array.shape)}")
    array = np.ascontiguousarray(array, dtype=np.float32)
    if not np.isfinite(array).all():
        raise ValueError(f"{name} has NaN or infinite elements")
    return array


def _size(size):
    try:
        width, height = (operator.index(side) for side in size)
    except (TypeError, ValueError):
        raise ValueError(f"size must be (width, height), two integers, got {size!r}") from None
    return width, height


def _output(name, out, dtype, shape):
    """The caller's `out=` array, checked, or a new one."""
    if out is None:
        return np.empty(shape, dtype)
    if not isinstance(out, np.ndarray):
        raise ValueError(f"{name} must be a numpy array, got {type(out).__name__}")
    out = _checked(name, out, (dtype,), shape)
    if not out.flags.writeable:
        raise ValueError(f"{name} is read-only")
    return out


def _warn_dropped_by_pipeline(count):
    if count:
        warnings.warn(f"{count} {'triangle' if count == 1 else 'triangles'} dropped: a clip coordinate is NaN "
                      "or infinite", TrianglesDroppedWarning, stacklevel=3)


# ---- Meshes and cameras ----

class Mesh:
    """An indexed triangle mesh: positions float32 (N, 3), indices int32 or uint32 (M, 3), and
    optionally normals float32 (N, 3) and texture coordinates float32 (N, 2).

    The mesh keeps a copy of the arrays (read-only numpy arrays as its properties) and each context
    uploads it once. Triangles with a NaN or infinite position, normal or texture coordinate at a
    corner are not drawn, with a TrianglesDroppedWarning, as the command line drops them; triangle
    indices (VisibilityBuffer.triangle) still count every triangle. Without normals, each vertex
    gets the area-weighted normal of the faces around its position, as the command line gives files
    without normals.
    """

    def __init__(self, positions, indices, normals=None, uvs=None):
        positions = _checked("positions", positions, (np.float32,), (None, 3))
        indices = _checked("indices", indices, (np.int32, np.uint32), (None, 3))
        if indices.dtype == np.int32 and indices.size and indices.min() < 0:
            triangle = int(np.argmax((indices < 0).any(axis=1)))
            raise ValueError(f"indices: triangle {triangle} has the negative index {indices[triangle].min()}")
        if normals is not None:
            normals = _checked("normals", normals, (np.float32,), (len(positions), 3))
        if uvs is not None:
            uvs = _checked("uvs", uvs, (np.float32,), (len(positions), 2))
        self._mesh = _clraster.Mesh(positions, indices.view(np.uint32), normals, uvs)
        if self._mesh.triangles_dropped:
            warnings.warn(_clraster.describe_triangles_dropped(self._mesh.triangles_dropped), TrianglesDroppedWarning,
                          stacklevel=2)

    @classmethod
    def _of(cls, handle):
        mesh = cls.__new__(cls)
        mesh._mesh = handle
        return mesh

    positions = property(lambda self: self._mesh.positions, doc="float32 (N, 3), read-only")
    indices = property(lambda self: self._mesh.indices, doc="uint32 (M, 3): the triangles, read-only")
    normals = property(lambda self: self._mesh.normals, doc="float32 (N, 3), read-only")
    uvs = property(lambda self: self._mesh.uvs, doc="float32 (N, 2) texture coordinates, or None")
    materials = property(lambda self: self._mesh.materials,
                         doc="a loaded model's materials: dicts of name, base_color (linear RGBA) and texture")

    def __repr__(self):
        return f"<clraster.Mesh of {len(self.positions)} vertices, {len(self.indices)} triangles>"


def load(path):
    """A model file, as the command line loads it (assimp: OBJ, glTF 2.0, PLY, STL, OFF, ...): node
    transforms applied, normals from the file or computed, the first set of texture coordinates,
    materials. What the command line prints as warnings are Python warnings."""
    handle, messages = _clraster.load(os.fspath(path))
    for message in messages:
        category = TrianglesDroppedWarning if "triangles dropped" in message or "triangle dropped" in message else UserWarning
        warnings.warn(message, category, stacklevel=2)
    return Mesh._of(handle)


def _points(name, value):
    array = _as_array(name, value)
    if not (np.issubdtype(array.dtype, np.floating) or np.issubdtype(array.dtype, np.integer)):
        raise ValueError(f"{name} must be numbers, got {array.dtype}")
    if array.shape != (3,) and (array.ndim != 2 or array.shape[1] != 3):
        raise ValueError(f"{name} must have shape (3,) or (B, 3), got {tuple(array.shape)}")
    return array.astype(np.float32)


def look_at(eye, target, up=(0, 1, 0)):
    """View matrices as gluLookAt (and the command line's --eye, --target, --up): float32 (B, 4, 4)
    for eyes (B, 3), or (4, 4) for one eye (3,). `target` and `up` are (3,) or one per eye."""
    eye, target, up = _points("eye", eye), _points("target", target), _points("up", up)
    single = eye.ndim == 1
    try:
        eyes, targets, ups = np.broadcast_arrays(np.atleast_2d(eye), np.atleast_2d(target), np.atleast_2d(up))
    except ValueError:
        raise ValueError(f"eye, target and up must have the same number of points: {eye.shape}, {target.shape}, "
                         f"{up.shape}") from None
    out = np.empty((len(eyes), 4, 4), np.float32)
    _clraster.look_at(np.ascontiguousarray(eyes), np.ascontiguousarray(targets), np.ascontiguousarray(ups), out)
    return out[0] if single and len(out) == 1 else out


def perspective(fov_y_degrees, aspect, near, far):
    """A projection matrix as gluPerspective (and the command line's --fov, --near, --far):
    float32 (4, 4), clip z from -w at `near` to w at `far`; aspect = width / height."""
    out = np.empty((4, 4), np.float32)
    _clraster.perspective(float(fov_y_degrees), float(aspect), float(near), float(far), out)
    return out


def _depth_range(projection):
    """The view distances a perspective or orthographic projection maps to clip z = -w and w: what
    shading="depth" draws white and black, as the command line's near and far planes."""
    p = projection.astype(np.float64)
    if p[3, 2] != 0:  # perspective: z_clip = p22 z + p23, w = -z
        near, far = p[2, 3] / (p[2, 2] - 1), p[2, 3] / (p[2, 2] + 1)
    else:  # orthographic: z_clip = p22 z + p23, w = 1
        near, far = (p[2, 3] + 1) / p[2, 2], (p[2, 3] - 1) / p[2, 2]
    return float(near), float(far)


# ---- Rendering ----

@dataclasses.dataclass(frozen=True)
class VisibilityBuffer:
    """What Context.rasterize gives, per view and pixel (rows from the top):

    - triangle: int32 (B, H, W), the index of the mesh triangle drawn there, -1 where none is;
    - barycentric: float32 (B, H, W, 2), the perspective-correct weights of the triangle's first
      and second corners (the third's is 1 - both), 0 where empty;
    - depth: float32 (B, H, W), window-space depth in [0, 1], 1 where empty.
    """

    triangle: np.ndarray
    barycentric: np.ndarray
    depth: np.ndarray

    def to_nvdiffrast(self):
        """nvdiffrast's rasterizer output: float32 (B, H, W, 4) of (u, v, z/w, triangle + 1), rows
        from the bottom, zeros where empty; z/w is normalized device depth, 2 * depth - 1."""
        covered = self.triangle >= 0
        out = np.zeros(self.triangle.shape + (4,), np.float32)
        out[..., :2] = self.barycentric
        out[..., 2] = np.where(covered, 2 * self.depth - 1, 0)
        out[..., 3] = self.triangle + 1
        return np.ascontiguousarray(out[:, ::-1])


class Context:
    """An OpenCL device with its compiled programs and memory. `device`: an index into devices();
    None takes $CLRASTER_DEVICE, else device 0. `memory_cap`: bytes of the pipeline's intermediate
    buffers (larger draws go in chunks). Calls release the GIL; a context draws one call at a time,
    so threads that draw in parallel each want their own."""

    def __init__(self, device=None, memory_cap=DEFAULT_MEMORY_CAP):
        index = -1 if device is None else operator.index(device)
        if index < -1:
            raise ValueError(f"device must be None or an index into clraster.devices(), got {device}")
        self._context = _clraster.Context(index, operator.index(memory_cap))

    @property
    def device(self):
        return self._context.device

    def __repr__(self):
        return f"<clraster.Context on {self.device!r}>"

    def render(self, mesh, view, projection, size, shading="normal", *, depth_range=None, out=None):
        """Pictures of `mesh`, one per view: uint8 (B, H, W, 4) RGBA, row 0 at the top, for
        `view` (4, 4) (B = 1) or (B, 4, 4), `projection` (4, 4) and size = (W, H). `shading` is
        one of the command line's: "normal", "lambert", "depth" (view distances from
        `depth_range`, by default the projection's near and far planes), "overdraw". One view's
        picture is the command line's for the same camera, byte for byte. `out`: an array of that
        shape and dtype to draw into instead of a new one."""
        if not isinstance(mesh, Mesh):
            raise ValueError(f"mesh must be a clraster.Mesh, got {type(mesh).__name__}")
        if shading not in SHADINGS:
            raise ValueError(f"shading must be one of {', '.join(SHADINGS)}, got {shading!r}")
        views = _matrices("view", view)
        projection = _matrices("projection", projection)
        if len(projection) != 1:
            raise ValueError(f"projection must have shape (4, 4), got {tuple(np.shape(projection))}")
        width, height = _size(size)
        if depth_range is None:
            depth_range = _depth_range(projection[0])
        out = _output("out", out, np.uint8, (len(views), height, width, 4))
        dropped = self._context.render(mesh._mesh, views, projection[0], shading, tuple(map(float, depth_range)), out)
        _warn_dropped_by_pipeline(dropped)
        return out

    def rasterize(self, mesh, view, projection, size):
        """The visibility buffer of `mesh` for each view (a VisibilityBuffer of B pictures), with
        the cameras and size of render(): the pixels it covers are exactly those render draws."""
        if not isinstance(mesh, Mesh):
            raise ValueError(f"mesh must be a clraster.Mesh, got {type(mesh).__name__}")
        views = _matrices("view", view)
        projection = _matrices("projection", projection)
        if len(projection) != 1:
            raise ValueError(f"projection must have shape (4, 4), got {tuple(np.shape(projection))}")
        width, height = _size(size)
        triangle = np.empty((len(views), height, width), np.int32)
        barycentric = np.empty((len(views), height, width, 2), np.float32)
        depth = np.empty((len(views), height, width), np.float32)
        dropped = self._context.rasterize(mesh._mesh, views, projection[0], triangle, barycentric, depth)
        _warn_dropped_by_pipeline(dropped)
        return VisibilityBuffer(triangle, barycentric, depth)


def interpolate(attributes, vb, mesh):
    """Per-vertex `attributes` (N, C), or (B, N, C) one set per view, interpolated over the
    visibility buffer `vb` of `mesh` with its barycentrics: float32 (B, H, W, C), 0 where empty."""
    if not isinstance(vb, VisibilityBuffer):
        raise ValueError(f"vb must be a clraster.VisibilityBuffer, got {type(vb).__name__}")
    if not isinstance(mesh, Mesh):
        raise ValueError(f"mesh must be a clraster.Mesh, got {type(mesh).__name__}")
    attributes = _as_array("attributes", attributes)
    vertex_count = len(mesh.positions)
    views = len(vb.triangle)
    if attributes.ndim == 2:
        attributes = attributes[None]
    if attributes.ndim != 3 or attributes.shape[1] != vertex_count or attributes.shape[0] not in (1, views):
        raise ValueError(f"attributes must have shape ({vertex_count}, C) or ({views}, {vertex_count}, C) for this "
                         f"mesh and visibility buffer, got {tuple(np.shape(attributes))}")
    covered = vb.triangle >= 0
    corners = mesh.indices[np.where(covered, vb.triangle, 0)]  # (B, H, W, 3)
    per_view = np.arange(views).reshape(-1, 1, 1, 1) if attributes.shape[0] == views else 0
    values = attributes[per_view, corners].astype(np.float32, copy=False)  # (B, H, W, 3, C)
    u, v = vb.barycentric[..., 0:1], vb.barycentric[..., 1:2]
    result = values[..., 0, :] * u + values[..., 1, :] * v + values[..., 2, :] * (1 - u - v)
    return np.where(covered[..., None], result, np.float32(0))
