"""Context.sweep and Context.stability: the rows of `sdfbrick sweep`, the atlas's report."""
import pytest

import sdfbrick
from conftest import SCENES

SMALL = {"scenes": [str(SCENES / "spheres.json")], "brick_sizes": [0.5], "width": 32, "height": 24, "warmup": 0,
         "repeat": 1}


def test_sweep_rows(ctx, spheres):
    seen = []
    rows = ctx.sweep(SMALL, chunks=[16, 32], progress=seen.append)
    assert [r["chunk"] for r in rows] == [16, 32]
    assert all(r["status"] == "ok" for r in rows)
    assert rows[0]["bricks"] == rows[1]["bricks"] > 0
    assert rows[0]["mismatch"] is not None
    assert [p["done"] for p in seen] == [0, 1, 2] and seen[-1]["total"] == 2
    assert SMALL["brick_sizes"] == [0.5], "the spec given is not changed"
    # keyword arguments alone, a single value as a list of one, scenes as Scene objects from files
    again = ctx.sweep(scenes=[spheres], brick_sizes=0.5, chunks=16, width=32, height=24, warmup=0, repeat=1,
                      accuracy=False)
    assert len(again) == 1 and again[0]["bricks"] == rows[0]["bricks"]


def test_sweep_cache_resumes(ctx, tmp_path):
    cache = tmp_path / "cache.jsonl"
    ctx.sweep(SMALL, cache=str(cache))
    seen = []
    rows = ctx.sweep(SMALL, cache=str(cache), progress=seen.append)
    assert len(rows) == 1 and seen[-1]["cached"] == 1


def test_sweep_errors(ctx, spheres):
    with pytest.raises(sdfbrick.InputError, match="flavours"):
        ctx.sweep({**SMALL, "flavours": [1]})
    with pytest.raises(sdfbrick.InputError, match="scenes"):
        ctx.sweep({**SMALL, "scenes": [sdfbrick.Scene.from_dict(spheres.to_dict())]})
    with pytest.raises(TypeError):
        ctx.sweep([1, 2])


def test_sweep_as_frame(ctx):
    pandas = pytest.importorskip("pandas")
    frame = ctx.sweep(SMALL, as_frame=True)
    assert isinstance(frame, pandas.DataFrame) and len(frame) == 1


def test_stability_report(ctx):
    report = ctx.stability([str(SCENES / "stability" / "face_rays.json")], brick_size=0.25, methods="sphere",
                           normals=["continuous"], formats=["int8"], builds=["uniform"], width=33, height=17)
    assert report["command"] == "stability"
    assert len(report["cells"]) == 1
    assert report["width"] == 33
    with pytest.raises(sdfbrick.InputError, match="^methods: "):
        ctx.stability([str(SCENES / "stability" / "face_rays.json")], methods=["x"])


def test_stability_writes_its_pictures(ctx, tmp_path):
    folder = tmp_path / "pictures"
    ctx.stability([str(SCENES / "stability" / "face_rays.json")], brick_size=0.25, methods="sphere",
                  normals=["continuous"], formats=["int8"], builds=["uniform"], width=33, height=17, pictures=folder)
    names = sorted(p.name for p in folder.iterdir())
    assert any(n.endswith("-reference.png") or n.endswith("-reference.ppm") for n in names), names
    assert len(names) >= 2, names
