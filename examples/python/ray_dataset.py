"""N views of a model rendered over a Ray cluster with Ray Data, written as view_00000.png, ...
(docs/python.md, "Scaling out with Ray"). Needs ray[data] and Pillow.

    python examples/python/ray_dataset.py MODEL OUTPUT_DIR [--views N] [--size PIXELS]
        [--shading NAME] [--batch-size B] [--workers W] [--cpus-per-worker C]

ray.init() joins the cluster that RAY_ADDRESS (or `ray start` on this machine) names, else starts
one on this machine: the same command runs on a laptop and on a cluster. Each worker is a Ray Data
actor (map_batches with a callable class): it makes its context, compiles its programs and uploads
the mesh once, then draws a batch of views per call, one submission per batch. The pictures come
back to this process, which writes them.
"""

import argparse
import os
import pathlib

import numpy as np
import ray
from PIL import Image

import clraster


def orbit(mesh, count):
    """`count` cameras on a spiral around the mesh, looking at its centre: view matrices (count,
    4, 4) and one projection. The same numbers on every machine."""
    centre = (mesh.positions.min(axis=0) + mesh.positions.max(axis=0)) / 2
    radius = float(np.linalg.norm(mesh.positions - centre, axis=1).max())
    turns = np.linspace(0, 1, count, endpoint=False)
    angles = 2 * np.pi * 3 * turns
    heights = np.sin(np.pi * (turns - 0.5)) * 0.8
    directions = np.stack([np.cos(heights) * np.sin(angles), np.sin(heights), np.cos(heights) * np.cos(angles)], axis=1)
    views = clraster.look_at(centre + 2.6 * radius * directions, centre)
    return views, clraster.perspective(40, 1, 0.5 * radius, 4 * radius)


class Renderer:
    """A Ray Data worker. Ray gives it `cpus` CPUs; PoCL would otherwise start a thread per core
    of the machine in every worker, so it is told to use that many (docs/python.md, "Worker
    sizing"), before the first OpenCL call of the process."""

    def __init__(self, model, size, shading, cpus):
        os.environ.setdefault("POCL_MAX_PTHREAD_COUNT", str(cpus))  # PoCL up to 3.x (Debian 12's)
        os.environ.setdefault("POCL_CPU_MAX_CU_NUM", str(cpus))     # PoCL 4 and later
        self.ctx = clraster.Context()
        self.mesh = clraster.load(model)
        self.size = size
        self.shading = shading
        _, self.projection = orbit(self.mesh, 1)

    def __call__(self, batch):
        pictures = self.ctx.render(self.mesh, batch["view"], self.projection, size=(self.size, self.size),
                                   shading=self.shading, progress=False)
        return {"index": batch["index"], "picture": pictures}


def batches(count, batch_size):
    """The views each call draws: consecutive ones, split as evenly as np.array_split splits them."""
    return np.array_split(np.arange(count), -(-count // batch_size))


def render_views(model, count, size=256, shading="normal", batch_size=16, workers=2, cpus_per_worker=1):
    """A Ray dataset of `count` rows (index, picture uint8 (size, size, 4)), rendered lazily by
    `workers` actors of `cpus_per_worker` CPUs each, up to `batch_size` views per call."""
    views, _ = orbit(clraster.load(model), count)
    # A block per batch (batches()), so that a call draws the same views whatever Ray schedules:
    # a view's picture depends on its place in its batch (docs/python.md, "Batches").
    rows = ray.data.from_items([{"index": k, "view": view} for k, view in enumerate(views)],
                               override_num_blocks=len(batches(count, batch_size)))
    return rows.map_batches(Renderer, fn_constructor_args=(str(model), size, shading, cpus_per_worker),
                            batch_size=batch_size, concurrency=workers, num_cpus=cpus_per_worker,
                            batch_format="numpy")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("model")
    parser.add_argument("output", type=pathlib.Path)
    parser.add_argument("--views", type=int, default=64)
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--shading", default="normal", choices=clraster.SHADINGS)
    parser.add_argument("--batch-size", type=int, default=16)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--cpus-per-worker", type=int, default=1)
    arguments = parser.parse_args(argv)

    if not ray.is_initialized():  # a caller that started Ray itself (the tests) keeps its own
        ray.init()
    arguments.output.mkdir(parents=True, exist_ok=True)
    dataset = render_views(arguments.model, arguments.views, arguments.size, arguments.shading, arguments.batch_size,
                           arguments.workers, arguments.cpus_per_worker)
    written = 0
    for batch in dataset.iter_batches(batch_size=arguments.batch_size, batch_format="numpy"):
        for index, picture in zip(batch["index"], batch["picture"]):
            Image.fromarray(picture).save(arguments.output / f"view_{index:05d}.png")
            written += 1
    print(f"wrote {written} pictures to {arguments.output}")


if __name__ == "__main__":
    main()
