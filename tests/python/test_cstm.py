"""The CulinaryCut paper's Cutting Style Transfer Module (learning/culinarycut_learning/cstm/): the contact
classifier C (torchvision's ViT) and the style generator f, their shapes, gradients and training (the loss
falls on a toy problem, the same seed gives the same weights, a stopped run resumes to the weights of an
uninterrupted one), the pair builder on synthetic trajectories, the policy wrapper's switch (f applied exactly
while C says contact, in the right units), its errors, the commands; then, with a real server, one (normal,
saw) pair of oracle cuts recorded live and one suite episode run by `culinarycut bench run` through the
wrapper around the oracle. Coarse MPM (bench/lib/quick.py's) keeps the simulated cuts to about a second."""
from __future__ import annotations

import json
import math
import os
import re
import sqlite3
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
import torch

REPO_ROOT = Path(__file__).resolve().parents[2]
# learning/ importable where scripts/install_deps.sh has not installed it (it installs it editable, from here)
sys.path.insert(0, str(REPO_ROOT / "learning"))

from culinarycut.datasets.adapter_layouts import delta_ee_actions
from culinarycut.geometry import quat_from_axis_angle, quat_mul
from culinarycut.policies.base import Policy
from culinarycut_learning.__main__ import main as learning_main
from culinarycut_learning.cstm import runs
from culinarycut_learning.cstm.classifier_train import train_classifier
from culinarycut_learning.cstm.configs import (ClassifierConfig, ClassifierModel, GeneratorConfig, GeneratorModel,
                                               Optimisation)
from culinarycut_learning.cstm.contact_classifier import ContactClassifier
from culinarycut_learning.cstm.generator_train import load_generator, train_generator
from culinarycut_learning.cstm.oracle_pairs import Recording, load_pair, oracle_pair, save_pair
from culinarycut_learning.cstm.pairs import contact_pairs, pair_windows
from culinarycut_learning.cstm.policy import ContactRun, CstmPolicy
from culinarycut_learning.cstm.style_generator import StyleGenerator
from culinarycut_learning.cstm.styles import STYLES
from culinarycut_learning.cstm.trajectories import Trajectory, contact_segments, resample
from culinarycut_learning.train import RunError

torch.set_num_threads(1)

SIZE = 32                                   # px: the toy images and the tiny classifier's input
COARSE_MPM = {"dx": 0.008, "particles_per_cell": 2, "cfl": 0.8}   # bench/lib/quick.py: a cut in under a second
EDGE_DOWN = np.array([0.0, 1.0, 0.0, 0.0])  # the knife's TCP quaternion, edge down
TINY_VIT = ClassifierModel(image_size=SIZE, patch_size=8, layers=2, heads=2, hidden_dim=32, mlp_dim=64)
TINY_F = GeneratorModel(chunk=4, d_model=16, heads=2, layers=1, feedforward=32)


def optim(steps: int, **extra) -> Optimisation:
    return Optimisation(**{"steps": steps, "batch_size": 8, "lr": 3e-3, "warmup_steps": 0, "threads": 1,
                           "save_every": steps, "log_every": 1, **extra})


def toy_frame(contact: bool, rng: np.random.Generator) -> np.ndarray:
    """A dark noisy frame; with contact a bright square somewhere in its middle."""
    frame = rng.integers(0, 60, size=(SIZE, SIZE, 3), dtype=np.uint8)
    if contact:
        y, x = rng.integers(6, 16, size=2)
        frame[y:y + 10, x:x + 10] = 230
    return frame


def toy_export(path: Path, demos: int = 4, frames: int = 16, valid: bool = True) -> Path:
    """A robomimic file with what the classifier reads: front frames, obs/knife_contact, train/valid masks
    (with `valid`, the last demo in mask/valid)."""
    rng = np.random.default_rng(0)
    with h5py.File(path, "w") as file:
        for d in range(demos):
            contact = (np.arange(frames) % 4 >= 2).astype(np.uint8)
            demo = file.create_group(f"data/demo_{d}")
            demo.create_dataset("obs/front_image", data=np.stack([toy_frame(bool(c), rng) for c in contact]))
            demo.create_dataset("obs/knife_contact", data=contact)
        names = [f"demo_{d}" for d in range(demos)]
        held_out = names[-1:] if valid else []
        file.create_dataset("mask/train", data=np.array([n for n in names if n not in held_out], dtype="S"))
        file.create_dataset("mask/valid", data=np.array(held_out, dtype="S"))
    return path


def toy_pair(seed: int, style: str = "saw") -> tuple[Trajectory, Trajectory]:
    """A normal cut (12 contact steps straight down) and its saw counterpart (24 contact steps: down at half the
    speed while x swings with a 8-step period), each with 5 steps of approach and retreat around the contact."""
    def cut(contact_steps: int, actions) -> tuple[np.ndarray, np.ndarray]:
        contact = np.r_[np.zeros(5), np.ones(contact_steps), np.zeros(5)].astype(bool)
        full = np.zeros((len(contact), 6), np.float32)
        full[5:5 + contact_steps] = actions
        return full, contact
    down = np.zeros((12, 6), np.float32)
    down[:, 2] = -0.2
    steps = np.arange(24)
    saw = np.zeros((24, 6), np.float32)
    saw[:, 2] = -0.1
    saw[:, 0] = 0.3 * np.sin(2 * np.pi * steps / 8)
    return (Trajectory("normal", *cut(12, down), seed=seed), Trajectory(style, *cut(24, saw), seed=seed))


def save_stub_classifier(folder: Path, logit: float | None) -> Path:
    """A classifier checkpoint (the real format) whose ViT head says `logit` for every image: the head's
    weights start at zero in torchvision's ViT, so its bias is the logit. None: as built."""
    torch.manual_seed(0)
    model = ContactClassifier(TINY_VIT)
    if logit is not None:
        model.vit.heads.head.bias.data.fill_(logit)
    config = ClassifierConfig(model=TINY_VIT, optim=optim(1))
    runs.save(folder, runs.CLASSIFIER_FORMAT, {"config": config.to_dict(), "step": 0, "loss": math.nan,
                                               "data": {"source": "stub", "sha256": "0" * 64, "camera_size": SIZE},
                                               "held_out": None, "model": model.state_dict(), "optimizer": {}})
    return folder


def save_stub_generator(folder: Path, styles=("normal", "saw"), offset=None, std: float = 0.1) -> Path:
    """An untrained generator checkpoint (f is the identity: its output layer starts at zero); with `offset`
    (6 values, normalised units) as the output layer's bias, f(a) = a + offset * std."""
    torch.manual_seed(0)
    normalisation = {"mean": [0.0] * 6, "std": [std] * 6}
    model = StyleGenerator(TINY_F, normalisation)
    if offset is not None:
        model.out.bias.data.copy_(torch.tensor(offset, dtype=torch.float32))
    config = GeneratorConfig(model=TINY_F, optim=optim(1))
    runs.save(folder, runs.GENERATOR_FORMAT, {"config": config.to_dict(), "step": 0, "loss": math.nan,
                                              "data": {"source": "stub", "sha256": "0" * 64},
                                              "normalisation": normalisation, "styles": list(styles),
                                              "valid_l1": None, "model": model.state_dict(), "optimizer": {}})
    return folder


def observation(tcp_pose=None) -> dict:
    pose = np.r_[0.5, 0.0, 0.2, EDGE_DOWN] if tcp_pose is None else np.asarray(tcp_pose, float)
    return {"extra": {"tcp_pose": pose, "tcp_velocity": np.zeros(6), "wrist_wrench": np.zeros(6)},
            "sensor_data": {"front": {"rgb": np.zeros((SIZE, SIZE, 3), np.uint8)}}}


def same(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(torch.equal(a[k], b[k]) for k in a)


class HoldTarget(Policy):
    """A pd_ee_pose_quat policy: a target 4 mm below and 3 mm beside the measured TCP, turned 0.088 rad about a
    slanted axis (within pd_ee_delta_pose's 0.1 rad a step; XYZ Euler angles and an axis-angle of it differ, so a
    mix-up of the two shows)."""

    name = "hold-target"
    control_mode = "pd_ee_pose_quat"

    def act(self, observation):
        tcp = np.asarray(observation["extra"]["tcp_pose"], float)
        turn = quat_mul(quat_from_axis_angle(np.array([0.05, -0.04, 0.06])), tcp[3:7])
        return self.control_mode, np.r_[tcp[:3] + [0.003, 0.0, -0.004], turn]


# --- the networks ---------------------------------------------------------------------------------------------

def test_classifier_is_torchvisions_vit_and_gives_one_logit_per_image_with_gradients():
    torch.manual_seed(0)
    model = ContactClassifier(TINY_VIT)
    assert type(model.vit).__module__ == "torchvision.models.vision_transformer"
    logits = model(torch.randint(0, 256, (5, SIZE, SIZE, 3), dtype=torch.uint8))
    assert logits.shape == (5,)
    torch.nn.functional.binary_cross_entropy_with_logits(logits, torch.ones(5)).backward()
    missing = [n for n, p in model.named_parameters() if p.grad is None]
    assert not missing, missing
    # any frame size: resized as the learned policy's frames are
    assert 0.0 < model.contact_probability(np.zeros((48, 80, 3), np.uint8)) < 1.0


def test_generator_maps_a_chunk_per_style_and_starts_as_the_identity():
    torch.manual_seed(0)
    model = StyleGenerator(TINY_F, {"mean": [0.0] * 6, "std": [0.2] * 6})
    chunk = torch.randn(len(STYLES), TINY_F.chunk, 6) * 0.1
    out = model(chunk, torch.arange(len(STYLES)), torch.tensor([0.0, 3.0, 7.0, 20.0]))
    assert out.shape == (len(STYLES), TINY_F.chunk, 6)
    assert torch.allclose(model.actions(out), chunk, atol=1e-6)     # untrained f leaves a_hat as it is
    (out - 1.0).abs().mean().backward()
    assert model.out.weight.grad.abs().sum() > 0 and model.style.weight.grad is not None
    with pytest.raises(ValueError, match="chunks of 4"):
        model(torch.zeros(1, 5, 6), torch.tensor([0]), torch.tensor([0.0]))


# --- training ---------------------------------------------------------------------------------------------------

def test_the_robomimic_export_carries_the_contact_labels_c_trains_on():
    from culinarycut.datasets.export_robomimic import _obs   # the exporter's per-step observations
    n = 6
    contact = np.array([0, 0, 1, 1, 0, 1], bool)
    steps = {"obs/front_rgb": np.zeros((n, SIZE, SIZE, 3), np.uint8), "obs/qpos": np.zeros((n, 7)),
             "obs/qvel": np.zeros((n, 7)), "obs/tcp_pose": np.zeros((n, 7)), "obs/tcp_velocity": np.zeros((n, 6)),
             "obs/wrist_wrench": np.zeros((n, 6)), "phase": np.array(["approach"] * n), "knife_contact": contact}
    obs = _obs(steps)
    assert "front_image" in obs and obs["knife_contact"].dtype == np.uint8
    assert obs["knife_contact"].tolist() == contact.astype(int).tolist()   # contact_data.CONTACT_KEY's source


def test_classifier_learns_a_toy_contact_cue_and_reports_held_out_accuracy(tmp_path):
    data = toy_export(tmp_path / "toy.hdf5")
    config = ClassifierConfig(model=TINY_VIT, optim=optim(40, log_every=5), shift_px=2)
    summary = train_classifier(data, tmp_path / "run", config, progress=False, log=lambda _: None)
    losses = [json.loads(line)["loss"] for line in (tmp_path / "run" / "log.jsonl").read_text().splitlines()]
    assert losses[-1] < 0.5 * losses[0], losses
    held_out = summary["held_out"]
    assert held_out["demos"] == 1 and held_out["frames"] == 16 and held_out["contact_frames"] == 8
    assert held_out["balanced_accuracy"] >= 0.9, held_out
    saved = runs.load(tmp_path / "run", runs.CLASSIFIER_FORMAT)
    assert saved["config"]["model"]["camera"] == "front" and saved["data"]["camera_size"] == SIZE


def test_generator_learns_toy_pairs(tmp_path):
    windows = pair_windows([toy_pair(s) for s in range(3)], chunk=TINY_F.chunk)
    for i in range(3):
        save_pair(tmp_path / "pairs" / f"p{i}.npz", *recordings(toy_pair(i)), {})
    config = GeneratorConfig(model=TINY_F, optim=optim(300, batch_size=32, log_every=20))
    summary = train_generator(tmp_path / "pairs", tmp_path / "run", config, progress=False, log=lambda _: None)
    losses = [json.loads(line)["loss"] for line in (tmp_path / "run" / "log.jsonl").read_text().splitlines()]
    assert losses[-1] < 0.25 * losses[0], losses
    assert summary["styles"] == ["normal", "saw"]
    assert summary["windows"] == len(windows["inputs"]) == 3 * (24 + 12)
    # f learnt the stroke: the held normal descent, restyled at each step of contact, swings in x with the saw
    model = load_generator(tmp_path / "run")[0]
    held = torch.zeros(TINY_F.chunk, 6)
    held[:, 2] = -0.2
    swing = [float(model.stylise(held, STYLES.index("saw"), t)[0, 0]) for t in range(24)]
    assert np.corrcoef(swing, np.sin(2 * np.pi * np.arange(24) / 8))[0, 1] > 0.8, swing


def recordings(pair: tuple[Trajectory, Trajectory]) -> tuple[Recording, Recording]:
    """Recordings (pd_ee_pose_quat targets from a fixed TCP) whose OSC actions are the pair's."""
    out = []
    for trajectory in pair:
        tcp = np.tile(np.r_[0.5, 0.0, 0.2, EDGE_DOWN], (len(trajectory.actions), 1))
        targets = tcp.copy()
        targets[:, :3] += trajectory.actions[:, :3] * 0.05      # OSC: 1 = 0.05 m (no rotation in the toys)
        out.append(Recording(trajectory.style, targets, tcp, trajectory.contact, trajectory.seed))
    return tuple(out)


def test_the_same_seed_gives_the_same_weights_and_another_seed_does_not(tmp_path):
    data = toy_export(tmp_path / "toy.hdf5", demos=2, frames=8)

    def classifier(name, seed):
        config = ClassifierConfig(model=TINY_VIT, optim=optim(3, seed=seed))
        train_classifier(data, tmp_path / name, config, progress=False, log=lambda _: None)
        return runs.load(tmp_path / name, runs.CLASSIFIER_FORMAT)["model"]

    assert same(classifier("a", 0), classifier("b", 0))
    assert not same(classifier("a", 0), classifier("c", 1))
    for i in range(2):
        save_pair(tmp_path / "pairs" / f"p{i}.npz", *recordings(toy_pair(i)), {})

    def generator(name, seed):
        config = GeneratorConfig(model=TINY_F, optim=optim(3, seed=seed))
        train_generator(tmp_path / "pairs", tmp_path / name, config, progress=False, log=lambda _: None)
        return runs.load(tmp_path / name, runs.GENERATOR_FORMAT)["model"]

    assert same(generator("f-a", 0), generator("f-b", 0))
    assert not same(generator("f-a", 0), generator("f-c", 1))


class Stop(Exception):
    pass


def test_a_stopped_run_resumes_to_the_weights_of_an_uninterrupted_one_and_refuses_other_settings(tmp_path):
    data = toy_export(tmp_path / "toy.hdf5", demos=2, frames=8)
    config = ClassifierConfig(model=TINY_VIT, optim=optim(4, save_every=2))
    train_classifier(data, tmp_path / "whole", config, progress=False, log=lambda _: None)

    def stop_at_3(step):
        if step == 3:
            raise Stop
    with pytest.raises(Stop):
        train_classifier(data, tmp_path / "stopped", config, progress=False, log=lambda _: None, on_step=stop_at_3)
    assert runs.load(tmp_path / "stopped", runs.CLASSIFIER_FORMAT)["step"] == 2    # step 3's work is lost
    summary = train_classifier(data, tmp_path / "stopped", config, progress=False, log=lambda _: None)
    assert summary["resumed_from"] == 2
    assert same(runs.load(tmp_path / "whole", runs.CLASSIFIER_FORMAT)["model"],
                runs.load(tmp_path / "stopped", runs.CLASSIFIER_FORMAT)["model"])
    steps = [json.loads(line)["step"] for line in (tmp_path / "stopped" / "log.jsonl").read_text().splitlines()]
    assert steps == [1, 2, 3, 4]
    other = ClassifierConfig(model=TINY_VIT, optim=optim(4, save_every=2, lr=1e-3))
    with pytest.raises(RunError, match=r"optim.lr: 0.003 -> 0.001"):
        train_classifier(data, tmp_path / "stopped", other, progress=False, log=lambda _: None)


# --- pairs --------------------------------------------------------------------------------------------------------

def test_contact_segments_merge_short_gaps_and_drop_grazes():
    contact = np.zeros(30, bool)
    contact[[0]] = True              # a one-step graze, 4 steps before the cut: dropped
    contact[5:10] = True
    contact[12:15] = True            # 2 steps apart from the run before: the same segment
    contact[20:24] = True            # 5 steps apart: a second segment
    assert contact_segments(contact, max_gap=2, min_steps=3) == [(5, 15), (20, 24)]
    assert contact_segments(contact, max_gap=0, min_steps=1) == [(0, 1), (5, 10), (12, 15), (20, 24)]
    assert contact_segments(np.zeros(4, bool)) == []


def test_resample_keeps_the_ends_and_interpolates_linearly():
    values = np.array([[0.0, 1.0], [1.0, 3.0], [2.0, 5.0]])
    out = resample(values, 5)
    assert out.shape == (5, 2)
    np.testing.assert_allclose(out[:, 0], [0.0, 0.5, 1.0, 1.5, 2.0])
    np.testing.assert_allclose(out[:, 1], [1.0, 2.0, 3.0, 4.0, 5.0])
    np.testing.assert_allclose(resample(values[:1], 3), np.repeat(values[:1], 3, axis=0))


def test_pairs_are_cut_to_contact_resampled_to_the_styles_length_and_windowed():
    normal, saw = toy_pair(7)
    [(source, target)] = contact_pairs(normal, saw)
    assert source.shape == target.shape == (24, 6)               # the saw segment's own length
    np.testing.assert_allclose(source[:, 2], -0.2)               # the normal descent, stretched over 24 steps
    np.testing.assert_allclose(target, saw.actions[5:29], atol=1e-6)
    windows = pair_windows([(normal, saw)], chunk=4)
    assert windows["inputs"].shape == windows["targets"].shape == (24 + 12, 4, 6)
    assert windows["style"][:24].tolist() == [STYLES.index("saw")] * 24
    assert windows["style"][24:].tolist() == [STYLES.index("normal")] * 12     # the identity samples
    assert windows["contact_step"][:24].tolist() == list(range(24))
    assert windows["mask"][23].tolist() == [1, 0, 0, 0] and windows["mask"][0].tolist() == [1, 1, 1, 1]
    torch.testing.assert_close(windows["targets"][3], torch.from_numpy(saw.actions[8:12]))
    # a split cut twice against a styled cut once: no pairs, said plainly
    twice = np.zeros(len(normal.actions), bool)
    twice[[*range(2, 8), *range(12, 18)]] = True
    split = Trajectory("normal", normal.actions, twice)
    with pytest.raises(ValueError, match="2 contact segments, the saw cut 1"):
        contact_pairs(split, saw)


def test_recorded_targets_become_the_learned_policys_osc_units():
    tcp = np.tile(np.r_[0.5, 0.0, 0.2, EDGE_DOWN], (2, 1))
    targets = tcp.copy()
    targets[:, 2] -= [0.005, 0.0025]                   # 5 mm and 2.5 mm below the TCP
    trajectory = Trajectory.from_recording("normal", targets, tcp, [1, 1], "pd_ee_pose_quat")
    np.testing.assert_allclose(trajectory.actions[:, 2], [-0.1, -0.05], atol=1e-6)   # 1 = 0.05 m
    np.testing.assert_allclose(trajectory.actions[:, [0, 1, 3, 4, 5]], 0.0, atol=1e-6)


# --- the policy wrapper ----------------------------------------------------------------------------------------

def test_contact_run_counts_steps_since_contact_began_across_short_misses():
    run = ContactRun(release_steps=2)
    seen = [run.update(c) for c in [0, 1, 1, 0, 1, 0, 0, 0, 1, 1]]
    assert seen == [None, 0, 1, None, 3, None, None, None, 0, 1]


def test_f_is_applied_exactly_while_the_classifier_says_contact(tmp_path):
    offset = [0.0, 0.0, -1.0, 0.5, 0.0, 0.0]          # normalised; std 0.1: -0.1 and 0.05 OSC units
    generator = save_stub_generator(tmp_path / "f", offset=offset)
    options = {"inner": "noop", "generator": str(generator), "style": "saw"}
    never = CstmPolicy(classifier=str(save_stub_classifier(tmp_path / "never", -20.0)), **options)
    always = CstmPolicy(classifier=str(save_stub_classifier(tmp_path / "always", 20.0)), **options)
    assert never.cameras == always.cameras == ({"name": "front", "width": SIZE, "height": SIZE, "channels": ["rgb"]},)
    for policy in (never, always):
        policy.reset("cut the strawberry in the middle", {"seed": 0})
    for _ in range(5):
        mode, action = never.act(observation())
        assert mode == "pd_ee_delta_pose" and np.array_equal(action, np.zeros(6))     # the inner's, untouched
        mode, action = always.act(observation())
        # -0.1 OSC z = -5 mm = -0.05 pd_ee_delta_pose units; 0.05 OSC about x = 0.025 rad = 0.25 units
        assert mode == "pd_ee_delta_pose"
        np.testing.assert_allclose(action, [0.0, 0.0, -0.05, 0.25, 0.0, 0.0], atol=1e-6)
    assert never.latency_summary()["cstm"]["transformed_steps"] == 0
    report = always.latency_summary()["cstm"]
    assert report["transformed_steps"] == report["steps"] == 5 and report["first_transformed_step"] == 0
    assert report["style"] == "saw" and report["classifier_ms_mean"] > 0


def test_an_identity_f_executes_the_inner_policys_own_target(tmp_path):
    policy = CstmPolicy(inner="test_cstm:HoldTarget", classifier=str(save_stub_classifier(tmp_path / "c", 20.0)),
                        generator=str(save_stub_generator(tmp_path / "f")), style="saw")
    assert policy.control_mode == "pd_ee_pose_quat"
    policy.reset("", {"seed": 0})
    tcp = np.r_[0.48, 0.02, 0.15, quat_mul(quat_from_axis_angle(np.array([0.1, 0.0, 0.0])), EDGE_DOWN)]
    mode, values = policy.act(observation(tcp))
    _, target = HoldTarget().act(observation(tcp))
    executed = delta_ee_actions({"actions": values[None], "obs/tcp_pose": tcp[None]}, mode)
    wanted = delta_ee_actions({"actions": target[None], "obs/tcp_pose": tcp[None]}, "pd_ee_pose_quat")
    np.testing.assert_allclose(executed, wanted, atol=1e-6)


def test_the_wrapper_names_what_is_wrong(tmp_path):
    classifier = str(save_stub_classifier(tmp_path / "c", 0.0))
    generator = str(save_stub_generator(tmp_path / "f"))
    nowhere = tmp_path / "nowhere"
    with pytest.raises(ValueError, match=re.escape(f"option classifier: {nowhere}: no such file or folder")):
        CstmPolicy(inner="noop", classifier=str(tmp_path / "nowhere"), generator=generator)
    with pytest.raises(ValueError, match=r"style='wobble'.*normal, bias, guillotine, saw"):
        CstmPolicy(inner="noop", classifier=classifier, generator=generator, style="wobble")
    with pytest.raises(ValueError, match="trained on normal, saw pairs, not bias"):
        CstmPolicy(inner="noop", classifier=classifier, generator=generator, style="bias")
    with pytest.raises(ValueError, match="not a CSTM style generator checkpoint"):
        CstmPolicy(inner="noop", classifier=classifier, generator=classifier)
    with pytest.raises(ValueError, match="unknown option colour.*inner.KEY=VALUE"):
        CstmPolicy(inner="noop", classifier=classifier, generator=generator, colour="red")
    with pytest.raises(ValueError, match="option scale must be in"):       # the inner policy's own check
        CstmPolicy(inner="random", classifier=classifier, generator=generator, **{"inner.scale": 3})


# --- the commands ----------------------------------------------------------------------------------------------

def test_the_commands_train_resume_and_report(tmp_path, capsys):
    data = toy_export(tmp_path / "toy.hdf5", demos=2, frames=8, valid=False)
    for i in range(2):
        save_pair(tmp_path / "pairs" / f"p{i}.npz", *recordings(toy_pair(i)), {})
    tiny = ["--steps", "2", "--batch-size", "4", "--threads", "1", "--log-every", "1", "--no-progress"]
    assert learning_main(["cstm-classifier", "train", "--data", str(data), "--out", str(tmp_path / "c"), *tiny,
                          "--image-size", str(SIZE), "--layers", "1", "--hidden-dim", "32", "--mlp-dim", "32",
                          "--heads", "2"]) == 0
    out = capsys.readouterr()
    assert "2 steps (from 0)" in out.out and "held-out accuracy" in out.out, out
    assert "1 demos; held out: 8 frames (no mask/valid demos: the last demo (demo_1) held out)" in out.err, out.err
    # the same command again: the run is done, resumed at its last step
    assert learning_main(["cstm-classifier", "train", "--data", str(data), "--out", str(tmp_path / "c"), *tiny]) == 0
    assert "2 steps (from 2)" in capsys.readouterr().out
    assert learning_main(["cstm-generator", "train", "--pairs", str(tmp_path / "pairs"), "--out",
                          str(tmp_path / "f"), *tiny, "--chunk", "4", "--d-model", "16", "--layers", "1"]) == 0
    out = capsys.readouterr().out
    assert "2 steps (from 0)" in out and "(normal, saw)" in out, out
    assert learning_main(["cstm-generator", "train", "--pairs", str(tmp_path / "nowhere"), "--out",
                          str(tmp_path / "g")]) == 1
    assert "no pair files" in capsys.readouterr().err


def test_a_pair_file_reads_back_as_its_trajectories(tmp_path):
    normal, saw = toy_pair(3)
    path = save_pair(tmp_path / "pair.npz", *recordings((normal, saw)), {"food": "toy"})
    loaded_normal, loaded_saw, meta = load_pair(path)
    assert meta["style"] == "saw" and meta["food"] == "toy" and meta["seed"] == 3
    np.testing.assert_allclose(loaded_normal.actions, normal.actions, atol=1e-6)
    np.testing.assert_allclose(loaded_saw.actions, saw.actions, atol=1e-6)
    assert np.array_equal(loaded_saw.contact, saw.contact)


# --- with a server --------------------------------------------------------------------------------------------

def test_a_live_pair_of_oracle_cuts_of_one_scene(client):
    normal, saw = oracle_pair(client, "strawberry", "saw", seed=11, mpm=COARSE_MPM)
    normal_t, saw_t = normal.trajectory(), saw.trajectory()
    assert normal.contact.any() and saw.contact.any()
    [(source, target)] = contact_pairs(normal_t, saw_t)
    [(saw_start, saw_end)] = contact_segments(saw.contact)
    [(normal_start, normal_end)] = contact_segments(normal.contact)
    assert len(target) == saw_end - saw_start > normal_end - normal_start    # the saw descends slower
    # the saw strokes along the blade (x, across the strawberry's long axis): its x actions swing, the
    # normal cut's do not
    assert np.ptp(target[:, 0]) > 3 * np.ptp(source[:, 0]), (np.ptp(target[:, 0]), np.ptp(source[:, 0]))
    assert np.all(np.abs(target) <= 1.0) and np.all(np.isfinite(target))


SUITE = """name = "cstm-e2e"
description = "one strawberry middle cut at draft, coarse MPM, through the CSTM wrapper"
trials = 1
max_episode_steps = 200
quality = "draft"
mpm = { dx = 0.008, particles_per_cell = 2, cfl = 0.8 }

[[tasks]]
food = "strawberry"
state = "middle"
"""


def bench_run(suite: Path, out: Path, address: str, *policy) -> dict:
    """`culinarycut bench run` of the one-episode suite; its row."""
    env = {**os.environ, "OMP_NUM_THREADS": "1",
           "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO_ROOT / "learning"), os.environ.get("PYTHONPATH")]))}
    result = subprocess.run([sys.executable, "-m", "culinarycut", "bench", "run", str(suite), *policy, "--server",
                             address, "--workers", "1", "--out", str(out), "--no-progress"],
                            capture_output=True, text=True, timeout=120, env=env, cwd=REPO_ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    with sqlite3.connect(out / "results.sqlite") as db:
        db.row_factory = sqlite3.Row
        rows = [dict(r) for r in db.execute("SELECT * FROM episodes")]
    assert len(rows) == 1, rows
    return rows[0]


def test_bench_run_through_the_wrapper_around_the_oracle(address, tmp_path):
    classifier = save_stub_classifier(tmp_path / "classifier", 20.0)      # untrained; says contact everywhere
    generator = save_stub_generator(tmp_path / "generator")               # untrained: f is the identity
    suite = tmp_path / "cstm-e2e.toml"
    suite.write_text(SUITE)
    row = bench_run(suite, tmp_path / "cstm", address, "--policy", "culinarycut_learning.cstm.policy:CstmPolicy",
                    "--policy-option", "inner=oracle", "--policy-option", f"classifier={classifier}",
                    "--policy-option", f"generator={generator}", "--policy-option", "style=saw")
    assert row["error"] in (None, "") and row["end_reason"] != "policy_error", row
    assert row["policy_name"] == "cstm" and row["steps"] > 0
    report = json.loads(row["policy_latency"])["cstm"]
    assert report["transformed_steps"] == report["steps"] == row["steps"], report
    assert report["camera"] == "front" and report["style"] == "saw"
    # Every step went through f (the identity) and was executed as pd_ee_delta_pose from the measured TCP:
    # the episode is the oracle's own, as the plain oracle runs it in pd_ee_pose_quat.
    oracle = bench_run(suite, tmp_path / "oracle", address, "--policy", "oracle")
    for key in ("steps", "end_reason", "outcome"):
        assert row[key] == oracle[key], (key, row[key], oracle[key])
    assert row["peak_force_n"] == pytest.approx(oracle["peak_force_n"], rel=1e-2), (row, oracle)


def test_the_saw_study_asks_for_the_saw_tasks_it_names(tmp_path):
    # learning/scripts/cstm_saw_study.py writes its own suite of saw cuts: the runner's loader reads it as the
    # foods x states given, every task a saw cut; a state it cannot say is refused before anything runs.
    sys.path.insert(0, str(REPO_ROOT / "learning" / "scripts"))
    from cstm_saw_study import main as study_main, suite_text
    from culinarycut.bench.suite import load_suite
    path = tmp_path / "cstm-saw.toml"
    path.write_text(suite_text(["cucumber", "banana"], ["middle", "ratio-0.3"], trials=2))
    suite = load_suite(str(path))
    assert sorted(t.name for t in suite.tasks) == ["banana/saw/middle", "banana/saw/ratio-0.3-left",
                                                   "cucumber/saw/middle", "cucumber/saw/ratio-0.3-left"]
    assert {(t.style, t.trials, t.quality) for t in suite.tasks} == {("saw", 2, "draft")}
    with pytest.raises(SystemExit, match="split-3 is neither middle nor ratio-R"):
        suite_text(["cucumber"], ["split-3"], trials=1)
    # Another data option for an existing study folder is refused, naming it.
    (tmp_path / "study").mkdir()
    (tmp_path / "study" / "study.json").write_text(json.dumps({"options": {"data": "elsewhere"}, "stages": {}}))
    with pytest.raises(SystemExit, match=r"other data options \(data, foods"):
        study_main(["--out", str(tmp_path / "study"), "--data", str(tmp_path), "--server", "127.0.0.1:1"])


def test_a_resumed_study_skips_the_stages_it_finished_with_the_same_command(tmp_path):
    # The studies' stages are resumable commands; one that already finished is neither run again nor timed
    # again (a resumed study's table would otherwise grow by each no-op rerun), while another command runs.
    from culinarycut_learning.study import Study
    study = Study(tmp_path, {"data": "d"}, ("data",), "test")
    runs = tmp_path / "runs.txt"
    count = ["-c", f"open({str(runs)!r}, 'a').write('x')"]
    assert study.stage("count", count) == 0
    wall_s = study.state["stages"]["count"]["wall_s"]
    resumed = Study(tmp_path, {"data": "d"}, ("data",), "test")
    assert resumed.stage("count", count) == 0
    assert runs.read_text() == "x" and resumed.state["stages"]["count"]["wall_s"] == wall_s
    assert resumed.stage("count", count + ["another"]) == 0  # another command (e.g. more steps) runs
    assert runs.read_text() == "xx"
    failing = ["-c", "raise SystemExit(3)"]
    with pytest.raises(SystemExit, match="fail exited 3"):
        resumed.stage("fail", failing)
    with pytest.raises(SystemExit, match="fail exited 3"):  # a failed stage is tried again, not skipped
        resumed.stage("fail", failing)
    assert resumed.stage("fail", failing, ok_codes=(0, 3)) == 3
    assert resumed.stage("fail", failing, ok_codes=(0, 3)) == 3
    # The report lists stages in the order a run reaches them (study.json keeps them sorted by name).
    again = Study(tmp_path, {"data": "d"}, ("data",), "test")
    again.stage("fail", failing, ok_codes=(0, 3))
    again.stage("count", count + ["another"])
    assert list(again.stage_times()) == ["fail", "count"]
