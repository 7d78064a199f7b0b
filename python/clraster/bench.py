"""python -m clraster.bench: a batch of views of a 50k-triangle knot, pictures per second with
clraster (render with normal shading, and the visibility buffer) against moderngl drawing the same
views with Mesa's llvmpipe through a standalone EGL context, in the same run (docs/performance.md).

    python -m clraster.bench [--views 64] [--size 256] [--triangles 50000] [--repeats 5] [--json]

Needs moderngl (pip install moderngl==5.13.0; python/requirements.txt pins it) and Mesa's EGL.
"""

import argparse
import json
import statistics
import time

import numpy as np

import clraster

_VERTEX_SHADER = """#version 330
in vec3 position;
in vec3 normal;
uniform mat4 mvp;
out vec3 object_normal;
void main() {
  gl_Position = mvp * vec4(position, 1.0);
  object_normal = normal;
}
"""
# clraster's shading="normal": the interpolated object-space normal, n * 0.5 + 0.5.
_FRAGMENT_SHADER = """#version 330
in vec3 object_normal;
out vec4 color;
void main() { color = vec4(object_normal * 0.5 + 0.5, 1.0); }
"""


def knot(triangles):
    """A trefoil knot's tube of about `triangles` triangles (rings of 50 around a closed curve),
    with the normals Mesh computes (area-weighted, smooth)."""
    around = 50
    along = max(3, round(triangles / (2 * around)))
    t = np.linspace(0, 2 * np.pi, along, endpoint=False)[:, None]
    curve = np.concatenate([(2 + np.cos(3 * t)) * np.cos(2 * t), (2 + np.cos(3 * t)) * np.sin(2 * t), np.sin(3 * t)],
                           axis=1)
    tangent = np.gradient(curve, axis=0)
    binormal = np.cross(tangent, np.gradient(tangent, axis=0))
    binormal /= np.linalg.norm(binormal, axis=1, keepdims=True)
    normal = np.cross(binormal, tangent / np.linalg.norm(tangent, axis=1, keepdims=True))
    angle = np.linspace(0, 2 * np.pi, around, endpoint=False)[None, :, None]
    ring = np.cos(angle) * normal[:, None] + np.sin(angle) * binormal[:, None]
    positions = (curve[:, None] + 0.35 * ring).reshape(-1, 3).astype(np.float32)
    i, j = np.meshgrid(np.arange(along), np.arange(around), indexing="ij")
    corner = lambda di, dj: ((i + di) % along) * around + (j + dj) % around
    quads = np.stack([corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)], axis=-1).reshape(-1, 4)
    indices = np.ascontiguousarray(np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]), np.int32)
    return clraster.Mesh(positions, indices)


def cameras(views):
    """`views` cameras around the knot: rows of elevations by azimuths, as the C++ benchmark's views-64."""
    rows = max(1, int(round(np.sqrt(views))))
    elevation = np.repeat(np.radians(np.linspace(-60, 60, rows)), -(-views // rows))[:views]
    azimuth = np.tile(np.linspace(0, 2 * np.pi, -(-views // rows), endpoint=False), rows)[:views]
    eyes = 9 * np.stack([np.cos(elevation) * np.sin(azimuth), np.sin(elevation), np.cos(elevation) * np.cos(azimuth)],
                        axis=1)
    return clraster.look_at(eyes, (0, 0, 0)), clraster.perspective(45, 1, 4, 14)


class ModernglViews:
    """The same views drawn by moderngl on llvmpipe (headless EGL): per view, clear, one draw and
    the picture read back into numpy, rows from the top as clraster's."""

    def __init__(self, mesh, size):
        import moderngl
        self.gl = moderngl.create_standalone_context(backend="egl")
        self.renderer = self.gl.info["GL_RENDERER"]
        program = self.gl.program(vertex_shader=_VERTEX_SHADER, fragment_shader=_FRAGMENT_SHADER)
        self.mvp = program["mvp"]
        vertices = np.concatenate([mesh.positions, mesh.normals], axis=1).astype(np.float32)
        self.vao = self.gl.vertex_array(program, [(self.gl.buffer(vertices.tobytes()), "3f 3f", "position", "normal")],
                                        index_buffer=self.gl.buffer(mesh.indices.astype(np.uint32).tobytes()),
                                        index_element_size=4)
        self.size = size
        self.framebuffer = self.gl.framebuffer(color_attachments=[self.gl.texture((size, size), 4)],
                                               depth_attachment=self.gl.depth_texture((size, size)))
        self.gl.enable(moderngl.DEPTH_TEST)

    def render(self, views, projection):
        pictures = np.empty((len(views), self.size, self.size, 4), np.uint8)
        self.framebuffer.use()
        for k, view in enumerate(views):
            self.mvp.write(np.ascontiguousarray((projection @ view).T, np.float32).tobytes())  # column-major
            self.framebuffer.clear(0, 0, 0, 1, depth=1.0)
            self.vao.render()
            picture = np.frombuffer(self.framebuffer.read(components=4), np.uint8)
            pictures[k] = picture.reshape(self.size, self.size, 4)[::-1]
        return pictures


def _timed(run, repeats):
    """Seconds of each of `repeats` runs, after one that is not timed (programs built, memory
    allocated); and what the last run returned."""
    result = run()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = run()
        times.append(time.perf_counter() - start)
    return times, result


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m clraster.bench", description=__doc__.split("\n\n")[0])
    parser.add_argument("--views", type=int, default=64)
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--triangles", type=int, default=50000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--device", type=int, default=None)
    parser.add_argument("--json", action="store_true", help="one JSON object instead of the table")
    arguments = parser.parse_args(argv)

    mesh = knot(arguments.triangles)
    views, projection = cameras(arguments.views)
    size = (arguments.size, arguments.size)
    ctx = clraster.Context(arguments.device)
    moderngl_views = ModernglViews(mesh, arguments.size)

    render_times, pictures = _timed(lambda: ctx.render(mesh, views, projection, size=size, progress=False),
                                    arguments.repeats)
    rasterize_times, _ = _timed(lambda: ctx.rasterize(mesh, views, projection, size=size, progress=False),
                                arguments.repeats)
    moderngl_times, moderngl_pictures = _timed(lambda: moderngl_views.render(views, projection), arguments.repeats)
    # The two draw the same pictures (the conformance threshold: colours within 8 / 255).
    differing = (np.abs(pictures.astype(int) - moderngl_pictures.astype(int)) > 8).any(axis=-1).mean()

    rate = lambda times: arguments.views / statistics.median(times)
    result = {
        "triangles": len(mesh.indices), "views": arguments.views, "size": arguments.size,
        "repeats": arguments.repeats, "clraster_device": ctx.device.name, "moderngl_renderer": moderngl_views.renderer,
        "clraster_render_pictures_per_second": rate(render_times),
        "clraster_rasterize_pictures_per_second": rate(rasterize_times),
        "moderngl_pictures_per_second": rate(moderngl_times),
        "pixels_differing_from_moderngl": float(differing),
        "times_s": {"clraster_render": render_times, "clraster_rasterize": rasterize_times,
                    "moderngl": moderngl_times},
    }
    if arguments.json:
        print(json.dumps(result))
        return
    print(f"{result['views']} views of a {result['triangles']}-triangle knot at {arguments.size}x{arguments.size}, "
          f"median of {arguments.repeats} batches")
    print(f"clraster on {result['clraster_device']}; moderngl on {result['moderngl_renderer']}\n")
    print("| | pictures/s | vs moderngl |")
    print("|---|---|---|")
    moderngl_rate = result["moderngl_pictures_per_second"]
    for name, key in (("clraster render (normal shading)", "clraster_render_pictures_per_second"),
                      ("clraster rasterize (visibility buffer)", "clraster_rasterize_pictures_per_second"),
                      ("moderngl, llvmpipe (EGL)", "moderngl_pictures_per_second")):
        print(f"| {name} | {result[key]:.1f} | {result[key] / moderngl_rate:.2f}x |")
    print(f"\npixels whose colour differs from moderngl's by more than 8/255: {100 * differing:.3f}%")


if __name__ == "__main__":
    main()
