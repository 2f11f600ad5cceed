"""Devices and scenes: the lists and dicts the CLI prints, and its error messages."""
import json
import subprocess
import sys

import pytest

import sdfbrick
from conftest import DEVICE, ROOT, SCENES, cli


def test_devices_have_the_fields_of_devices_json():
    devices = sdfbrick.devices(DEVICE)
    assert isinstance(devices, list) and devices
    assert all(isinstance(d, dict) for d in devices)
    assert any(d["selected"] for d in devices)
    _, out, _ = cli("devices", "--json")
    listed = json.loads(out)
    assert [d["name"] for d in devices] == [d["name"] for d in listed]
    assert [sorted(d) for d in devices] == [sorted(d) for d in listed]


def test_context_devices_and_placement(ctx):
    assert [d["index"] for d in ctx.devices] == [d["index"] for d in sdfbrick.devices(DEVICE) if d["selected"]]
    assert ctx.placement == "whole"


def test_unknown_device_is_input_error():
    with pytest.raises(sdfbrick.InputError) as e:
        sdfbrick.Context(device="no-such-device-name")
    assert isinstance(e.value, ValueError)
    status, _, err = cli("devices", check=False, device="no-such-device-name")
    assert status == 2
    assert err.strip() == f"sdfbrick: {e.value}"



def test_scene_round_trip(spheres):
    d = spheres.to_dict()
    assert d["name"] == "spheres"
    again = sdfbrick.Scene.from_dict(d)
    assert again.to_dict() == d
    assert again.file is None and spheres.file.endswith("spheres.json")
    assert spheres.name == "spheres" and spheres.time == 0.0
    assert sdfbrick.Scene.from_json(spheres.to_json()).to_dict() == d


def test_scene_info_is_scene_info_json(spheres):
    info = spheres.info()
    _, out, _ = cli("scene", "info", "--json", SCENES / "spheres.json")
    assert info == json.loads(out)


def test_scene_error_names_the_json_path_as_the_cli_does(spheres, tmp_path):
    d = spheres.to_dict()
    d["geometries"][0]["edits"][1]["radius"] = -1.0
    with pytest.raises(sdfbrick.InputError) as e:
        sdfbrick.Scene.from_dict(d)
    assert isinstance(e.value, ValueError)
    message = str(e.value)
    assert message.startswith("<dict>: /geometries/0/edits/1/radius: ")
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(d))
    status, _, err = cli("scene", "info", bad, check=False)
    assert status == 2
    assert err.strip() == f"sdfbrick: {bad}: {message.removeprefix('<dict>: ')}"


def test_scene_from_dict_refuses_what_json_cannot_hold(spheres):
    d = spheres.to_dict()
    d["geometries"][0]["edits"][0]["radius"] = float("nan")
    with pytest.raises(sdfbrick.InputError, match=r"/geometries/0/edits/0/radius: number is not finite"):
        sdfbrick.Scene.from_dict(d)
    d["geometries"][0]["edits"][0]["radius"] = object()
    with pytest.raises(TypeError, match=r"/geometries/0/edits/0/radius"):
        sdfbrick.Scene.from_dict(d)
    with pytest.raises(TypeError):
        sdfbrick.Scene.from_dict([1, 2])


def test_missing_scene_file_is_input_error(tmp_path):
    with pytest.raises(sdfbrick.InputError, match="nothing.json"):
        sdfbrick.Scene.load(str(tmp_path / "nothing.json"))


def test_generated_scene():
    s = sdfbrick.Scene.generate("drops")
    assert s.name == "drops"
    assert len(s.to_dict()["geometries"]) >= 1


def test_scene_from_dict_takes_numpy_values(spheres):
    np = pytest.importorskip("numpy")
    d = spheres.to_dict()
    edit = d["geometries"][0]["edits"][0]
    edit["position"] = np.array(edit["position"])
    edit["radius"] = np.float32(edit["radius"])
    assert sdfbrick.Scene.from_dict(d).to_dict() == spheres.to_dict()


def test_a_mesh_wound_inward_is_turned_with_a_warning(tmp_path):
    subprocess.run([sys.executable, str(ROOT / "tools" / "make_knot_mesh.py"), str(tmp_path / "knot.obj"),
                    "--winding", "inward", "--u", "40", "--v", "8"], check=True)
    (tmp_path / "s.json").write_text(json.dumps(
        {"geometries": [{"name": "g", "edits": [{"primitive": "mesh", "file": "knot.obj", "resolution": 16}]}]}))
    scene = sdfbrick.Scene.load(tmp_path / "s.json")
    assert len(scene.warnings) == 1
    assert "knot.obj" in scene.warnings[0] and "turned to face outward" in scene.warnings[0]
    assert sdfbrick.Scene.load(SCENES / "knot.json").warnings == []
