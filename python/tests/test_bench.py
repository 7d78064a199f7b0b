"""python -m clraster.bench, small: both sides draw the same pictures and it reports their rates."""

import json

from clraster import bench


def test_the_benchmark_compares_the_same_pictures(capsys):
    bench.main(["--views", "4", "--size", "64", "--triangles", "20000", "--repeats", "1", "--json"])
    result = json.loads(capsys.readouterr().out)
    assert result["triangles"] == 20000 and result["views"] == 4
    assert "llvmpipe" in result["moderngl_renderer"]
    assert result["pixels_differing_from_moderngl"] < 0.002
    for key in ("clraster_render", "clraster_rasterize", "moderngl"):
        assert len(result["times_s"][key]) == 1
        assert result[f"{key}_pictures_per_second"] > 0
