"""The MPM kernels' instruction set: one build per x86-64 level, the loader's pick (or --simd's) reported by
cc-cut's summary, GetServerInfo, `culinarycut info` and every result row; the same bits twice within a level;
a level the build lacks refused; and the benchmark runner refusing to mix levels in one run."""
from __future__ import annotations

import json
import platform
import subprocess
import sys
from pathlib import Path

import pytest

from bench_cli import bench
from stored_runs import rows_so_far
from culinarycut import Client
from culinarycut.launch import ServerProcess, server_binary
from culinarycut.safety.binary import cc_cut_binary

pytestmark = pytest.mark.skipif(platform.machine() not in ("x86_64", "AMD64"),
                                reason="one MPM build per x86-64 level: x86-64 only")
BASELINE = "x86-64"
# A draft cucumber cut fast: about a thousand particles, a second or two of cc-cut.
SCENE = {
    "scene": {"effects": {"mpm": True, "plasticity": True, "damage": True, "friction": True, "force_sensing": True},
              "objects": [{"food": "cucumber", "scale": 0.5, "pose": {"position": [0.5, 0.0]}}],
              "quality": "draft", "seed": 3},
    "solver": {"threads": 2},
    "knife": {"cut_fraction": 0.4, "start_above_top_m": 0.004, "end_below_bottom_m": 0.001,
              "descent_speed_m_s": 0.5, "lift_speed_m_s": 1.0, "settle_s": 0.01},
}


def cc_cut(tmp_path: Path, name: str, *args: str) -> subprocess.CompletedProcess:
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps(SCENE))
    return subprocess.run([str(cc_cut_binary()), str(scene), "--quiet", "--out", str(tmp_path / name), *args],
                          capture_output=True, text=True, timeout=300)


def loader_pick(tmp_path: Path) -> str:
    """The level the loader chooses on this CPU (cc-cut's summary says it)."""
    done = cc_cut(tmp_path, "auto")
    assert done.returncode == 0, done.stderr
    return json.loads((tmp_path / "auto" / "summary.json").read_text())["simd"]


def test_each_level_gives_the_same_bits_twice_and_says_which_it_ran(tmp_path):
    levels = sorted({BASELINE, loader_pick(tmp_path)})
    steps = {}
    for level in levels:
        for run in ("first", "second"):
            done = cc_cut(tmp_path, f"{level}-{run}", "--simd", level)
            assert done.returncode == 0, done.stderr
            summary = json.loads((tmp_path / f"{level}-{run}" / "summary.json").read_text())
            assert summary["simd"] == level
            steps[level, run] = (tmp_path / f"{level}-{run}" / "steps.csv").read_bytes()
        assert steps[level, "first"] == steps[level, "second"], f"two runs at {level} differ"
        assert steps[level, "first"].count(b"\n") > 50  # a real cut, not an empty file


def test_a_level_the_build_or_cpu_lacks_is_refused(tmp_path):
    refused = cc_cut(tmp_path, "bad", "--simd", "x86-64-v9")
    assert refused.returncode == 2
    assert "--simd must be auto or a level this build has (x86-64" in refused.stderr
    server = subprocess.run([str(server_binary()), "--listen", "127.0.0.1:0", "--simd", "sse9"],
                            capture_output=True, text=True, timeout=30)
    assert server.returncode == 2 and "--simd must be auto or a level this build has" in server.stdout + server.stderr


def test_the_server_reports_its_level_and_a_run_refuses_to_mix_levels(address, tmp_path):
    with ServerProcess(server_binary(), max_sessions=2, extra_args=["--simd", BASELINE]) as baseline:
        with Client(baseline.address) as client:
            assert client.server_info().simd == BASELINE
        info = subprocess.run([sys.executable, "-m", "culinarycut", "info", "--address", baseline.address],
                              capture_output=True, text=True, timeout=60)
        assert info.returncode == 0 and f"MPM kernels   {BASELINE}" in info.stdout, info.stderr
        with Client(address) as client:
            shared_level = client.server_info().simd
        if shared_level == BASELINE:
            pytest.skip("this CPU runs only the baseline: no second level to mix")
        mixed = bench("run", "smoke", "--tasks", "cucumber/normal/ratio-*", "--trials", "1", "--server", address,
                      "--server", baseline.address, "--out", str(tmp_path / "mixed"), "--no-progress", check=False)
        assert mixed.returncode == 1, mixed.stderr
        assert "instruction sets would mix" in mixed.stderr
        assert f"{BASELINE})" in mixed.stderr and f"{shared_level})" in mixed.stderr
        assert not rows_so_far(tmp_path / "mixed")  # refused before the first episode
