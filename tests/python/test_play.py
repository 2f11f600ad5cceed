"""Context.play: the report of `sdfbrick play --json`, an edit log applied frame by frame, errors."""
import json

import pytest

import sdfbrick
from conftest import cli_json

SCENE = {
    "name": "falling", "time": 0.0,
    "camera": {"orbit": {"target": [0, 0, 0], "distance": 4.0}},
    "geometries": [
        {"name": "ground", "edits": [{"primitive": "box", "half_extents": [1.5, 0.1, 1.5], "position": [0, -0.8, 0]}]},
        {"name": "drop", "edits": [{"primitive": "sphere", "radius": 0.4, "blend": 0.1,
                                    "animation": {"velocity": [0, -1.0, 0], "wrap_y": [-0.5, 1.0]}}]}],
}


def test_play_report_equals_the_cli_report(ctx, tmp_path):
    (tmp_path / "falling.json").write_text(json.dumps(SCENE))
    scene = sdfbrick.Scene.load(str(tmp_path / "falling.json"))
    r = ctx.play(scene, frames=3, fps=10, brick_size=0.125, width=48, height=32, digests=True)
    expected = cli_json(tmp_path, "play", tmp_path / "falling.json", "--frames", 3, "--fps", 10, "--brick-size", 0.125,
                        "--width", 48, "--height", 32, "--digests")
    assert r["command"] == "play" and len(r["frames"]) == 3
    assert [f["digest"] for f in r["frames"]] == [f["digest"] for f in expected["frames"]]
    assert [f["geometries_rebuilt"] for f in r["frames"]] == [2, 1, 1]
    assert set(r["summary"]) == set(expected["summary"])
    assert r["fps"] == 10


def test_play_applies_an_edit_log(ctx, tmp_path):
    log = tmp_path / "strokes.jsonl"
    log.write_text(json.dumps({"frame": 1, "op": "append", "geometry": "ground",
                               "edit": {"primitive": "sphere", "radius": 0.3, "position": [0.5, -0.7, 0]}}) + "\n")
    scene = sdfbrick.Scene.from_dict(SCENE)
    r = ctx.play(scene, frames=2, dt=0.05, edits=str(log), work="bvh", brick_size=0.125, digests=True)
    assert [f["operations"] for f in r["frames"]] == [0, 1]
    assert r["work"] == "bvh" and "digest" not in r["frames"][1] and "brick_digest" in r["frames"][1]
    assert r["fps"] is None


def test_play_refuses_bad_arguments(ctx, tmp_path):
    scene = sdfbrick.Scene.from_dict(SCENE)
    with pytest.raises(TypeError, match="'frame'"):
        ctx.play(scene, frame=3)
    with pytest.raises(TypeError, match="fps and dt exclude each other"):
        ctx.play(scene, fps=30, dt=0.1)
    with pytest.raises(sdfbrick.InputError, match="fps must be > 0"):
        ctx.play(scene, fps=0)
    with pytest.raises(sdfbrick.InputError, match="frames must lie in 1 .. 100000"):
        ctx.play(scene, frames=0)
    log = tmp_path / "bad.jsonl"
    log.write_text('{"frame": 0, "op": "remove", "geometry": "drop", "index": 3}\n')
    with pytest.raises(sdfbrick.InputError, match=r"bad.jsonl:1: /index: no edit 3"):
        ctx.play(scene, edits=str(log))
