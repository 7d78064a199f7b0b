"""Arrays in through DLPack without copies, and batches larger than one framebuffer's layers."""

import numpy as np

import clraster

QUAD = np.array([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], np.float32)
QUAD_INDICES = np.array([(0, 1, 2), (0, 2, 3)], np.uint32)


class DLPackOnly:
    """An array that numpy can read only through the DLPack protocol (as JAX's or torch's)."""

    def __init__(self, array):
        self._array = array

    def __dlpack__(self, **kwargs):
        return self._array.__dlpack__(**kwargs)

    def __dlpack_device__(self):
        return self._array.__dlpack_device__()


def test_dlpack_arrays_make_the_same_mesh(ctx):
    mesh = clraster.Mesh(DLPackOnly(QUAD), DLPackOnly(QUAD_INDICES), normals=DLPackOnly(np.tile([0, 0, 1], (4, 1)).astype(np.float32)))
    np.testing.assert_array_equal(mesh.positions, QUAD)
    np.testing.assert_array_equal(mesh.indices, QUAD_INDICES)
    np.testing.assert_array_equal(mesh.normals[:, 2], 1)
    assert not mesh.positions.flags.writeable


def test_normals_computed_when_not_given():
    mesh = clraster.Mesh(QUAD, QUAD_INDICES)  # counter-clockwise seen from +z
    np.testing.assert_allclose(mesh.normals, np.tile([0, 0, 1], (4, 1)), atol=1e-7)
    assert mesh.uvs is None


def test_a_batch_larger_than_a_framebuffer_keeps_its_order(ctx):
    # More views than a layered framebuffer has layers (4096): two submissions. Even views see the
    # quad fill the picture, odd ones look away from it.
    count = 4100
    eyes = np.zeros((count, 3), np.float32)
    eyes[:, 2] = 0.5
    targets = np.zeros((count, 3), np.float32)
    targets[1::2, 2] = 3
    views = clraster.look_at(eyes, targets)
    projection = clraster.perspective(90, 1, 0.1, 10)
    pictures = ctx.render(clraster.Mesh(QUAD, QUAD_INDICES), views, projection, size=(4, 4), shading="overdraw")
    assert pictures.shape == (count, 4, 4, 4)
    np.testing.assert_array_equal(pictures[0::2, ..., 0], 1)
    np.testing.assert_array_equal(pictures[1::2, ..., 0], 0)
    vb = ctx.rasterize(clraster.Mesh(QUAD, QUAD_INDICES), views[-6:], projection, size=(4, 4))
    assert (vb.triangle[0::2] >= 0).all() and (vb.triangle[1::2] == -1).all()


def test_progress_bars_over_chunks(ctx, capsys):
    # Pictures 10000 pixels wide take a framebuffer each (two side by side would pass 16384): three
    # views, three chunks.
    mesh = clraster.Mesh(QUAD, QUAD_INDICES)
    views = clraster.look_at(np.float32([[0, 0, 0.5]] * 3), (0, 0, 0))
    projection = clraster.perspective(90, 1, 0.1, 10)
    ctx.render(mesh, views, projection, size=(10000, 1), progress=True)
    ctx.rasterize(mesh, views, projection, size=(10000, 1), progress=True)
    shown = capsys.readouterr().err
    assert "clraster render" in shown and "clraster rasterize" in shown and "3/3" in shown, shown
    # Off by default when stderr is not a terminal (as under pytest), and with progress=False.
    ctx.render(mesh, views, projection, size=(10000, 1))
    ctx.render(mesh, views, projection, size=(10000, 1), progress=False)
    # One chunk shows none.
    ctx.render(mesh, views, projection, size=(8, 8), progress=True)
    assert capsys.readouterr().err == ""
