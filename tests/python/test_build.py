"""Context.build: the report of `sdfbrick build --json` for the same settings."""
import pytest

import sdfbrick
from conftest import DEVICE, SCENES, cli_json, keys


def test_build_report_equals_the_cli_report(ctx, spheres, tmp_path):
    report = ctx.build(spheres, brick_size=0.25)
    expected = cli_json(tmp_path, "build", SCENES / "spheres.json", "--brick-size", 0.25)
    assert report["command"] == "build"
    assert keys(report) == keys(expected)
    for key in ("digest", "list_digest", "bricks", "edit_evaluations", "settings", "tuning", "tuning_db", "repeat",
                "warmup", "placement", "devices_agree", "edit_lists_agree"):
        assert report[key] == expected[key], key
    assert report["scene"] == expected["scene"]
    for mine, theirs in zip(report["geometries"], expected["geometries"]):
        assert mine["bricks"] == theirs["bricks"]
        assert [level["bricks"] for level in mine["levels"]] == [level["bricks"] for level in theirs["levels"]]
    assert report["bricks"] > 0


def test_build_settings_round_trip(ctx, spheres):
    first = ctx.build(spheres, brick_size=0.25, format="int16", cull=False, chunk=32)
    assert first["settings"]["format"] == "int16" and first["settings"]["cull"] is False
    assert first["settings"]["chunk"] == 32
    again = ctx.build(spheres, **first["settings"])
    assert again["digest"] == first["digest"]
    culled = ctx.build(spheres, brick_size=0.25, format="int16")
    assert culled["digest"] == first["digest"], "culling on and off give the same bricks"
    split = ctx.build(spheres, brick_size=0.25, format="int16", count_parts=4, count_splits=2, cull_siblings=1,
                      count_untested=16)
    assert split["settings"]["count_splits"] == 2 and split["settings"]["cull_siblings"] == 1
    assert split["settings"]["count_untested"] == 16
    assert split["digest"] == first["digest"], "the count's work-groups change no bit"


def test_repeats_and_lanes_keep_state(spheres):
    with sdfbrick.Context(device=DEVICE) as c:
        first = c.build(spheres, brick_size=0.25)
        again = c.build(spheres, brick_size=0.25, repeat=2)
    assert again["repeat"] == 2 and again["warmup"] == 1 and again["captures"]["repeat"] == 2
    # the first call made the lane (its builder and programs); the second found it made
    assert again["wall_breakdown_ms"]["setup_once"] < 0.1 * first["wall_breakdown_ms"]["setup_once"]


def test_adaptive_build_from_tolerance_voxels(ctx, spheres, tmp_path):
    report = ctx.build(spheres, brick_size=0.25, tolerance_voxels=0.5)
    expected = cli_json(tmp_path, "build", SCENES / "spheres.json", "--brick-size", 0.25, "--tolerance-voxels", 0.5)
    assert report["digest"] == expected["digest"]
    assert report["settings"]["tolerance"] == expected["settings"]["tolerance"] > 0


def test_scene_from_a_dict_builds_the_same_bricks(ctx, spheres):
    made = sdfbrick.Scene.from_dict(spheres.to_dict())
    assert ctx.build(made, brick_size=0.25)["digest"] == ctx.build(spheres, brick_size=0.25)["digest"]
    assert ctx.build(made, brick_size=0.25)["scene"]["file"] == ""
