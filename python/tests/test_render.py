"""Pictures: the command line's, byte for byte, one view or many in a batch."""

import numpy as np
import pytest

import clraster
from conftest import cli_picture

WIDTH, HEIGHT = 160, 120
EYE, TARGET, NEAR, FAR = (2.0, 1.5, 3.0), (0.0, 0.3, 0.0), 0.5, 20.0


def camera(eye=EYE):
    return clraster.look_at(eye, TARGET), clraster.perspective(45, WIDTH / HEIGHT, NEAR, FAR)


@pytest.mark.parametrize("shading", clraster.SHADINGS)
def test_one_view_is_the_command_lines_picture(ctx, cli, wuson, tmp_path, shading):
    expected = cli_picture(cli, tmp_path, wuson, "--size", f"{WIDTH}x{HEIGHT}", "--eye", ",".join(map(str, EYE)),
                           "--target", ",".join(map(str, TARGET)), "--near", NEAR, "--far", FAR, "--fov", 45,
                           "--shading", shading)
    view, projection = camera()
    pictures = ctx.render(clraster.load(wuson), view, projection, size=(WIDTH, HEIGHT), shading=shading)
    assert pictures.shape == (1, HEIGHT, WIDTH, 4) and pictures.dtype == np.uint8
    assert (expected[..., :3] != 0).any(), "the camera sees the model"
    np.testing.assert_array_equal(pictures[0], expected)


def test_a_batch_draws_each_view_as_alone(ctx, wuson):
    mesh = clraster.load(wuson)
    eyes = np.array([EYE, (-2, 1, 3), (0, 4, 0.5), (3, -1, -2), (0.5, 0.5, 4)], np.float32)
    views, projection = camera(eyes)
    batch = ctx.render(mesh, views, projection, size=(WIDTH, HEIGHT))
    assert batch.shape == (len(eyes), HEIGHT, WIDTH, 4)
    for k, view in enumerate(views):
        alone = ctx.render(mesh, view, projection, size=(WIDTH, HEIGHT))[0]
        # A layer's offset in the batch's attachments changes the rounding of window positions in
        # their last bits (docs/python.md): the conformance thresholds, not bytes.
        differs = (np.abs(batch[k].astype(int) - alone.astype(int)) > 8).any(axis=-1)
        assert differs.mean() < 0.002, f"view {k}: {differs.sum()} pixels differ"
        assert (alone[..., :3] != 0).sum() > 500, f"view {k} sees the model"


def test_out_is_drawn_into(ctx, wuson):
    view, projection = camera()
    out = np.zeros((1, HEIGHT, WIDTH, 4), np.uint8)
    result = ctx.render(clraster.load(wuson), view, projection, size=(WIDTH, HEIGHT), out=out)
    assert result is out
    assert (out[..., 3] == 255).all() and (out[..., :3] != 0).any()


def test_a_mesh_from_arrays_is_drawn_as_its_file(ctx, wuson):
    loaded = clraster.load(wuson)
    mesh = clraster.Mesh(loaded.positions, loaded.indices, loaded.normals, loaded.uvs)
    view, projection = camera()
    np.testing.assert_array_equal(ctx.render(mesh, view, projection, size=(WIDTH, HEIGHT)),
                                  ctx.render(loaded, view, projection, size=(WIDTH, HEIGHT)))


def test_rendering_releases_the_gil(ctx, wuson):
    import threading
    mesh = clraster.load(wuson)
    eyes = np.array([EYE] * 64, np.float32) * np.linspace(1, 2, 64, dtype=np.float32)[:, None]
    views, projection = camera(eyes)
    ctx.render(mesh, views[:1], projection, size=(WIDTH, HEIGHT))  # programs built and mesh uploaded first
    worker = threading.Thread(target=ctx.render, args=(mesh, views, projection), kwargs=dict(size=(WIDTH, HEIGHT)))
    steps = 0
    worker.start()
    while worker.is_alive():  # runs only while the render lets go of the GIL
        steps += 1
    worker.join()
    assert steps > 1000, steps
