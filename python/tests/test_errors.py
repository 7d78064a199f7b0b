"""Bad input: a clear Python exception or warning each time, never a crash."""

import numpy as np
import pytest

import clraster

POSITIONS = np.array([(-1, -1, 0), (1, -1, 0), (0, 1, 0), (0, 0, 1)], np.float32)
INDICES = np.array([(0, 1, 2), (0, 1, 3)], np.int32)
VIEW = clraster.look_at((0, 0, 3), (0, 0, 0))
PROJECTION = clraster.perspective(45, 1, 0.5, 10)


@pytest.mark.parametrize("positions, indices, message", [
    (POSITIONS.astype(np.float64), INDICES, "positions must be float32, got float64"),
    (POSITIONS, INDICES.astype(np.int64), "indices must be int32 or uint32, got int64"),
    (POSITIONS[:, :2].copy(), INDICES, r"positions must have shape \(N, 3\), got \(4, 2\)"),
    (POSITIONS.ravel(), INDICES, r"positions must have shape \(N, 3\), got \(12,\)"),
    (np.asfortranarray(POSITIONS), INDICES, "positions must be C-contiguous"),
    (POSITIONS, INDICES[:, ::-1], "indices must be C-contiguous"),
    (POSITIONS, np.array([(0, 1, 4)], np.int32), "triangle 0 has index 4, out of range for 4 vertices"),
    (POSITIONS, np.array([(0, 1, 2), (0, -1, 2)], np.int32), "triangle 1 has the negative index -1"),
    (POSITIONS, np.zeros((0, 3), np.int32), "a mesh needs at least one triangle"),
    ([[0.0, 0.0, 0.0]], INDICES, "positions must be float32, got float64"),
])
def test_bad_mesh_arrays(positions, indices, message):
    with pytest.raises(ValueError, match=message):
        clraster.Mesh(positions, indices)


def test_bad_normals_and_uvs():
    with pytest.raises(ValueError, match=r"normals must have shape \(4, 3\), got \(3, 3\)"):
        clraster.Mesh(POSITIONS, INDICES, normals=POSITIONS[:3])
    with pytest.raises(ValueError, match="uvs must be float32, got int32"):
        clraster.Mesh(POSITIONS, INDICES, uvs=np.zeros((4, 2), np.int32))


def test_nan_vertices_are_dropped_with_a_warning(ctx):
    positions = POSITIONS.copy()
    positions[3] = np.nan
    with pytest.warns(clraster.TrianglesDroppedWarning,
                      match="1 triangle dropped: a corner's position, normal or texture coordinate is NaN or infinite"):
        mesh = clraster.Mesh(positions, INDICES)
    assert mesh.indices.shape == (2, 3)  # the mesh keeps what it was given
    picture = ctx.render(mesh, VIEW, PROJECTION, size=(32, 32), shading="overdraw")
    assert picture[..., 0].max() == 1, "the other triangle is drawn, once per pixel"
    with pytest.raises(ValueError, match="no triangles left: 1 triangle dropped"):
        clraster.Mesh(positions, INDICES[1:])


@pytest.mark.parametrize("arguments, message", [
    (dict(shading="phong"), "shading must be one of normal, lambert, depth, overdraw, material or a clraster.Program, got 'phong'"),
    (dict(size=(0, 32)), "size 0x32 is out of range"),
    (dict(size=(32,)), r"size must be \(width, height\)"),
    (dict(view=np.zeros((2, 3, 4))), r"view must have shape \(4, 4\) or \(B, 4, 4\)"),
    (dict(view=np.full((4, 4), np.nan)), "view has NaN or infinite elements"),
    (dict(projection=np.stack([PROJECTION] * 2)), r"projection must have shape \(4, 4\)"),
    (dict(out=np.zeros((1, 32, 32, 3), np.uint8)), r"out must have shape \(1, 32, 32, 4\)"),
    (dict(out=np.zeros((1, 32, 32, 4), np.float32)), "out must be uint8"),
    (dict(mesh="model.obj"), "mesh must be a clraster.Mesh"),
])
def test_bad_render_arguments(ctx, arguments, message):
    call = dict(mesh=clraster.Mesh(POSITIONS, INDICES), view=VIEW, projection=PROJECTION, size=(32, 32))
    call.update(arguments)
    with pytest.raises(ValueError, match=message):
        ctx.render(**call)


def test_bad_cameras():
    with pytest.raises(ValueError, match=r"camera 0: camera: eye and target are the same point"):
        clraster.look_at((1, 2, 3), (1, 2, 3))
    with pytest.raises(ValueError, match=r"camera 1: camera: up \(0, 1, 0\) is zero or parallel"):
        clraster.look_at([(0, 0, 3), (0, 3, 0)], (0, 0, 0))
    with pytest.raises(ValueError, match=r"eye must have shape \(3,\) or \(B, 3\)"):
        clraster.look_at((0, 0), (0, 0, 0))
    with pytest.raises(ValueError, match="near_plane must be greater than 0"):
        clraster.perspective(45, 1, 0, 10)
    with pytest.raises(ValueError, match="aspect must be a positive finite number"):
        clraster.perspective(45, -1, 0.1, 10)


def test_library_errors_are_the_error_hierarchy(tmp_path):
    assert issubclass(clraster.InvalidArgument, clraster.Error) and issubclass(clraster.InvalidArgument, ValueError)
    assert issubclass(clraster.DeviceError, clraster.Error) and issubclass(clraster.BuildError, clraster.Error)
    with pytest.raises(clraster.InvalidArgument, match="missing.obj"):
        clraster.load(tmp_path / "missing.obj")
    (tmp_path / "broken.obj").write_text("f 1 2 3\n")
    with pytest.raises(clraster.InvalidArgument, match="broken.obj"):
        clraster.load(tmp_path / "broken.obj")
    with pytest.raises(clraster.DeviceError, match="1000"):
        clraster.Context(device=1000)
