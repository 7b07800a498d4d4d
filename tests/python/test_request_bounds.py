"""Every request is bounded before work starts: a scene whose cost is past a limit is refused at
CreateSession in well under a second, naming the limit and what to lower."""
from __future__ import annotations

import time

import pytest

from culinarycut import Client
from culinarycut.errors import InvalidArgument
from culinarycut.launch import ServerProcess, server_binary

EFFECTS = {"mpm": True, "damage": True, "friction": True, "topology": True, "force_sensing": True}


def food_scene(*objects, quality="draft", **extra) -> dict:
    return {"quality": quality, "effects": EFFECTS, "objects": list(objects), **extra}


@pytest.mark.parametrize("scene, field, hint", [
    # 216 million particles at the fine preset: refused from the melon's box, before sampling.
    (food_scene({"food": "melon", "scale": 3}, quality="fine"), "scene.objects[0]", "particles"),
    (food_scene({"food": "melon", "scale": 10}, quality="fine"), "scene.objects[0]", "off the table"),
    (food_scene({"food": "cucumber"}, mpm={"cfl": 1e-6}), "scene.mpm.cfl", "MPM substeps per control step"),
    (food_scene({"food": "cucumber"}, mpm={"cfl": 1e-300}), "scene.mpm.cfl", "e+302 MPM substeps"),
    (food_scene({"food": "cucumber", "material_overrides": {"youngs_modulus_pa": 2.5e11}}),
     "youngs_modulus_pa", "1e9"),
    (food_scene({"food": "cucumber", "material_overrides": {"density_kg_m3": 1e-9}}), "density_kg_m3", "[10, 1e4]"),
    (food_scene({"food": "cucumber", "material_overrides": {"maxwell_modulus_ratio": 1e3}}),
     "maxwell_modulus_ratio", "[0, 100]"),
    (food_scene({"food": "apple", "pose": {"position": [0.5, 0.0, 0.05]}},
                {"food": "apple", "pose": {"position": [3.5, 0.0, 0.05]}}), "scene.objects[1].pose.position", "off the table"),
    ({"cameras": [{"name": f"c{i}", "width": 2048, "height": 2048,
                   "pose": {"position": [0.5, 0.0, 1.0], "quaternion": [0, 1, 0, 0]}} for i in range(8)]},
     "scene.cameras", "pixels"),
])
def test_an_unbounded_scene_is_refused_before_any_work(client, scene, field, hint):
    started = time.monotonic()
    with pytest.raises(InvalidArgument) as refused:
        client.create_session(scene)
    elapsed = time.monotonic() - started
    assert field in refused.value.details and hint in refused.value.details, refused.value.details
    assert elapsed < 1.0, f"refused only after {elapsed:.2f} s"


def test_a_nan_camera_quaternion_is_refused_naming_the_field(client):
    scene = {"cameras": [{"name": "c", "pose": {"position": [0.5, 0.0, 1.0], "quaternion": ["NaN", 1, 0, 0]}}]}
    with pytest.raises(InvalidArgument, match=r"scene\.cameras\[0\]\.pose\.quaternion"):
        client.create_session(scene)


def peak_rss_mb(pid: int) -> float:
    """The process's peak resident memory (VmHWM), MB."""
    with open(f"/proc/{pid}/status") as status:
        for line in status:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024.0
    raise AssertionError("no VmHWM in /proc/PID/status")


def test_a_huge_melon_is_refused_without_taking_memory():
    # A server of its own, so its peak memory is this request's and the start's alone.
    with ServerProcess(server_binary(), max_sessions=1) as server, Client(server.address) as client:
        with pytest.raises(InvalidArgument, match="particles"):
            client.create_session(food_scene({"food": "melon", "scale": 3}, quality="fine"))
        assert peak_rss_mb(server.proc.pid) < 200.0
