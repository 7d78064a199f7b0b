"""Shading in numpy from the visibility buffer: interpolate's derivatives (nvdiffrast's) and
texture's mipmapped sampling, against numpy references and against what a program samples."""

import numpy as np
import pytest

import clraster

SIZE = 64
# A quad of two triangles, uv 0..4 across it (the texture repeats), seen at a slant.
QUAD = np.float32([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]])
QUAD_INDICES = np.int32([[0, 1, 2], [0, 2, 3]])
QUAD_UVS = np.float32([[0, 0], [4, 0], [4, 4], [0, 4]])
VIEW = clraster.look_at((0.4, -0.8, 1.3), (0, 0, 0))
PROJECTION = clraster.perspective(60, 1, 0.1, 10)

SAMPLING_PROGRAM = """
clr_attribute(float3, position)
clr_attribute(float2, uv)
clr_varying(float2, uv)
clr_uniform(float16, mvp)
clr_texture(albedo)
clr_output(float4, color)

void vertex(clr_vertex* v) {
  v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f));
  v->out.uv = v->in.uv;
}

void fragment(clr_fragment* f) { f->out.color = clr_sample(f, f->textures.albedo, f->in.uv); }
"""


@pytest.fixture(scope="module")
def quad():
    return clraster.Mesh(QUAD, QUAD_INDICES, uvs=QUAD_UVS)


def test_derivatives_are_those_of_the_interpolated_values(ctx, quad):
    vb = ctx.rasterize(quad, VIEW, PROJECTION, size=(SIZE, SIZE))
    values, derivatives = clraster.interpolate(QUAD_UVS, vb, quad, diff_attrs="all")
    assert derivatives.shape == (1, SIZE, SIZE, 4) and derivatives.dtype == np.float32
    only_u = clraster.interpolate(QUAD_UVS, vb, quad, diff_attrs=[0])[1]
    np.testing.assert_array_equal(only_u, derivatives[..., :2])

    # Central differences, where a pixel's four neighbours are on its triangle: X to the right, Y
    # up (rows from the top, so up is the row before).
    triangle = vb.triangle[0]
    inner = np.zeros_like(triangle, bool)
    inner[1:-1, 1:-1] = ((triangle[1:-1, 1:-1] >= 0) & (triangle[1:-1, :-2] == triangle[1:-1, 1:-1])
                         & (triangle[1:-1, 2:] == triangle[1:-1, 1:-1]) & (triangle[:-2, 1:-1] == triangle[1:-1, 1:-1])
                         & (triangle[2:, 1:-1] == triangle[1:-1, 1:-1]))
    assert inner.sum() > SIZE * SIZE // 3
    uv = values[0].astype(np.float64)
    d_dx = np.zeros_like(uv)
    d_dy = np.zeros_like(uv)
    d_dx[1:-1, 1:-1] = (uv[1:-1, 2:] - uv[1:-1, :-2]) / 2
    d_dy[1:-1, 1:-1] = (uv[:-2, 1:-1] - uv[2:, 1:-1]) / 2
    expected = np.stack([d_dx[..., 0], d_dy[..., 0], d_dx[..., 1], d_dy[..., 1]], axis=-1)
    scale = np.abs(expected[inner]).max()
    np.testing.assert_allclose(derivatives[0][inner], expected[inner], atol=0.02 * scale)
    assert (derivatives[0][triangle < 0] == 0).all()


def test_derivatives_under_an_orthographic_camera_are_constant(ctx, quad):
    orthographic = np.float32([[0.5, 0, 0, 0], [0, 0.5, 0, 0], [0, 0, -0.2, -1], [0, 0, 0, 1]])
    vb = ctx.rasterize(quad, clraster.look_at((0, 0, 3), (0, 0, 0)), orthographic, size=(SIZE, SIZE))
    _, derivatives = clraster.interpolate(QUAD_UVS, vb, quad, diff_attrs="all")
    covered = vb.triangle[0] >= 0
    # The quad covers the middle half of the picture: u runs 0..4 over SIZE / 2 pixels to the
    # right, v likewise upward.
    assert covered.sum() == (SIZE // 2) ** 2
    np.testing.assert_allclose(derivatives[0][covered], [[8 / SIZE, 0, 0, 8 / SIZE]] * covered.sum(), atol=1e-6)


def test_texture_level_0_at_texel_centres_and_repeat():
    image = np.arange(4 * 3 * 4, dtype=np.uint8).reshape(4, 3, 4)
    rows, columns = np.mgrid[0:4, 0:3]
    uv = np.stack([(columns + 0.5) / 3, 1 - (rows + 0.5) / 4], axis=-1)  # row 0 at the top: v near 1
    np.testing.assert_allclose(clraster.texture(image, uv), image / 255, atol=1e-6)
    edge = clraster.texture(image, np.array([[0.0, 1 - 0.5 / 4]]))  # between the last column and the first
    np.testing.assert_allclose(edge[0], (image[0, 0] / 255 + image[0, 2] / 255) / 2, atol=1e-6)


def test_texture_levels_from_uv_derivatives():
    checker = np.indices((8, 8)).sum(axis=0) % 2  # 0 and 1: level 1 and below are 0.5
    image = np.repeat(checker[..., None], 4, axis=-1).astype(np.float32)
    uv = np.full((3, 2), (0.5 + 0.5 / 8, 0.5 + 0.5 / 8))  # a texel's centre
    texels = np.array([1, 2, np.sqrt(2)])  # the footprint: level 0, 1, and half-way
    uv_da = np.stack([texels / 8, np.zeros(3), np.zeros(3), texels / 8], axis=-1)
    sampled = clraster.texture(image, uv, uv_da)[..., 0]
    level0 = clraster.texture(image, uv[:1])[0, 0]
    np.testing.assert_allclose(sampled, [level0, 0.5, (level0 + 0.5) / 2], atol=1e-6)


def test_texture_bad_arguments(ctx, quad):
    with pytest.raises(ValueError, match="image must be uint8 or float32, got float64"):
        clraster.texture(np.zeros((2, 2, 4)), np.zeros((1, 2)))
    with pytest.raises(ValueError, match=r"uv must be floats of shape \(\.\.\., 2\)"):
        clraster.texture(np.zeros((2, 2, 4), np.uint8), np.zeros((1, 3)))
    with pytest.raises(ValueError, match=r"uv_da must be floats of shape \(1, 4\)"):
        clraster.texture(np.zeros((2, 2, 4), np.uint8), np.zeros((1, 2)), np.zeros((1, 2)))
    vb = ctx.rasterize(quad, VIEW, PROJECTION, size=(8, 8))
    with pytest.raises(ValueError, match="diff_attrs: indices must be within 0..1"):
        clraster.interpolate(QUAD_UVS, vb, quad, diff_attrs=[2])
    with pytest.raises(ValueError, match='diff_attrs must be "all" or a list of attribute indices'):
        clraster.interpolate(QUAD_UVS, vb, quad, diff_attrs="some")


def test_shading_in_numpy_samples_as_a_program_does(ctx, quad):
    # A smooth texture, so that the programs' level of detail (from differences across 2x2 quads)
    # and interpolate's (exact) choose nearly the same blend.
    y, x = np.mgrid[0:32, 0:32] / 32
    image = (np.stack([np.sin(2 * np.pi * x) * 0.5 + 0.5, np.cos(2 * np.pi * y) * 0.5 + 0.5, x * 0 + 0.25,
                       x * 0 + 1], axis=-1) * 255).round().astype(np.uint8)
    program = clraster.Program(ctx, SAMPLING_PROGRAM)
    program["albedo"] = image
    drawn = ctx.render(quad, VIEW, PROJECTION, size=(SIZE, SIZE), shading=program)[0]
    vb = ctx.rasterize(quad, VIEW, PROJECTION, size=(SIZE, SIZE))
    uv, uv_da = clraster.interpolate(QUAD_UVS, vb, quad, diff_attrs="all")
    shaded = clraster.texture(image, uv, uv_da)[0]
    covered = vb.triangle[0] >= 0
    difference = np.abs(shaded[covered] * 255 - drawn[covered].astype(np.float32))
    assert difference.mean() < 1.5 and np.quantile(difference, 0.99) < 8, (difference.mean(), difference.max())
