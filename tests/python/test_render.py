"""Context.render: the report of `sdfbrick render --json`, the pictures as NumPy views."""
import numpy as np
import pytest

import sdfbrick
from conftest import SCENES, cli_json, keys

W, H = 64, 40


def test_render_arrays_are_views(ctx, spheres):
    r = ctx.render(spheres, brick_size=0.25, width=W, height=H)
    assert r.image.shape == (H, W, 3) and r.image.dtype == np.float32
    assert r.depth.shape == (H, W) and r.depth.dtype == np.float32
    assert r.normals.shape == (H, W, 3) and r.normals.dtype == np.float32
    assert r.counters.shape == (H, W, 2) and r.counters.dtype == np.uint32
    for a in (r.image, r.depth, r.normals, r.counters):
        # each array views memory a capsule owns: none was copied into a NumPy buffer of its own
        assert not a.flags.owndata and type(a.base).__name__ == "PyCapsule"
    # depth and normals view the tracer's one buffer of (nx, ny, nz, depth) per pixel
    address = lambda a: a.__array_interface__["data"][0]
    assert r.depth.strides == (W * 16, 16) and r.normals.strides == (W * 16, 16, 4)
    assert address(r.depth) - address(r.normals) == 12
    assert np.may_share_memory(r.depth, r.normals)
    assert (r.depth >= 0).any() and (r.depth < 0).any(), "hits and misses"
    hit = r.depth >= 0
    assert np.allclose(np.linalg.norm(r.normals[hit], axis=1), 1.0, atol=1e-3)
    assert r.reference_image is None and r.accuracy is None


def test_arrays_outlive_the_result(ctx, spheres):
    depth = ctx.render(spheres, brick_size=0.25, width=W, height=H).depth
    ctx.render(spheres, brick_size=0.25, width=W, height=H, method="analytic")
    assert (depth >= 0).any()


def test_render_report_equals_the_cli_report(ctx, spheres, tmp_path):
    r = ctx.render(spheres, brick_size=0.25, width=W, height=H, compare=True)
    expected = cli_json(tmp_path, "render", SCENES / "spheres.json", "--brick-size", 0.25, "--width", W, "--height", H,
                        "--compare", "--out", tmp_path / "spheres.ppm")
    assert r.report["command"] == "render"
    assert {k: v for k, v in keys(r.report).items() if k != "images"} == \
        {k: v for k, v in keys(expected).items() if k != "images"}
    for key in ("digest", "bricks", "settings", "tuning", "placement", "devices_agree", "accuracy", "scene"):
        assert r.report[key] == expected[key], key
    assert r.report["images"] == {"image": None}


def test_compare_gives_accuracy_and_reference_pictures(ctx, spheres):
    r = ctx.render(spheres, brick_size=0.25, width=W, height=H, compare=True)
    accuracy = r.accuracy
    for key in ("mismatch_fraction", "depth_error_mean", "depth_error_p99", "normal_error_mean_deg", "psnr_db"):
        assert key in accuracy, key
    assert accuracy["mismatch_fraction"] < 0.05
    assert r.reference_image.shape == (H, W, 3) and r.difference_image.shape == (H, W, 3)
    assert r.reference_depth.shape == (H, W)
    assert "reference" in [s["name"] for s in r.report["stages"]]


def test_modes_and_reference(ctx, spheres):
    shaded = ctx.render(spheres, brick_size=0.25, width=W, height=H, mode="shaded", shadow_rays=1, ao_rays=1)
    assert shaded.image.shape == (H, W, 3) and shaded.image.max() > 0
    assert shaded.report["settings"]["shadow_rays"] == 1
    reference = ctx.render(spheres, width=W, height=H, reference=True)
    assert reference.report["settings"]["reference"] is True
    assert "bricks" not in reference.report
    steps = ctx.render(spheres, brick_size=0.25, width=W, height=H, mode="steps")
    assert steps.report["settings"]["mode"] == "steps"


def test_register_cap_is_kept_as_given_and_changes_no_bit(ctx, spheres):
    plain = ctx.render(spheres, brick_size=0.25, width=W, height=H, method="hybrid")
    capped = ctx.render(spheres, brick_size=0.25, width=W, height=H, method="hybrid", max_registers=64)
    assert capped.report["tuning"]["trace_primary"]["params"]["registers"] == 64
    assert capped.report["digest"] == plain.report["digest"]
    with pytest.raises(sdfbrick.InputError, match=r"^max_registers: "):
        ctx.render(spheres, brick_size=0.25, width=W, height=H, max_registers=256)
