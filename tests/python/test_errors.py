"""Errors: InputError (a ValueError) for bad input, DeviceError (a RuntimeError) for device
failures, each with the CLI's one line; TypeError for wrong types and unknown keywords; the GIL
released while devices work."""
import os
import subprocess
import sys
import threading
import time

import pytest

import sdfbrick
from conftest import DEVICE, SCENES, cli


def test_unknown_keyword_names_it(ctx, spheres):
    with pytest.raises(TypeError, match="'brick_sise'"):
        ctx.build(spheres, brick_sise=0.25)
    with pytest.raises(TypeError, match="'widht'"):
        ctx.render(spheres, widht=32)
    with pytest.raises(TypeError, match="'brick_size'"):
        ctx.sweep(brick_size=[0.25])


def test_wrong_type_names_the_argument(ctx, spheres):
    with pytest.raises(TypeError, match=r"build\(\): chunk must be an int, got str"):
        ctx.build(spheres, chunk="64")
    with pytest.raises(TypeError, match=r"build\(\): chunk must be an int, got float"):
        ctx.build(spheres, chunk=64.0)
    with pytest.raises(TypeError, match=r"cull must be a bool, got int"):
        ctx.build(spheres, cull=1)
    with pytest.raises(TypeError, match=r"brick_size must be a number, got str"):
        ctx.build(spheres, brick_size="0.25")


def test_setting_error_is_input_error_with_the_cli_message(ctx, spheres):
    with pytest.raises(sdfbrick.InputError) as e:
        ctx.build(spheres, brick_size=0.25, chunk=8)
    assert isinstance(e.value, ValueError)
    assert e.value.setting == "chunk" and e.value.argument == "chunk"
    status, _, err = cli("build", SCENES / "spheres.json", "--brick-size", 0.25, "--chunk", 8, check=False)
    assert status == 2
    # the CLI names its flag where the module names its keyword
    assert err.strip() == f"sdfbrick: --{e.value}"
    with pytest.raises(sdfbrick.InputError, match=r"^group: ") as e:
        ctx.build(spheres, brick_size=0.25, group=100000)
    assert e.value.setting == "eval_group"
    with pytest.raises(sdfbrick.InputError, match=r"^format: format must be int8, int16 or float"):
        ctx.build(spheres, format="int4")
    with pytest.raises(sdfbrick.InputError, match=r"^width: "):
        ctx.render(spheres, width=0, height=10)
    with pytest.raises(sdfbrick.InputError, match=r"^mode: "):
        ctx.render(spheres, mode="x-ray")


def test_placement_is_checked():
    with pytest.raises(sdfbrick.InputError, match="placement must be whole, replicate or split"):
        sdfbrick.Context(device=DEVICE, placement="everywhere")


CHILD = """
import sys, sdfbrick
ctx = sdfbrick.Context(device=sys.argv[1])
scene = sdfbrick.Scene.load(sys.argv[2])
try:
    ctx.build(scene, brick_size=0.25)
except sdfbrick.DeviceError as e:
    assert isinstance(e, RuntimeError)
    print(e)
"""


def test_device_failure_is_device_error_with_the_cli_message():
    env = {**os.environ, "SDFBRICK_FAULT": "launch:3"}
    child = subprocess.run([sys.executable, "-c", CHILD, DEVICE, str(SCENES / "spheres.json")], env=env,
                           capture_output=True, text=True, timeout=300)
    assert child.returncode == 0, child.stderr
    message = child.stdout.strip()
    assert "injected" in message
    status, _, err = cli("build", SCENES / "spheres.json", "--brick-size", 0.25, env={"SDFBRICK_FAULT": "launch:3"},
                         check=False)
    assert status == 1
    assert err.strip() == f"sdfbrick: error: {message}"


def test_closed_context_refuses(spheres):
    c = sdfbrick.Context(device=DEVICE)
    c.close()
    with pytest.raises(RuntimeError, match="closed"):
        c.build(spheres)


def test_the_gil_is_released_during_a_render(ctx, spheres):
    ctx.render(spheres, brick_size=0.25, width=96, height=64)  # programs built, lane made
    ticks, calls = [], []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.001)

    ticker = threading.Thread(target=tick)
    ticker.start()
    try:
        time.sleep(0.02)
        first = time.monotonic()
        while time.monotonic() - first < 0.3:  # renders for 0.3 s, however fast the device
            start = time.monotonic()
            ctx.render(spheres, brick_size=0.25, width=96, height=64, repeat=2)
            calls.append((start, time.monotonic()))
    finally:
        stop.set()
        ticker.join()
    inside = sum(1 for t in ticks if any(start < t < end for start, end in calls))
    in_calls = sum(end - start for start, end in calls)
    # with the GIL held the ticker could not run while a render did: no tick would fall inside one
    assert inside >= 0.25 * in_calls / 0.0011, (inside, in_calls, len(calls))
