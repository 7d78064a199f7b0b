"""examples/python/ray_dataset.py on a local Ray of 2 CPUs: its pictures are those one process
draws of the same batches, byte for byte. Ray is installed for the tests (scripts/test.sh, from
python/requirements-ray.txt): without it this test fails rather than skips."""

import sys

import numpy as np
import pytest
from PIL import Image

import clraster
from conftest import REPOSITORY

EXAMPLES = REPOSITORY / "examples" / "python"


@pytest.fixture
def local_ray(monkeypatch):
    import ray
    # Ray's workers import the example's module by name, as this process does.
    monkeypatch.syspath_prepend(str(EXAMPLES))
    monkeypatch.setenv("PYTHONPATH", str(EXAMPLES) + ":" + ":".join(sys.path))
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield ray
    ray.shutdown()


def test_the_ray_example_draws_what_one_process_draws(ctx, wuson, tmp_path, local_ray):
    import ray_dataset
    count, batch_size, size = 7, 3, 64
    ray_dataset.main([str(wuson), str(tmp_path), "--views", str(count), "--size", str(size), "--batch-size",
                      str(batch_size), "--workers", "2", "--cpus-per-worker", "1"])
    written = sorted(tmp_path.glob("view_*.png"))
    assert [path.name for path in written] == [f"view_{k:05d}.png" for k in range(count)]

    mesh = clraster.load(wuson)
    views, projection = ray_dataset.orbit(mesh, count)
    for batch in ray_dataset.batches(count, batch_size):
        expected = ctx.render(mesh, views[batch], projection, size=(size, size))
        for k, picture in zip(batch, expected):
            assert (picture[..., :3] != 0).sum() > 200, f"view {k} sees the model"
            with Image.open(tmp_path / f"view_{k:05d}.png") as drawn:
                np.testing.assert_array_equal(np.asarray(drawn), picture, err_msg=f"view {k}")
