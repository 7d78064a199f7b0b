"""shading="material" and programs of one's own: the command line's pictures byte for byte, and
uniforms and textures bound from numpy."""

import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

import clraster
from conftest import MODELS, REPOSITORY, cli_picture

WIDTH, HEIGHT = 96, 72
EYE, TARGET, NEAR, FAR = (2.0, 1.5, 3.0), (0.0, 0.0, 0.0), 0.5, 20.0
TEXTURED_BOX = MODELS / "glTF2" / "BoxTextured-glTF-Binary" / "BoxTextured.glb"
SPIDER = MODELS / "OBJ" / "spider.obj"

# A program of its own: the mesh moved by `transform`, coloured by `albedo` sampled at `at`, times
# `tint`.
OWN_PROGRAM = """
clr_attribute(float3, position)
clr_uniform(float16, mvp)
clr_uniform(float16, transform)
clr_uniform(float4, tint)
clr_uniform(float2, at)
clr_texture(albedo)
clr_output(float4, color)

void vertex(clr_vertex* v) {
  v->position = clr_mul(v->uniforms->mvp, clr_mul(v->uniforms->transform, (float4)(v->in.position, 1.0f)));
}

void fragment(clr_fragment* f) {
  f->out.color = clr_sample(f, f->textures.albedo, f->uniforms->at) * f->uniforms->tint;
}
"""
# 2x2 texels, row 0 at the top: (0.25, 0.75) is the top left one's centre.
ALBEDO = np.array([[[200, 100, 40, 255], [0, 0, 255, 255]],
                   [[0, 255, 0, 255], [255, 255, 255, 255]]], np.uint8)


def camera(eye=EYE, size=(WIDTH, HEIGHT)):
    return clraster.look_at(eye, TARGET), clraster.perspective(45, size[0] / size[1], NEAR, FAR)


def cli_arguments(model):
    return [model, "--size", f"{WIDTH}x{HEIGHT}", "--eye", ",".join(map(str, EYE)), "--target",
            ",".join(map(str, TARGET)), "--near", NEAR, "--far", FAR, "--fov", 45]


@pytest.fixture(scope="module")
def own_program(ctx):
    return clraster.Program(ctx, OWN_PROGRAM)


@pytest.mark.parametrize("model", [TEXTURED_BOX, SPIDER], ids=["BoxTextured.glb", "spider.obj"])
def test_material_is_the_command_lines_picture(ctx, cli, tmp_path, model):
    expected = cli_picture(cli, tmp_path, *cli_arguments(model), "--shading", "material")
    view, projection = camera()
    picture = ctx.render(clraster.load(model), view, projection, size=(WIDTH, HEIGHT), shading="material")[0]
    assert len(np.unique(expected[..., :3].reshape(-1, 3), axis=0)) > 50, "textured and lit"
    np.testing.assert_array_equal(picture, expected)


def test_a_program_file_is_the_command_lines_picture(ctx, cli, tmp_path):
    material = REPOSITORY / "programs" / "material.cl"
    expected = cli_picture(cli, tmp_path, *cli_arguments(TEXTURED_BOX), "--program", material)
    view, projection = camera()
    mesh = clraster.load(TEXTURED_BOX)
    program = clraster.Program(ctx, material)
    assert program.uniforms == {} and program.textures == []  # all of it is the contract's
    picture = ctx.render(mesh, view, projection, size=(WIDTH, HEIGHT), shading=program)[0]
    np.testing.assert_array_equal(picture, expected)


def test_a_batch_of_materials_draws_each_view_as_alone(ctx):
    mesh = clraster.load(TEXTURED_BOX)
    eyes = np.array([EYE, (-2, 1, 3), (0, 3, 0.5)], np.float32)
    views, projection = camera(eyes)
    batch = ctx.render(mesh, views, projection, size=(WIDTH, HEIGHT), shading="material")
    for k, view in enumerate(views):
        alone = ctx.render(mesh, view, projection, size=(WIDTH, HEIGHT), shading="material")[0]
        differs = (np.abs(batch[k].astype(int) - alone.astype(int)) > 8).any(axis=-1)
        assert differs.mean() < 0.002, f"view {k}: {differs.sum()} pixels differ"
        assert (alone[..., :3] != 0).sum() > 500


def test_own_uniforms_and_textures(ctx, own_program, wuson):
    mesh = clraster.load(wuson)
    view, projection = camera()
    own_program["transform"] = np.eye(4)
    own_program["tint"] = (1.0, 0.5, 1.0, 1.0)
    own_program["at"] = (0.25, 0.75)
    own_program["albedo"] = ALBEDO
    picture = ctx.render(mesh, view, projection, size=(WIDTH, HEIGHT), shading=own_program)[0]
    covered = picture[..., :3].any(axis=-1)
    assert covered.sum() > 500
    colours = np.unique(picture[covered], axis=0)
    assert len(colours) == 1 and np.abs(colours[0].astype(int) - (200, 50, 40, 255)).max() <= 1, colours

    # A matrix as numpy writes it (row-major): moving the mesh by it draws the moved mesh.
    moved = np.eye(4)
    moved[:3, 3] = (0.3, -0.2, 0.1)
    own_program["transform"] = moved
    shifted = ctx.render(mesh, view, projection, size=(WIDTH, HEIGHT), shading=own_program)[0]
    own_program["transform"] = np.eye(4)
    moved_mesh = clraster.Mesh(mesh.positions + np.float32([0.3, -0.2, 0.1]), mesh.indices, mesh.normals)
    expected = ctx.render(moved_mesh, view, projection, size=(WIDTH, HEIGHT), shading=own_program)[0]
    differs = (picture != shifted).any(axis=-1)
    assert differs.sum() > 100, "the transform moves the picture"
    assert ((shifted != expected).any(axis=-1)).mean() < 0.002


def test_uniforms_one_per_view(ctx, own_program, wuson):
    mesh = clraster.load(wuson)
    views, projection = camera(np.array([EYE, (-2, 1, 3), (0, 3, 0.5)], np.float32))
    tints = np.array([[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1]], np.float32)
    own_program["transform"] = np.eye(4)
    own_program["at"] = (0.75, 0.25)  # the white texel
    own_program["albedo"] = ALBEDO
    own_program["tint"] = tints
    pictures = ctx.render(mesh, views, projection, size=(WIDTH, HEIGHT), shading=own_program)
    for picture, tint in zip(pictures, tints):
        covered = picture[..., :3].any(axis=-1)
        assert covered.sum() > 500
        np.testing.assert_array_equal(np.unique(picture[covered], axis=0), [np.round(tint * 255)])
    with pytest.raises(ValueError, match="uniform 'tint' has values for 3 views, the batch has 1"):
        ctx.render(mesh, views[0], projection, size=(WIDTH, HEIGHT), shading=own_program)
    own_program["tint"] = (1, 1, 1, 1)


def test_program_errors(ctx, own_program, tmp_path):
    fresh = clraster.Program(ctx, OWN_PROGRAM)
    mesh = clraster.Mesh(np.float32([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.int32([[0, 1, 2]]))
    view, projection = camera()
    with pytest.raises(ValueError, match=r"'transform', 'tint', 'at', 'albedo' not set"):
        ctx.render(mesh, view, projection, size=(8, 8), shading=fresh)
    with pytest.raises(ValueError, match=r"uniform 'tint' \(float4\) must have shape \(4,\)"):
        own_program["tint"] = (1, 2, 3)
    with pytest.raises(ValueError, match=r"uniform 'transform' \(float16\) must have shape \(4, 4\)"):
        own_program["transform"] = np.eye(3)
    with pytest.raises(ValueError, match="has no uniform or texture 'mvp' of its own"):
        own_program["mvp"] = np.eye(4)
    with pytest.raises(ValueError, match=r"texture 'albedo' must be uint8 or float32, got float64"):
        own_program["albedo"] = np.zeros((4, 4, 4))
    with pytest.raises(ValueError, match="attribute 'colour', which clraster does not provide"):
        clraster.Program(ctx, "clr_attribute(float4, colour)\n" + OWN_PROGRAM)
    with pytest.raises(ValueError, match="declares 2 outputs; clraster draws exactly one"):
        clraster.Program(ctx, OWN_PROGRAM + "clr_output(float4, second)\n")
    with pytest.raises(clraster.InvalidArgument, match="cannot read program file"):
        clraster.Program(ctx, tmp_path / "missing.cl")
    other = clraster.Context()
    with pytest.raises(ValueError, match="compiled for another context"):
        other.render(mesh, view, projection, size=(8, 8), shading=own_program)


def test_the_programs_example_runs(tmp_path):
    subprocess.run([sys.executable, str(REPOSITORY / "examples" / "python" / "programs.py"), str(tmp_path)], check=True)
    with Image.open(tmp_path / "programs.png") as sheet:
        assert sheet.size == (4 * 192, 2 * 192)
