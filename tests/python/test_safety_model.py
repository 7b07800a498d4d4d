"""The safety module's force model: the fitter recovers a known posynomial, v_safe is the largest safe speed,
the asset holds to the server's contract, and `culinarycut safety dataset` runs real cc-cut cuts, resumes and
refuses bad arguments (cc-cut from $CULINARYCUT_CC_CUT or the build tree)."""
from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from culinarycut.safety.asset import AssetError, ForceModel, validate
from culinarycut.safety.binary import cc_cut_binary
from culinarycut.safety.dataset import HEADER_FILE, ROWS_FILE, read_rows
from culinarycut.safety.fit import fit_force_model, monotonic_in_speed
from culinarycut.safety.posynomial import INPUTS, Posynomial
from culinarycut.safety.speed_limit import TOLERANCE_M_S, material_inputs, safe_speed

REPO = Path(__file__).resolve().parents[2]
# A known model: toughness x edge, friction per edge length, and a speed-squared term (N).
TRUE_TERMS = {(0, 0, 0, 1, 1): 0.9, (0, 0, 0, 0, 1): 40.0, (2, 0, 0, 0, 1): 6.0}


def true_force(x: np.ndarray) -> np.ndarray:
    return sum(c * np.prod(x ** np.array(a, dtype=float), axis=1) for a, c in TRUE_TERMS.items())


def synthetic_inputs(count: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.column_stack([np.exp(rng.uniform(np.log(0.02), np.log(4.0), count)), rng.uniform(0.1, 5.0, count),
                            rng.uniform(20, 100, count), rng.uniform(60, 200, count), rng.uniform(0.015, 0.05, count)])


def cli(*args: str, env: dict | None = None, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "culinarycut", "safety", *args], capture_output=True, text=True,
                          env={**os.environ, **(env or {})}, timeout=600, cwd=cwd)


def coefficient_of(model: Posynomial, exponents: tuple) -> float:
    matches = [c for c, row in zip(model.coefficients, model.exponents) if tuple(row) == exponents]
    return float(sum(matches))


def test_the_fitter_recovers_a_known_posynomial():
    x = synthetic_inputs(200, seed=1)
    noise = np.random.default_rng(2).normal(0.0, 0.01, len(x))  # 10 mN on forces of 3-15 N
    result = fit_force_model(x, true_force(x) + noise, seed=0)
    assert result.held_out["r2"] > 0.999
    assert result.held_out["max_abs_error_n"] < 0.06
    for exponents, coefficient in TRUE_TERMS.items():
        assert coefficient_of(result.model, exponents) == pytest.approx(coefficient, rel=0.03), exponents
    others = [(c, row) for c, row in zip(result.model.coefficients, result.model.exponents)
              if tuple(row) not in TRUE_TERMS]
    assert sum(c * np.prod(x.max(axis=0) ** row) for c, row in others) < 0.1  # the rest adds < 0.1 N anywhere
    assert result.family == "+ speed"  # the smallest candidate family holding the true monomials
    assert result.monotonic_in_speed
    # Deterministic: the same rows and seed give the same split and the same model.
    again = fit_force_model(x, true_force(x) + noise, seed=0)
    assert np.array_equal(again.model.coefficients, result.model.coefficients)


def test_the_monotonicity_check_sees_a_force_that_falls_with_speed():
    falling = Posynomial.__new__(Posynomial)  # bypass the constructor's refusal of negative coefficients
    object.__setattr__(falling, "coefficients", np.array([5.0, -1.0]))
    object.__setattr__(falling, "exponents", np.array([[0, 0, 0, 0, 0], [1, 0, 0, 0, 0]], dtype=float))
    x = synthetic_inputs(5, seed=3)
    assert not monotonic_in_speed(falling, x, (0.02, 4.0))
    with pytest.raises(ValueError):
        Posynomial(coefficients=np.array([5.0, -1.0]), exponents=falling.exponents)


def make_asset(terms: dict, speed_range=(0.02, 4.0)) -> dict:
    return {"format": "culinarycut.safety.force_model", "version": 1, "target": "peak_blade_force_n",
            "inputs": list(INPUTS),
            "ranges": {"speed_m_s": list(speed_range), "youngs_modulus_mpa": [0.1, 5.0], "yield_stress_kpa": [20, 100],
                       "fracture_toughness_j_m2": [60, 200], "edge_length_m": [0.015, 0.05]},
            "terms": [{"coefficient": c, "exponents": list(a)} for a, c in terms.items()],
            "out_of_range_factor": 1.5}


@pytest.mark.parametrize("f_max_n", [3.0, 5.0, 6.5, 8.0])
def test_v_safe_is_safe_and_the_largest_safe_speed(f_max_n):
    model = ForceModel(make_asset(TRUE_TERMS))
    # F_hat: 5.92 N at rest (8.88 N with the factor: 0 m/s is below the speed range), 9.76 N at 4 m/s.
    x = material_inputs(0.0, 1.0, 50.0, 120.0, 0.04)
    limit = safe_speed(model, x, f_max_n)
    force = lambda v: model.predict(np.where(np.arange(len(x)) == 0, v, x))[0]  # noqa: E731
    assert limit.predicted_force_n == pytest.approx(force(limit.v_safe_m_s))
    if force(0.0) > f_max_n and force(0.02) > f_max_n:  # too much even at the slowest speed
        assert limit.v_safe_m_s == 0.0
    else:
        assert force(limit.v_safe_m_s) <= f_max_n
        assert force(limit.v_safe_m_s + 2 * TOLERANCE_M_S) > f_max_n  # maximal to the tolerance


def test_v_safe_inside_the_range_matches_the_closed_form():
    model = ForceModel(make_asset(TRUE_TERMS))
    x = material_inputs(0.0, 1.0, 50.0, 120.0, 0.04)
    # 0.9*120*0.04 + 40*0.04 + 6*v^2*0.04 = 8 N  ->  v = sqrt((8 - 5.92) / 0.24)
    limit = safe_speed(model, x, 8.0)
    assert limit.v_safe_m_s == pytest.approx(np.sqrt(2.08 / 0.24), abs=2 * TOLERANCE_M_S)
    assert not limit.out_of_range
    top = safe_speed(model, x, 100.0)  # safe across the whole range: the top of it
    assert top.v_safe_m_s == 4.0
    assert safe_speed(model, x, 1.0).v_safe_m_s == 0.0


@pytest.mark.parametrize("edit, field", [
    (lambda a: a.update(format="other"), "format"),
    (lambda a: a.update(version=2), "version"),
    (lambda a: a["terms"][0].update(coefficient=-1.0), "terms[0].coefficient"),
    (lambda a: a["terms"][1].update(exponents=[0, 0, 0, 1]), "terms[1].exponents"),
    (lambda a: a["terms"][2]["exponents"].__setitem__(0, -2), "terms[2].exponents[0]"),
    (lambda a: a["terms"][0].update(coefficient=float("nan")), "terms[0].coefficient"),
    (lambda a: a["ranges"].update(speed_m_s=[4.0, 0.02]), "ranges.speed_m_s"),
    (lambda a: a.update(out_of_range_factor=0.5), "out_of_range_factor"),
    (lambda a: a.update(inputs=list(reversed(INPUTS))), "inputs"),
])
def test_a_bad_asset_is_refused_naming_the_field(edit, field):
    asset = make_asset(TRUE_TERMS)
    validate(asset)
    edit(asset)
    with pytest.raises(AssetError, match="^" + re.escape(field + ":")):
        validate(asset)


def write_synthetic_dataset(directory, x: np.ndarray, forces: np.ndarray) -> None:
    directory.mkdir()
    (directory / HEADER_FILE).write_text(json.dumps({
        "format": "culinarycut.safety.force_dataset", "version": 1, "created": "2026-01-01T00:00:00+00:00",
        "engine_builds": ["synthetic"], "quality": "draft", "dx_m": 0.008, "sweep": {}, "sweeps": []}))
    with open(directory / ROWS_FILE, "w") as f:
        for i, (row, force) in enumerate(zip(x, forces)):
            f.write(json.dumps({"key": str(i), "food": "cucumber", "scale": 0.5, "speed_requested_m_s": row[0],
                                **dict(zip(INPUTS, row.tolist())), "peak_blade_force_n": force}) + "\n")


def test_fit_and_predict_through_the_cli_write_and_read_a_valid_asset(tmp_path):
    x = synthetic_inputs(120, seed=4)
    write_synthetic_dataset(tmp_path / "data", x, true_force(x))
    asset_path = tmp_path / "force_model.json"
    done = cli("fit", str(tmp_path / "data"), "--out", str(asset_path), "--plots", str(tmp_path / "images"))
    assert done.returncode == 0, done.stderr
    assert {p.name for p in (tmp_path / "images").iterdir()} == {"safety_force_predicted_vs_measured.png",
                                                                "safety_force_vs_speed.png"}
    asset = json.loads(asset_path.read_text())
    validate(asset)
    assert asset["fit"]["r2_held_out"] > 0.9999 and asset["fit"]["monotonic_in_speed"] is True
    assert asset["fit"]["samples"] == 120 and asset["fit"]["held_out"] == 24
    for j, name in enumerate(INPUTS):
        assert asset["ranges"][name] == [x[:, j].min(), x[:, j].max()]
    assert asset["provenance"]["dataset"] == "data/samples.jsonl" and len(asset["provenance"]["dataset_sha256"]) == 64
    assert all(t["coefficient"] > 0 for t in asset["terms"])

    shown = cli("predict", "--model", str(asset_path), "--speed", "1", "--youngs-mpa", "1", "--yield-kpa", "50",
                "--toughness", "120", "--edge-length-m", "0.04", "--f-max", "8")
    assert shown.returncode == 0, shown.stderr
    assert "F_hat at 1 m/s: 6.160 N" in shown.stdout  # 0.9*120*0.04 + 40*0.04 + 6*0.04
    v_safe = float(re.search(r"v_safe for F_max 8 N: ([0-9.]+) m/s", shown.stdout).group(1))
    assert v_safe == pytest.approx(np.sqrt(2.08 / 0.24), abs=1e-3)

    bad = cli("predict", "--model", str(asset_path), "--speed", "-1", "--youngs-mpa", "1", "--yield-kpa", "50",
              "--toughness", "120", "--edge-length-m", "0.04")
    assert bad.returncode == 2 and "--speed" in bad.stderr
    assert cli("fit", str(tmp_path / "nowhere")).returncode == 2


def predicted_force(printed: str) -> float:
    return float(re.search(r"F_hat at 1 m/s: ([0-9.]+) N", printed).group(1))


def test_predict_reads_the_servers_force_model_from_any_working_folder(tmp_path):
    """Without --model, as the server: $CULINARYCUT_ASSETS_DIR/safety/force_model.json, else the checkout's."""
    inputs = ("predict", "--speed", "1", "--youngs-mpa", "2.5", "--yield-kpa", "300", "--toughness", "488",
              "--edge-length-m", "0.04")
    env = {k: v for k, v in os.environ.items() if k != "CULINARYCUT_ASSETS_DIR"}
    shipped = subprocess.run([sys.executable, "-m", "culinarycut", "safety", *inputs], capture_output=True,
                             text=True, env=env, cwd=tmp_path, timeout=60)
    assert shipped.returncode == 0, shipped.stderr
    force = predicted_force(shipped.stdout)
    # The same model with every coefficient doubled, in an assets folder of its own: twice the force.
    asset = json.loads((REPO / "assets" / "safety" / "force_model.json").read_text())
    for term in asset["terms"]:
        term["coefficient"] *= 2
    (tmp_path / "assets" / "safety").mkdir(parents=True)
    (tmp_path / "assets" / "safety" / "force_model.json").write_text(json.dumps(asset))
    doubled = cli(*inputs, env={"CULINARYCUT_ASSETS_DIR": str(tmp_path / "assets")}, cwd=tmp_path / "assets")
    assert doubled.returncode == 0, doubled.stderr
    assert predicted_force(doubled.stdout) == pytest.approx(2 * force, abs=2e-3)
    missing = cli(*inputs, env={"CULINARYCUT_ASSETS_DIR": str(tmp_path / "empty")})
    assert missing.returncode == 2 and "Traceback" not in missing.stderr
    assert f"no force model at {tmp_path / 'empty' / 'safety' / 'force_model.json'}" in missing.stderr
    assert "CULINARYCUT_ASSETS_DIR" in missing.stderr


@pytest.fixture(scope="module")
def cc_cut():
    binary = cc_cut_binary()
    if not binary.is_file():
        pytest.fail(f"cc-cut not found at {binary}: build it (scripts/build.sh) or set CULINARYCUT_CC_CUT",
                    pytrace=False)
    return str(binary)


# A tiny real sweep: a small cucumber (1.2 cm across) of soft material at draft, two fast cuts (~1 s each).
TINY = ("--speeds", "0.5,2", "--foods", "cucumber", "--scales", "0.3", "--youngs-mpa", "0.3", "--yield-kpa", "50",
        "--toughness", "100", "--no-progress")


def test_the_dataset_command_runs_real_cuts_and_resumes(tmp_path, cc_cut):
    out = tmp_path / "data"
    first = cli("dataset", "--out", str(out), "--cc-cut", cc_cut, *TINY)
    assert first.returncode == 0, first.stderr
    rows = read_rows(out)
    assert sorted(r["speed_requested_m_s"] for r in rows) == [0.5, 2.0]
    header = json.loads((out / HEADER_FILE).read_text())
    assert header["quality"] == "draft" and header["engine_builds"][0].startswith("cc-cut")
    # draft's 8 mm, refined for the 12 mm cucumber (docs/world.md, quality presets), as the engine resolved it
    assert header["dx_m"] == rows[0]["dx_m"] and 0.004 <= header["dx_m"] < 0.008
    for row in rows:
        assert row["speed_m_s"] == pytest.approx(row["speed_requested_m_s"])  # no speed resistance: as prescribed
        assert 0.009 < row["edge_length_m"] <= 0.012  # the particles span the 12 mm diameter to a particle spacing
        # The edge takes at most G_c L; the windowed blade force is of that order (the faces add friction).
        assert 0.3 * 100 * row["edge_length_m"] < row["peak_blade_force_n"] < 5 * 100 * row["edge_length_m"]
        assert row["pieces"] == 2 and row["wall_s"] > 0 and 0 < row["mean_blade_force_n"] <= row["peak_substep_blade_force_n"]
    lines = (out / ROWS_FILE).read_text().splitlines()

    again = cli("dataset", "--out", str(out), "--cc-cut", cc_cut, *TINY)
    assert again.returncode == 0 and "this run: 0 in" in again.stdout
    assert (out / ROWS_FILE).read_text().splitlines() == lines

    # Lose the first row and leave half of the second, as a kill mid-write would: only those two run again.
    (out / ROWS_FILE).write_text(lines[1][: len(lines[1]) // 2])
    third = cli("dataset", "--out", str(out), "--cc-cut", cc_cut, *TINY)
    assert third.returncode == 0 and "this run: 2 in" in third.stdout, third.stdout + third.stderr
    rows = read_rows(out)
    assert sorted(r["key"] for r in rows) == sorted(json.loads(line)["key"] for line in lines)
    # Deterministic engine: the rerun cut gives the same force.
    before = {json.loads(line)["key"]: json.loads(line)["peak_blade_force_n"] for line in lines}
    assert {r["key"]: r["peak_blade_force_n"] for r in rows} == before

    # Delete exactly one row: a rerun adds only it.
    (out / ROWS_FILE).write_text("\n".join(lines[1:]) + "\n")
    fourth = cli("dataset", "--out", str(out), "--cc-cut", cc_cut, *TINY)
    assert "this run: 1 in" in fourth.stdout and len(read_rows(out)) == 2
    # Every run's count and wall time is in the header: the throughput report reads them.
    runs = json.loads((out / HEADER_FILE).read_text())["runs"]
    assert [r["ran"] for r in runs] == [2, 0, 2, 1] and all(r["wall_s"] >= 0 and r["workers"] == 2 for r in runs)


def test_a_sweep_killed_mid_run_resumes_without_losing_or_repeating_rows(tmp_path, cc_cut):
    out = tmp_path / "data"
    args = [sys.executable, "-m", "culinarycut", "safety", "dataset", "--out", str(out), "--cc-cut", cc_cut,
            "--speeds", "0.1,0.2,0.5,1,2,4", *TINY[2:], "--workers", "1"]
    # TMPDIR: the killed run's scratch folder (its cc-cut copy) stays under tmp_path.
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True,
                            env={**os.environ, "TMPDIR": str(tmp_path)})
    try:
        deadline = time.monotonic() + 120
        while not read_rows(out) and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)  # the CLI and its cc-cut, mid-run
        proc.wait()
    kept = read_rows(out)
    assert 1 <= len(kept) < 6, "the kill should land between the first and the last cut"
    done = cli("dataset", "--out", str(out), "--cc-cut", cc_cut, "--speeds", "0.1,0.2,0.5,1,2,4", *TINY[2:])
    assert done.returncode == 0 and f"this run: {6 - len(kept)} in" in done.stdout
    rows = read_rows(out)
    assert len(rows) == 6 and len({r["key"] for r in rows}) == 6
    assert rows[: len(kept)] == kept  # what was recorded before the kill is kept as it was


@pytest.mark.parametrize("args, named", [
    (("--speeds", "0"), "--speeds"),
    (("--speeds", "25"), "--speeds"),
    (("--speeds", "fast"), "--speeds"),
    (("--foods", "kiwi"), "--foods"),
    (("--youngs-mpa", "-1"), "--youngs-mpa"),
    (("--toughness", "2e4"), "--toughness"),
    (("--quality", "ultra"), "--quality"),
    (("--workers", "0"), "--workers"),
    (("--cc-cut", "/nonexistent/cc-cut"), "--cc-cut"),
])
def test_a_bad_dataset_argument_exits_2_naming_it(tmp_path, cc_cut, args, named):
    done = cli("dataset", "--out", str(tmp_path / "data"), "--cc-cut", cc_cut, *args)
    assert done.returncode == 2
    assert named in done.stderr
    assert not (tmp_path / "data" / ROWS_FILE).exists()


def test_a_dataset_of_another_quality_is_not_mixed_in(tmp_path, cc_cut):
    out = tmp_path / "data"
    assert cli("dataset", "--out", str(out), "--cc-cut", cc_cut, "--speeds", "2", *TINY[2:]).returncode == 0
    other = cli("dataset", "--out", str(out), "--cc-cut", cc_cut, *TINY, "--quality", "standard")
    assert other.returncode == 2 and "--quality" in other.stderr


def test_the_engine_a_dataset_names_is_the_binary_and_its_mpm_library(tmp_path):
    # The physics lives in the MPM library (one build per x86-64 level beside the binary): a rebuilt library is
    # another engine, and a run's private copy of cc-cut takes the library along where the binary looks for it.
    from culinarycut.safety.binary import snapshot_cc_cut
    from culinarycut.safety.dataset import engine_build
    build = tmp_path / "build"
    binary = build / "tools" / "cc_cut" / "cc-cut"
    level = build / "lib" / "glibc-hwcaps" / "x86-64-v3"
    for path, text in ((binary, "binary"), (build / "lib" / "libculinarycut_mpm.so", "baseline"),
                       (level / "libculinarycut_mpm.so", "v3")):
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    before = engine_build(binary)
    (level / "libculinarycut_mpm.so").write_text("v3, rebuilt")
    assert engine_build(binary) != before
    copy = snapshot_cc_cut(binary, tmp_path / "scratch")
    assert copy == tmp_path / "scratch" / "tools" / "cc_cut" / "cc-cut"
    assert (tmp_path / "scratch" / "lib" / "glibc-hwcaps" / "x86-64-v3" / "libculinarycut_mpm.so").read_text() == \
        "v3, rebuilt"
    assert engine_build(copy) == engine_build(binary)
