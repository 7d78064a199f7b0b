"""Eight views of a model around it in one batch, and its visibility buffer shaded in numpy; writes
views.png and visibility.png (docs/python.md shows both). Needs numpy and Pillow.

    python examples/python/views.py [MODEL] [OUTPUT_DIR]
"""

import sys

import numpy as np
from PIL import Image

import clraster

model = sys.argv[1] if len(sys.argv) > 1 else "/usr/share/assimp/models/OBJ/WusonOBJ.obj"
output = sys.argv[2] if len(sys.argv) > 2 else "."

ctx = clraster.Context()
mesh = clraster.load(model)
centre = (mesh.positions.min(axis=0) + mesh.positions.max(axis=0)) / 2
radius = np.linalg.norm(mesh.positions - centre, axis=1).max()

# Eight cameras on a circle around the model, slightly above it.
angles = np.linspace(0, 2 * np.pi, 8, endpoint=False)
eyes = centre + 2.6 * radius * np.stack([np.sin(angles), np.full(8, 0.4), np.cos(angles)], axis=1)
views = clraster.look_at(eyes, centre)                           # (8, 4, 4)
projection = clraster.perspective(40, 1, 0.5 * radius, 4 * radius)  # (4, 4)

pictures = ctx.render(mesh, views, projection, size=(192, 192))  # uint8 (8, 192, 192, 4), one submission
sheet = pictures.reshape(2, 4, 192, 192, 4).transpose(0, 2, 1, 3, 4).reshape(2 * 192, 4 * 192, 4)
Image.fromarray(sheet).save(f"{output}/views.png")

# The visibility buffer: which triangle each pixel sees, and where on it. Shade it in numpy: the
# interpolated normal lit from the camera, and the triangle ids as colours beside it.
vb = ctx.rasterize(mesh, views[2], projection, size=(192, 192))
normals = clraster.interpolate(mesh.normals, vb, mesh)[0]
light = (eyes[2] - centre) / np.linalg.norm(eyes[2] - centre)  # a headlight
lit = np.clip(normals @ light, 0, 1) * (vb.triangle[0] >= 0)
ids = vb.triangle[0]
palette = np.random.default_rng(0).integers(64, 256, (len(mesh.indices), 3), dtype=np.uint8)
colours = np.where((ids >= 0)[..., None], palette[np.maximum(ids, 0)], 0).astype(np.uint8)
shaded = np.repeat((lit * 255).astype(np.uint8)[..., None], 3, axis=-1)
Image.fromarray(np.concatenate([shaded, colours], axis=1)).save(f"{output}/visibility.png")
print(f"wrote {output}/views.png and {output}/visibility.png")
