"""Context.tune: the report of `sdfbrick tune --json`; save=True writes the tuning database."""
import json

import pytest

import sdfbrick
from conftest import DEVICE, SCENES

SMALL = dict(kernels=["evaluate"], strategy="random", budget=2, repeat=1, warmup=0, brick_size=0.25)


def test_tune_report(ctx, spheres):
    lines = []
    report = ctx.tune(spheres, progress=lines.append, **SMALL)
    assert report["command"] == "tune" and report["tuning_db"] is None
    (device,) = report["devices"]
    assert device["device"]["index"] == ctx.devices[0]["index"]
    (kernel,) = [k for k in device if k != "device"]
    assert len(device[kernel]["evaluated_configurations"]) <= 2
    assert set(device[kernel]["params"]) == {"chunk", "group", "registers"}
    assert lines[0].startswith("device ") and any("best" in line for line in lines)


def test_tune_saves_the_database_the_context_then_uses(spheres, tmp_path):
    db = tmp_path / "tuning.json"
    with sdfbrick.Context(device=DEVICE, tuning_db=str(db)) as c:
        report = c.tune(spheres, save=True, **SMALL)
        assert report["tuning_db"] == str(db)
        (kernel,) = [k for k in report["devices"][0] if k != "device"]
        best = report["devices"][0][kernel]["params"]
        assert json.loads(db.read_text())
        built = c.build(spheres, brick_size=0.25)
        assert built["settings"]["chunk"] == best["chunk"] and built["settings"]["group"] == best["group"]
        assert built["tuning"][kernel]["layer"] == "file"


def test_tune_refuses_bad_kernels_and_saving_without_a_database(ctx, spheres):
    with pytest.raises(sdfbrick.InputError, match="^kernels: "):
        ctx.tune(spheres, kernels=["shade"])
    with sdfbrick.Context(device=DEVICE, tuning=False) as c:
        with pytest.raises(sdfbrick.InputError, match="tuning database"):
            c.tune(spheres, save=True, **SMALL)


def test_tune_traces_with_the_method_given(ctx, spheres):
    report = ctx.tune(spheres, kernels=["trace"], strategy="random", budget=1, repeat=1, warmup=0, brick_size=0.25,
                      width=32, height=24, method="hybrid")
    assert report["devices"][0]["trace_primary"]["method"] == "hybrid"
    with pytest.raises(sdfbrick.InputError, match="^method: "):
        ctx.tune(spheres, kernels=["trace"], method="cubic", **{k: v for k, v in SMALL.items() if k != "kernels"})


def test_tune_over_several_scenes_reports_each_ones_time(ctx, spheres):
    cubes = sdfbrick.Scene.load(str(SCENES / "cubes.json"))
    report = ctx.tune([spheres, cubes], **SMALL)
    assert report["scenes"] == [spheres.file, cubes.file]
    record = report["devices"][0]["brick_evaluate"]
    assert record["scenes"] == report["scenes"] and "geometric mean" in record["objective"]
    for measured in record["evaluated_configurations"]:
        first, second = measured["scene_ms"]
        assert measured["ms"] == pytest.approx((first * second) ** 0.5)
    with pytest.raises(sdfbrick.InputError, match="^scenes: "):
        ctx.tune([], **SMALL)
    with pytest.raises(sdfbrick.InputError, match="^scenes: "):
        ctx.tune([spheres, "cubes.json"], **SMALL)
