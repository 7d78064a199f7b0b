"""Visibility buffers against a scene whose every pixel is computed here: pixel rays intersected
with the triangles' planes (independent of how the pipeline or its program weigh corners)."""

import numpy as np
import pytest

import clraster

WIDTH, HEIGHT = 64, 48
PROJECTION = clraster.perspective(45, WIDTH / HEIGHT, 0.5, 20)
# Triangle 0 far behind and large, triangle 1 in front and smaller, triangle 2 a floor that runs
# behind the eyes, so that the near plane clips it.
POSITIONS = np.array([(-3, -3, -1), (3, -3, -1), (0, 3, -1),
                      (-1, -1, 0), (1, -1, 0), (0, 1, 0),
                      (-1, -0.8, 0.5), (1, -0.8, 0.5), (0, -0.8, 10)], np.float32)
INDICES = np.arange(9, dtype=np.int32).reshape(3, 3)
EYES = np.array([(0, 0, 3), (0.4, 0.3, 2.5), (-0.5, 0.2, 3.5)], np.float32)


def expected_visibility(view):
    """Per pixel centre: the nearest triangle hit, its corners' weights and window depth (float64)."""
    inverse = np.linalg.inv(PROJECTION.astype(np.float64) @ view.astype(np.float64))
    x = (np.arange(WIDTH) + 0.5) / WIDTH * 2 - 1
    y = 1 - (np.arange(HEIGHT) + 0.5) / HEIGHT * 2  # row 0 at the top
    ndc = np.stack(np.broadcast_arrays(x[None, :], y[:, None], 0.0, 1.0), axis=-1)
    near, far = ndc.copy(), ndc.copy()
    near[..., 2], far[..., 2] = -1, 1
    start, end = ((inverse @ p[..., None])[..., 0] for p in (near, far))
    start, end = start[..., :3] / start[..., 3:], end[..., :3] / end[..., 3:]
    direction = end - start
    triangle = np.full((HEIGHT, WIDTH), -1)
    weights = np.zeros((HEIGHT, WIDTH, 3))
    distance = np.full((HEIGHT, WIDTH), np.inf)
    for t, corners in enumerate(POSITIONS.astype(np.float64).reshape(3, 3, 3)):
        normal = np.cross(corners[1] - corners[0], corners[2] - corners[0])
        along = ((corners[0] - start) @ normal) / (direction @ normal)
        point = start + along[..., None] * direction
        # Weights: areas of the sub-triangles opposite each corner, over the whole.
        area = normal @ normal
        w = np.stack([np.cross(corners[(i + 1) % 3] - point, corners[(i + 2) % 3] - point) @ normal / area
                      for i in range(3)], axis=-1)
        hit = (w >= 0).all(axis=-1) & (along > 0) & (along < 1) & (along < distance)
        triangle[hit], weights[hit], distance[hit] = t, w[hit], along[hit]
    distance = np.where(triangle >= 0, distance, 0)
    clip = np.concatenate([start + distance[..., None] * direction, np.ones((HEIGHT, WIDTH, 1))], axis=-1)
    clip = clip @ (PROJECTION.astype(np.float64) @ view.astype(np.float64)).T
    depth = np.where(triangle >= 0, clip[..., 2] / clip[..., 3] * 0.5 + 0.5, 1)
    return triangle, weights, depth


@pytest.fixture(scope="module")
def scene(ctx):
    mesh = clraster.Mesh(POSITIONS, INDICES)
    views = clraster.look_at(EYES, (0, 0, 0))
    return mesh, views, ctx.rasterize(mesh, views, PROJECTION, size=(WIDTH, HEIGHT))


def test_visibility_buffer_of_known_triangles(scene):
    mesh, views, vb = scene
    assert vb.triangle.shape == (3, HEIGHT, WIDTH) and vb.triangle.dtype == np.int32
    assert vb.barycentric.shape == (3, HEIGHT, WIDTH, 2) and vb.barycentric.dtype == np.float32
    assert vb.depth.shape == (3, HEIGHT, WIDTH) and vb.depth.dtype == np.float32
    for k, view in enumerate(views):
        triangle, weights, depth = expected_visibility(view)
        assert set(np.unique(triangle)) == {-1, 0, 1, 2}, "every triangle and the background are in view"
        # Pixel centres near an edge may go either way in float: compare those clearly inside one.
        clear = (weights.min(axis=-1) > 1e-3) | (triangle == -1)
        inside = clear & (triangle >= 0)
        np.testing.assert_array_equal(vb.triangle[k][clear], triangle[clear], err_msg=f"view {k}")
        np.testing.assert_allclose(vb.barycentric[k][inside], weights[inside][:, :2], atol=2e-4, err_msg=f"view {k}")
        np.testing.assert_allclose(vb.depth[k][clear], depth[clear], atol=1e-5, err_msg=f"view {k}")
        assert (vb.barycentric[k][vb.triangle[k] < 0] == 0).all()


def test_covers_exactly_what_render_draws(ctx, scene):
    mesh, views, vb = scene
    overdraw = ctx.render(mesh, views, PROJECTION, size=(WIDTH, HEIGHT), shading="overdraw")
    np.testing.assert_array_equal(vb.triangle >= 0, overdraw[..., 0] > 0)


def test_to_nvdiffrast_layout(scene):
    _, _, vb = scene
    rast = vb.to_nvdiffrast()
    assert rast.shape == (3, HEIGHT, WIDTH, 4) and rast.dtype == np.float32
    bottom_up = rast[:, ::-1]
    np.testing.assert_array_equal(bottom_up[..., 3], vb.triangle + 1)
    np.testing.assert_array_equal(bottom_up[..., :2], vb.barycentric)
    covered = vb.triangle >= 0
    np.testing.assert_allclose(bottom_up[..., 2][covered], 2 * vb.depth[covered] - 1, atol=1e-6)
    assert (bottom_up[..., 2][~covered] == 0).all()


def test_interpolate_gives_the_surface_point(scene):
    mesh, views, vb = scene
    points = clraster.interpolate(mesh.positions, vb, mesh)
    assert points.shape == (3, HEIGHT, WIDTH, 3) and points.dtype == np.float32
    for k, view in enumerate(views):
        triangle, weights, _ = expected_visibility(view)
        inside = (weights.min(axis=-1) > 1e-3) & (triangle >= 0)
        corners = POSITIONS[INDICES[triangle[inside]]]
        expected = (weights[inside][..., None] * corners).sum(axis=1)
        np.testing.assert_allclose(points[k][inside], expected, atol=1e-3)
        assert (points[k][vb.triangle[k] < 0] == 0).all()


def test_interpolate_per_view_attributes(scene):
    mesh, views, vb = scene
    per_view = np.arange(3, dtype=np.float32)[:, None, None] * np.ones((3, len(POSITIONS), 1), np.float32)
    values = clraster.interpolate(per_view, vb, mesh)[..., 0]
    for k in range(3):
        np.testing.assert_allclose(values[k][vb.triangle[k] >= 0], k, atol=1e-5)


def test_triangle_ids_count_the_triangles_left_out(ctx, scene):
    _, views, _ = scene
    positions = np.concatenate([[(np.nan, 0, 0), (0, 0, 0), (1, 0, 0)], POSITIONS]).astype(np.float32)
    indices = np.concatenate([[(0, 1, 2)], INDICES + 3]).astype(np.int32)
    with pytest.warns(clraster.TrianglesDroppedWarning, match="1 triangle dropped"):
        mesh = clraster.Mesh(positions, indices)
    vb = ctx.rasterize(mesh, views[0], PROJECTION, size=(WIDTH, HEIGHT))
    triangle, weights, _ = expected_visibility(views[0])
    clear = (weights.min(axis=-1) > 1e-3) | (triangle == -1)
    np.testing.assert_array_equal(vb.triangle[0][clear], np.where(triangle >= 0, triangle + 1, -1)[clear])


def test_clip_positions_rasterize_as_the_mesh_does(ctx):
    # nvdiffrast's form: clip-space positions per view and the triangles. The positions are
    # projected here, in float64, the pipeline projects its own in float: a few edge pixels may
    # fall to the other side.
    mesh = clraster.Mesh(POSITIONS, INDICES)
    views = clraster.look_at(EYES, (0, 0, 0))
    homogeneous = np.concatenate([POSITIONS, np.ones((len(POSITIONS), 1), np.float32)], axis=1).astype(np.float64)
    clip = np.einsum("bij,nj->bni", PROJECTION.astype(np.float64) @ views, homogeneous).astype(np.float32)
    by_mesh = ctx.rasterize(mesh, views, PROJECTION, size=(WIDTH, HEIGHT))
    by_clip = ctx.rasterize(clip, INDICES, size=(WIDTH, HEIGHT))
    same = by_mesh.triangle == by_clip.triangle
    assert same.mean() > 0.998 and (by_clip.triangle >= 0).sum() > WIDTH * HEIGHT
    np.testing.assert_allclose(by_clip.barycentric[same], by_mesh.barycentric[same], atol=1e-4)
    np.testing.assert_allclose(by_clip.depth[same], by_mesh.depth[same], atol=1e-5)
    # Derivatives from the clip positions, as from the mesh and its cameras.
    uv = POSITIONS[:, :2]
    _, from_mesh = clraster.interpolate(uv, by_mesh, mesh, diff_attrs="all")
    _, from_clip = clraster.interpolate(uv, by_clip, INDICES, diff_attrs="all")
    np.testing.assert_allclose(from_clip[same], from_mesh[same], rtol=1e-3, atol=1e-6)
    # One set of positions: one picture.
    single = ctx.rasterize(clip[1], INDICES, size=(WIDTH, HEIGHT))
    np.testing.assert_array_equal(single.triangle[0], by_clip.triangle[1])


@pytest.mark.parametrize("arguments, message", [
    (dict(mesh=np.zeros((1, 3, 4)), view=INDICES[:1]), "clip positions must be float32, got float64"),
    (dict(mesh=np.zeros((1, 3, 3), np.float32), view=INDICES[:1]), r"clip positions must have shape \(N, N, 4\)"),
    (dict(mesh=np.zeros((1, 3, 4), np.float32), view=INDICES[1:2]), "indices: triangle 0 has index 3, out of range "
     "for 3 vertices"),
    (dict(mesh=np.zeros((1, 3, 4), np.float32), view=INDICES[:1], projection=PROJECTION), "without a projection"),
])
def test_bad_clip_positions(ctx, arguments, message):
    with pytest.raises(ValueError, match=message):
        ctx.rasterize(**arguments, size=(8, 8))
