"""A model's materials, and a program of one's own with a uniform per view and a texture from
numpy; writes programs.png (docs/python.md shows it). Needs numpy and Pillow.

    python examples/python/programs.py [OUTPUT_DIR]
"""

import sys

import numpy as np
from PIL import Image

import clraster

output = sys.argv[1] if len(sys.argv) > 1 else "."
ctx = clraster.Context()
mesh = clraster.load("/usr/share/assimp/models/OBJ/spider.obj")  # materials with textures
centre = (mesh.positions.min(axis=0) + mesh.positions.max(axis=0)) / 2
radius = np.linalg.norm(mesh.positions - centre, axis=1).max()
angles = np.radians([20, 110, 200, 290])
eyes = centre + 2.2 * radius * np.stack([np.sin(angles), np.full(4, 0.6), np.cos(angles)], axis=1)
views = clraster.look_at(eyes, centre)
projection = clraster.perspective(40, 1, 0.5 * radius, 4 * radius)

materials = ctx.render(mesh, views, projection, size=(192, 192), shading="material")

# The same views with a program of its own: the eye-space normal picks a colour from a texture made
# in numpy, times a tint of each view's own.
program = clraster.Program(ctx, """
clr_attribute(float3, position)
clr_attribute(float3, normal)
clr_varying(float3, eye_normal)
clr_uniform(float16, mvp)
clr_uniform(float16, normal_matrix)
clr_uniform(float4, tint)
clr_texture(palette)
clr_output(float4, color)

void vertex(clr_vertex* v) {
  v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f));
  v->out.eye_normal = clr_mul3(v->uniforms->normal_matrix, v->in.normal);
}

void fragment(clr_fragment* f) {
  const float3 n = normalize(f->in.eye_normal);
  f->out.color = clr_sample(f, f->textures.palette, n.xy * 0.5f + 0.5f) * f->uniforms->tint;
}
""")
y, x = np.mgrid[0:64, 0:64] / 63
program["palette"] = (np.stack([x, y, 1 - x * y], axis=-1) * 255).astype(np.uint8)  # 3 channels: alpha 1 added
program["tint"] = np.float32([[1, 1, 1, 1], [1, 0.7, 0.7, 1], [0.7, 1, 0.7, 1], [0.7, 0.7, 1, 1]])  # one per view
own = ctx.render(mesh, views, projection, size=(192, 192), shading=program)

sheet = np.concatenate([np.concatenate(list(materials), axis=1), np.concatenate(list(own), axis=1)], axis=0)
Image.fromarray(sheet).save(f"{output}/programs.png")
print(f"wrote {output}/programs.png")
