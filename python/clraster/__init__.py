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
import re
import warnings

import numpy as np

from . import _clraster
from ._clraster import BuildError, Device, DeviceError, Error, InvalidArgument

__all__ = [
    "BuildError", "Context", "Device", "DeviceError", "Error", "InvalidArgument", "Mesh", "Program",
    "TrianglesDroppedWarning", "VisibilityBuffer", "devices", "interpolate", "load", "look_at", "perspective",
    "texture", "version",
]

for _exception in (Error, DeviceError, BuildError, InvalidArgument, Device):
    _exception.__module__ = __name__

__version__ = _clraster.version()

SHADINGS = ("normal", "lambert", "depth", "overdraw", "material")
_BUILTIN_SHADINGS = SHADINGS[:4]  # the library's own programs; "material" is programs/material.cl
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


def _indices(name, value):
    """Triangles, int32 or uint32 (M, 3) without negative indices, as uint32 (the same bytes)."""
    indices = _checked(name, value, (np.int32, np.uint32), (None, 3))
    if indices.dtype == np.int32 and indices.size and indices.min() < 0:
        triangle = int(np.argmax((indices < 0).any(axis=1)))
        raise ValueError(f"{name}: triangle {triangle} has the negative index {indices[triangle].min()}")
    return indices.view(np.uint32)


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
        indices = _indices("indices", indices)
        if normals is not None:
            normals = _checked("normals", normals, (np.float32,), (len(positions), 3))
        if uvs is not None:
            uvs = _checked("uvs", uvs, (np.float32,), (len(positions), 2))
        self._mesh = _clraster.Mesh(positions, indices, normals, uvs)
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
    - depth: float32 (B, H, W), window-space depth in [0, 1], 1 where empty;
    - positions: float32 (N, 4) or (B, N, 4), homogeneous vertex positions, and mvp: float32
      (B, 4, 4), the matrix of each view that takes them to clip space: the mesh's positions with
      w = 1 and projection @ view, or the clip positions given and the identity. interpolate's
      derivatives come from these.
    """

    triangle: np.ndarray
    barycentric: np.ndarray
    depth: np.ndarray
    positions: np.ndarray
    mvp: np.ndarray

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

    def render(self, mesh, view, projection, size, shading="normal", *, depth_range=None, out=None, progress=None):
        """Pictures of `mesh`, one per view: uint8 (B, H, W, 4) RGBA, row 0 at the top, for
        `view` (4, 4) (B = 1) or (B, 4, 4), `projection` (4, 4) and size = (W, H).

        `shading` is one of the command line's: "normal", "lambert", "depth" (view distances from
        `depth_range`, by default the projection's near and far planes), "overdraw", "material"
        (the mesh's materials, lit by a headlight: programs/material.cl), or a clraster.Program
        with its uniforms and textures. One view's picture is the command line's for the same
        camera, byte for byte. `out`: an array of that shape and dtype to draw into instead of a
        new one. `progress`: a progress bar over the batch's chunks (tqdm) when it takes more than
        one; None shows it when stderr is a terminal."""
        if not isinstance(mesh, Mesh):
            raise ValueError(f"mesh must be a clraster.Mesh, got {type(mesh).__name__}")
        if not isinstance(shading, Program) and shading not in SHADINGS:
            raise ValueError(f"shading must be one of {', '.join(SHADINGS)} or a clraster.Program, got {shading!r}")
        views, projection = self._camera(view, projection)
        width, height = _size(size)
        out = _output("out", out, np.uint8, (len(views), height, width, 4))
        with _ProgressBar(progress, "render") as report:
            if shading in _BUILTIN_SHADINGS:
                depth_range = _depth_range(projection) if depth_range is None else tuple(map(float, depth_range))
                dropped = self._context.render(mesh._mesh, views, projection, shading, depth_range, out, report)
                messages = []
            else:
                program = self._program_of(shading)
                uniforms, textures = ([], []) if shading == "material" else shading._own_values(len(views))
                dropped, messages = self._context.render_program(mesh._mesh, views, projection, program, uniforms,
                                                                 textures, out, report)
        for message in messages:  # materials' images that could not be used, as the command line warns
            warnings.warn(message, UserWarning, stacklevel=2)
        _warn_dropped_by_pipeline(dropped)
        return out

    def rasterize(self, mesh, view, projection=None, size=None, *, progress=None):
        """The visibility buffer of `mesh` for each view (a VisibilityBuffer of B pictures), with
        the cameras and size of render(): the pixels it covers are exactly those render draws.

        Or, as nvdiffrast's rasterize takes them, ``rasterize(clip_positions, indices, size=(W,
        H))``: clip-space positions float32 (B, N, 4) (or (N, 4): B = 1) and triangles int32 or
        uint32 (M, 3); a triangle with a NaN or infinite clip coordinate is not drawn, with a
        TrianglesDroppedWarning. `progress` as render's."""
        if isinstance(mesh, Mesh):
            views, projection = self._camera(view, projection)
            positions = np.concatenate([mesh.positions, np.ones((len(mesh.positions), 1), np.float32)], axis=1)
            mvp = projection @ views
            draw = lambda outputs, report: self._context.rasterize(mesh._mesh, views, projection, *outputs, report)
        else:
            if projection is not None:
                raise ValueError("rasterize takes a mesh, views and a projection, or clip positions and indices "
                                 "without a projection")
            positions = _as_array("clip positions", mesh)
            if positions.ndim == 2:
                positions = positions[None]
            positions = _checked("clip positions", positions, (np.float32,), (None, None, 4))
            if not len(positions) or not positions.shape[1]:
                raise ValueError(f"clip positions must have at least one view and vertex, got {positions.shape}")
            indices = _indices("indices", view)
            views = positions  # one picture per set of positions
            mvp = np.broadcast_to(np.eye(4, dtype=np.float32), (len(positions), 4, 4))
            draw = lambda outputs, report: self._context.rasterize_clip(positions, indices, *outputs, report)
        if size is None:
            raise ValueError("size must be (width, height), two integers, got None")
        width, height = _size(size)
        outputs = (np.empty((len(views), height, width), np.int32), np.empty((len(views), height, width, 2), np.float32),
                   np.empty((len(views), height, width), np.float32))
        with _ProgressBar(progress, "rasterize") as report:
            dropped = draw(outputs, report)
        _warn_dropped_by_pipeline(dropped)
        return VisibilityBuffer(*outputs, positions, mvp)

    @staticmethod
    def _camera(view, projection):
        views = _matrices("view", view)
        projection = _matrices("projection", projection)
        if len(projection) != 1:
            raise ValueError(f"projection must have shape (4, 4), got {tuple(np.shape(projection))}")
        return views, projection[0]

    def _program_of(self, shading):
        if shading == "material":
            return self._context.material_program()  # compiled by the first call, then kept
        if shading._ctx is not self:
            raise ValueError("the program was compiled for another context: programs draw on the context that "
                             "compiled them")
        return shading._program


class _ProgressBar:
    """A context manager giving the callback the extension calls after each chunk of a batch: a
    tqdm bar, made at the first call that leaves pictures to draw (a batch of one chunk shows
    none). progress None: shown when stderr is a terminal (tqdm's disable=None); False: none."""

    def __init__(self, progress, verb):
        self._enabled = progress
        self._verb = verb
        self._bar = None

    def __enter__(self):
        return None if self._enabled is False else self._report

    def _report(self, done, total):
        if self._bar is None:
            if done >= total:
                return
            from tqdm.auto import tqdm
            self._bar = tqdm(total=total, unit="view", desc=f"clraster {self._verb}",
                             disable=None if self._enabled is None else not self._enabled)
        self._bar.update(done - self._bar.n)

    def __exit__(self, *exception):
        if self._bar is not None:
            self._bar.close()


# ---- Programs of your own ----

_UNIFORM_TYPE = re.compile(r"(float|int|uint)(2|3|4|8|16)?")
_UNIFORM_DTYPES = {"float": np.float32, "int": np.int32, "uint": np.uint32}
_TEXTURE_DTYPES = (np.dtype(np.uint8), np.dtype(np.float32))  # RGBA8 (255 samples as 1.0) and RGBA32F


class Program:
    """A program of your own in OpenCL C (docs/programs.md) that Context.render draws meshes
    with: ``ctx.render(mesh, views, projection, size, shading=program)``.

    `program` is a path (a str without a newline, or a path-like object) or the source itself (a
    str with newlines). It is checked against what render binds, as the command line checks
    --program files (docs/cli.md): attributes position, normal and uv (the mesh's, (0, 0)
    without uvs); uniforms mvp, model_view, normal_matrix, projection (per view), base_color (the
    part's material), light_direction, viewport; the texture base_color_texture (the material's);
    one float4 output, the picture. Any other uniform or texture is the program's own: set it
    with ``program[name] = value`` before drawing.

    A uniform's value has the declared shape: () for float, int and uint, (n,) for their vectors,
    (4, 4) for float16 (a matrix as numpy writes it, row-major: transposed for the program),
    with (array size, ...) in front for arrays; or one more axis in front, one value per view of
    the batch. A texture's value is an image, uint8 or float32 (H, W), (H, W, 1), (H, W, 2),
    (H, W, 3) (alpha 1 added) or (H, W, 4), row 0 at the top as pictures are (t = 1 there, as the
    materials' images are mapped), sampled trilinearly from its mipmaps with repeat.
    """

    def __init__(self, ctx, program):
        if not isinstance(ctx, Context):
            raise ValueError(f"ctx must be a clraster.Context, got {type(ctx).__name__}")
        if isinstance(program, os.PathLike) or (isinstance(program, str) and "\n" not in program):
            file_name = os.fspath(program)
            source = _clraster.read_program_file(file_name)
        elif isinstance(program, str):
            source, file_name = program, "<program>"
        else:
            raise ValueError(f"program must be a path or the program's source (a str), got {type(program).__name__}")
        self._ctx = ctx
        self._program = ctx._context.compile(source, file_name)
        declared = self._program.declarations
        self._uniforms = {name: (kind, array_size, size) for name, kind, array_size, size, provided
                          in declared["uniforms"] if not provided}
        self._textures = [name for name, provided in declared["textures"] if not provided]
        self._values = {}  # name -> uniform bytes and whether one per view, or a texture

    @property
    def file_name(self):
        return self._program.file_name

    @property
    def uniforms(self):
        """The program's own uniforms (those render does not bind): name -> declared type."""
        return {name: kind + (f"[{array_size}]" if array_size else "") for name, (kind, array_size, _)
                in self._uniforms.items()}

    @property
    def textures(self):
        """The program's own textures (those render does not bind)."""
        return list(self._textures)

    def __setitem__(self, name, value):
        if name in self._uniforms:
            self._values[name] = self._uniform_bytes(name, value)
        elif name in self._textures:
            self._values[name] = self._ctx._context.texture(_texture_image(f"{self.file_name}: texture '{name}'", value))
        else:
            own = ", ".join(list(self._uniforms) + self._textures) or "none"
            raise ValueError(f"program {self.file_name} has no uniform or texture '{name}' of its own to set "
                             f"(its own: {own})")

    def _uniform_bytes(self, name, value):
        """The uniform's value in the program's layout (float3 padded to 16 bytes in arrays, float16
        column-major), and the number of views it gives values for (None: one for all)."""
        kind, array_size, size = self._uniforms[name]
        scalar, width = _UNIFORM_TYPE.fullmatch(kind).groups()
        width = int(width or 1)
        element_shape = (4, 4) if width == 16 else (() if width == 1 else (width,))
        shape = ((array_size,) if array_size else ()) + element_shape
        where = f"program {self.file_name}: uniform '{name}' ({self.uniforms[name]})"
        array = _as_array(where, value)
        if not (np.issubdtype(array.dtype, np.number) or array.dtype == np.bool_):
            raise ValueError(f"{where} takes numbers, got {array.dtype}")
        if array.shape == shape:
            views = None
        elif array.ndim == len(shape) + 1 and array.shape[1:] == shape and len(array):
            views = len(array)
        else:
            wanted = _shape_text(shape) if shape else "() (a number)"
            raise ValueError(f"{where} must have shape {wanted}, or (B,) + that for one per view, got {array.shape}")
        dtype = np.dtype(_UNIFORM_DTYPES[scalar])
        if scalar != "float":
            if not (np.issubdtype(array.dtype, np.integer) or array.dtype == np.bool_):
                raise ValueError(f"{where} takes integers, got {array.dtype}")
            limits = np.iinfo(dtype)
            if array.size and (array.min() < limits.min or array.max() > limits.max):
                raise ValueError(f"{where}: values must be within {limits.min}..{limits.max}")
        values = array.astype(dtype)
        if width == 16:
            values = np.swapaxes(values, -1, -2)  # row-major numpy matrices, column-major uniforms
        values = values.reshape(views or 1, max(array_size, 1), width)
        stride = size // max(array_size, 1) // dtype.itemsize  # components of an element, padding included
        padded = np.zeros(values.shape[:2] + (stride,), dtype)
        padded[..., :width] = values
        return padded.tobytes(), views

    def _own_values(self, views):
        """What render_program takes: [(name, bytes, one per view)], [(name, texture)]; ValueError
        for what is not set, or set for another number of views."""
        unset = [name for name in list(self._uniforms) + self._textures if name not in self._values]
        if unset:
            raise ValueError(f"program {self.file_name}: {', '.join(repr(n) for n in unset)} not set: "
                             f"program[name] = value sets {'it' if len(unset) == 1 else 'them'}")
        uniforms = []
        for name in self._uniforms:
            data, count = self._values[name]
            if count is not None and count != views:
                raise ValueError(f"program {self.file_name}: uniform '{name}' has values for {count} views, "
                                 f"the batch has {views}")
            uniforms.append((name, data, count is not None))
        return uniforms, [(name, self._values[name]) for name in self._textures]

    def __repr__(self):
        return f"<clraster.Program {self.file_name}>"


def _texture_image(where, value):
    """An image as the extension takes textures: C-contiguous (H, W, 1, 2 or 4) of uint8 or float32."""
    image = _as_array(where, value)
    if image.dtype not in _TEXTURE_DTYPES:
        raise ValueError(f"{where} must be uint8 or float32, got {image.dtype}")
    if image.ndim == 2:
        image = image[..., None]
    if image.ndim != 3 or image.shape[2] not in (1, 2, 3, 4):
        raise ValueError(f"{where} must have shape (H, W) or (H, W, C) with C 1..4, got {image.shape}")
    if not (1 <= image.shape[0] <= _clraster.MAX_TEXTURE_SIZE and 1 <= image.shape[1] <= _clraster.MAX_TEXTURE_SIZE):
        raise ValueError(f"{where}: each side must be 1..{_clraster.MAX_TEXTURE_SIZE}, got {image.shape[:2]}")
    if image.shape[2] == 3:
        opaque = np.full(image.shape[:2] + (1,), 255 if image.dtype == np.uint8 else 1, image.dtype)
        image = np.concatenate([image, opaque], axis=2)
    return np.ascontiguousarray(image)


def interpolate(attributes, vb, mesh, diff_attrs=None):
    """Per-vertex `attributes` (N, C), or (B, N, C) one set per view, interpolated over the
    visibility buffer `vb` of `mesh` with its barycentrics: float32 (B, H, W, C), 0 where empty.
    `mesh` is the Mesh rasterized, or the indices rasterized with clip positions.

    With `diff_attrs` (indices of attributes, or "all"), also their screen-space derivatives as
    nvdiffrast's interpolate gives them: float32 (B, H, W, 2 * len(diff_attrs)) of (da/dX, da/dY)
    per attribute, in pixels, Y up (window coordinates, as nvdiffrast's rows run bottom-up),
    computed exactly from the triangles' clip positions (perspective-correct, 0 where empty);
    then the result is the pair (values, derivatives)."""
    if not isinstance(vb, VisibilityBuffer):
        raise ValueError(f"vb must be a clraster.VisibilityBuffer, got {type(vb).__name__}")
    triangles = mesh.indices if isinstance(mesh, Mesh) else _indices("indices", mesh)
    attributes = _as_array("attributes", attributes)
    if not (np.issubdtype(attributes.dtype, np.floating) or np.issubdtype(attributes.dtype, np.integer)):
        raise ValueError(f"attributes must be numbers, got {attributes.dtype}")
    vertex_count = vb.positions.shape[-2]
    views = len(vb.triangle)
    if attributes.ndim == 2:
        attributes = attributes[None]
    if attributes.ndim != 3 or attributes.shape[1] != vertex_count or attributes.shape[0] not in (1, views):
        raise ValueError(f"attributes must have shape ({vertex_count}, C) or ({views}, {vertex_count}, C) for this "
                         f"mesh and visibility buffer, got {tuple(np.shape(attributes))}")
    covered = vb.triangle >= 0
    corners = triangles[np.where(covered, vb.triangle, 0)]  # (B, H, W, 3)
    per_view = np.arange(views).reshape(-1, 1, 1, 1) if attributes.shape[0] == views else 0
    values = attributes[per_view, corners].astype(np.float32, copy=False)  # (B, H, W, 3, C)
    u, v = vb.barycentric[..., 0:1], vb.barycentric[..., 1:2]
    result = values[..., 0, :] * u + values[..., 1, :] * v + values[..., 2, :] * (1 - u - v)
    result = np.where(covered[..., None], result, np.float32(0))
    if diff_attrs is None:
        return result

    channels = attributes.shape[2]
    if isinstance(diff_attrs, str) and diff_attrs == "all":
        diff_attrs = range(channels)
    try:
        chosen = [operator.index(a) for a in diff_attrs]
    except TypeError:
        raise ValueError(f"diff_attrs must be \"all\" or a list of attribute indices, got {diff_attrs!r}") from None
    if any(not 0 <= a < channels for a in chosen):
        raise ValueError(f"diff_attrs: indices must be within 0..{channels - 1}, got {chosen}")
    db = _barycentric_derivatives(vb, corners)  # (B, H, W, 2 corners, 2 axes)
    chosen_values = values[..., chosen].astype(np.float64)  # (B, H, W, 3, D)
    # a = a0 b0 + a1 b1 + a2 (1 - b0 - b1): da = (a0 - a2) db0 + (a1 - a2) db1
    differences = chosen_values[..., :2, :] - chosen_values[..., 2:3, :]  # (B, H, W, 2, D)
    derivatives = np.einsum("bhwcd,bhwca->bhwda", differences, db)  # (B, H, W, D, 2 axes)
    derivatives = np.where(covered[..., None, None], derivatives, 0).astype(np.float32)
    return result, derivatives.reshape(derivatives.shape[:3] + (2 * len(chosen),))


def _barycentric_derivatives(vb, corners):
    """d(b0, b1)/d(X, Y) in pixels (Y up) at each pixel, float64 (B, H, W, 2, 2): nvdiffrast's
    rast_db. A corner's weight at normalized device (x, y) is n_i . (x, y, 1) / sum_j n_j . (x, y, 1)
    with n_i = cross(c_j, c_k) of the corners' clip (x, y, w), as the visibility program weighs
    them, so its derivative is exact: (n_i S - w_i sum_j n_j) / S^2, times 2 / (W or H) per pixel."""
    views, height, width = vb.triangle.shape
    if vb.positions.ndim == 3:  # clip positions, a set per view
        positions = vb.positions[np.arange(views).reshape(-1, 1, 1, 1), corners]
    else:
        positions = vb.positions[corners]
    clip = np.einsum("bij,bhwcj->bhwci", vb.mvp.astype(np.float64), positions.astype(np.float64))
    clip = clip[..., [0, 1, 3]]  # (B, H, W, 3 corners, (x, y, w))
    normals = np.stack([np.cross(clip[..., 1, :], clip[..., 2, :]), np.cross(clip[..., 2, :], clip[..., 0, :]),
                        np.cross(clip[..., 0, :], clip[..., 1, :])], axis=-2)  # (B, H, W, 3, 3)
    x = (np.arange(width) + 0.5) * 2 / width - 1
    y = 1 - (np.arange(height) + 0.5) * 2 / height  # rows from the top
    point = np.stack(np.broadcast_arrays(x[None, None, :], y[None, :, None], np.ones((1, 1, 1))), axis=-1)
    weights = np.einsum("bhwck,bhwk->bhwc", normals, np.broadcast_to(point, (views, height, width, 3)))
    total = weights.sum(axis=-1)[..., None, None]
    total = np.where(total == 0, 1, total)
    gradient = normals[..., :2, :2]  # d w_i / d(x, y) of corners 0 and 1
    gradient_of_total = normals[..., :2].sum(axis=-2)[..., None, :]
    db = (gradient * total - weights[..., :2, None] * gradient_of_total) / total**2
    return db * np.array([2 / width, 2 / height])


def texture(image, uv, uv_da=None):
    """`image` sampled at texture coordinates `uv` as a program samples a texture: float32
    (..., C) for uv (..., 2). `image`: uint8 (read as /255) or float32 (H, W) or (H, W, C), row 0
    at the top as pictures are (v = 1 there, as clraster maps the materials' images; nvdiffrast's
    textures have v = 0 at row 0: flip them with image[::-1]). Bilinear with repeat; with `uv_da`
    (..., 4) of (du/dX, du/dY, dv/dX, dv/dY), as interpolate(uv, ..., diff_attrs="all") gives
    them, trilinear between the mipmaps at OpenGL's level of detail, log2 of the longer of the
    footprint's two sides in texels; without, level 0. The mipmaps are made as the library makes
    them (each level samples the one before bilinearly at its texel centres: 2x2 averages where a
    side halves exactly)."""
    image = _as_array("image", image)
    if image.dtype not in (np.uint8, np.float32):
        raise ValueError(f"image must be uint8 or float32, got {image.dtype}")
    if image.ndim == 2:
        image = image[..., None]
    if image.ndim != 3 or 0 in image.shape:
        raise ValueError(f"image must have shape (H, W) or (H, W, C), got {image.shape}")
    texels = image[::-1].astype(np.float32) / (255 if image.dtype == np.uint8 else 1)  # row 0 at v = 0
    uv = _as_array("uv", uv)
    if not np.issubdtype(uv.dtype, np.floating) or uv.ndim < 1 or uv.shape[-1] != 2:
        raise ValueError(f"uv must be floats of shape (..., 2), got {uv.dtype} {uv.shape}")
    if uv_da is None:
        return _bilinear(texels, uv.astype(np.float64))
    uv_da = _as_array("uv_da", uv_da)
    if not np.issubdtype(uv_da.dtype, np.floating) or uv_da.shape != uv.shape[:-1] + (4,):
        raise ValueError(f"uv_da must be floats of shape {uv.shape[:-1] + (4,)}, got {uv_da.dtype} {uv_da.shape}")
    levels = _mipmaps(texels)
    height, width = texels.shape[:2]
    da = uv_da.astype(np.float64)
    footprint_x = np.hypot(da[..., 0] * width, da[..., 2] * height)
    footprint_y = np.hypot(da[..., 1] * width, da[..., 3] * height)
    with np.errstate(divide="ignore"):
        lod = np.log2(np.maximum(footprint_x, footprint_y))
    lod = np.clip(np.nan_to_num(lod, nan=0.0, neginf=0.0), 0, len(levels) - 1)
    lower = np.floor(lod).astype(int)
    blend = (lod - lower)[..., None]
    result = np.zeros(uv.shape[:-1] + (texels.shape[2],), np.float64)
    for level, level_texels in enumerate(levels):
        for chosen, weight in ((lower == level, 1 - blend), (lower + 1 == level, blend)):
            if chosen.any():
                result[chosen] += weight[chosen] * _bilinear(level_texels, uv[chosen].astype(np.float64))
    return result.astype(np.float32)


def _bilinear(texels, uv):
    """texels (H, W, C), row 0 at v = 0, sampled at uv (..., 2) bilinearly with repeat."""
    height, width = texels.shape[:2]
    x = uv[..., 0] * width - 0.5
    y = uv[..., 1] * height - 0.5
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    x0, y0 = x0.astype(np.int64) % width, y0.astype(np.int64) % height
    x1, y1 = (x0 + 1) % width, (y0 + 1) % height
    top = texels[y0, x0] * (1 - fx) + texels[y0, x1] * fx
    bottom = texels[y1, x0] * (1 - fx) + texels[y1, x1] * fx
    return (top * (1 - fy) + bottom * fy).astype(np.float32)


def _mipmaps(texels):
    """Level 0 and each smaller level down to 1x1: every level samples the one before bilinearly
    (clamped to its edges) at its own texel centres, as Texture::generate_mipmaps does."""
    levels = [texels.astype(np.float64)]
    while levels[-1].shape[0] > 1 or levels[-1].shape[1] > 1:
        previous = levels[-1]
        height, width = previous.shape[:2]
        new_height, new_width = max(height // 2, 1), max(width // 2, 1)
        y = np.clip((np.arange(new_height) + 0.5) * height / new_height - 0.5, 0, height - 1)
        x = np.clip((np.arange(new_width) + 0.5) * width / new_width - 0.5, 0, width - 1)
        y0, x0 = np.floor(y).astype(int), np.floor(x).astype(int)
        y1, x1 = np.minimum(y0 + 1, height - 1), np.minimum(x0 + 1, width - 1)
        fy, fx = (y - y0)[:, None, None], (x - x0)[None, :, None]
        rows = previous[y0] * (1 - fy) + previous[y1] * fy
        levels.append(rows[:, x0] * (1 - fx) + rows[:, x1] * fx)
    return levels
