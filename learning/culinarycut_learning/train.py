"""Training: seeded and deterministic, checkpointed, resumable after a kill with the same result.

Determinism: the model is built after torch.manual_seed(seed); every step draws its batch, its image
shifts, its instruction choice and word dropout from a generator seeded with (seed, step) and seeds
torch's generator (dropout) the same way, so no random state has to survive a restart; the learning
rate is a function of the step; torch runs deterministic algorithms with a fixed thread count. Resuming
loads the weights and the optimiser's state of the last checkpoint and runs the remaining steps: the
same weights as a run that was never interrupted (tested), for the same configuration, data, torch
build and device."""
from __future__ import annotations

import hashlib
import json
import math
import os
import signal
import time
from pathlib import Path

import numpy as np
import torch

from culinarycut_learning.checkpoint import CHECKPOINT, load_checkpoint, save_checkpoint
from culinarycut_learning.config import TrainConfig, differences
from culinarycut_learning.data import Windows, file_digest, find_robomimic_file, load_episodes, normalisation
from culinarycut_learning.language import COUNT, RATIO, UNK, Tokenizer, load_templates, numeric_features
from culinarycut_learning.model import CuttingPolicy
from culinarycut_learning.progress import progress_bar

# Test hook: SIGKILL this process right after the given step's update, before any checkpoint of that step
# (the work since the last checkpoint is lost, as in a real kill).
KILL_AT_STEP_ENV = "CULINARYCUT_LEARNING_KILL_AT_STEP"
VALID_SAMPLES = 256


class RunError(ValueError):
    """A run folder that cannot be resumed with these options; the message says what differs."""


def resolve_device(name: str) -> torch.device:
    if name == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    device = torch.device(name)
    if device.type == "cuda" and not torch.cuda.is_available():
        raise RunError(f"--device {name}: this torch has no CUDA device (torch {torch.__version__}, "
                       f"CUDA {'built' if torch.backends.cuda.is_built() else 'not built'})")
    return device


def set_deterministic(threads: int) -> None:
    # cuBLAS needs this before its first call to be deterministic (the CLI sets it before importing torch).
    os.environ.setdefault("CUBLAS_WORKSPACE_CONFIG", ":4096:8")
    torch.set_num_threads(threads)
    torch.use_deterministic_algorithms(True)
    torch.backends.cudnn.benchmark = False
    torch.backends.cudnn.deterministic = True


def step_seed(seed: int, step: int) -> int:
    digest = hashlib.sha256(f"culinarycut-learning/{seed}/{step}".encode()).digest()
    return int.from_bytes(digest[:8], "little") >> 1


def optimisation_step(model: torch.nn.Module, optimizer: torch.optim.Optimizer, loss: torch.Tensor, lr: float,
                      grad_clip: float) -> float:
    """Backpropagates `loss` and steps `optimizer` at learning rate `lr`, the gradient's norm clipped to
    `grad_clip`; the loss's value. The one update every trainer here (the policy, CSTM's C and f) makes."""
    for group in optimizer.param_groups:
        group["lr"] = lr
    optimizer.zero_grad(set_to_none=True)
    loss.backward()
    torch.nn.utils.clip_grad_norm_(model.parameters(), grad_clip)
    optimizer.step()
    return float(loss.detach())


def resume_state(resumed: dict | None, model: torch.nn.Module, optimizer: torch.optim.Optimizer, out: Path,
                 steps: int, log) -> int:
    """Loads a resumed checkpoint's model and optimizer (when there is one) and says so; the step to go on from."""
    if resumed is None:
        return 0
    model.load_state_dict(resumed["model"])
    optimizer.load_state_dict(resumed["optimizer"])
    start = int(resumed["step"])
    log(f"resuming {out} at step {start} of {steps}")
    return start


def step_record(step: int, loss_value: float, lr: float, started: float, log_every: int, save_every: int,
                steps: int) -> dict | None:
    """The log line's record at a logging or saving step (and the last), else None."""
    if step % log_every and step % save_every and step != steps:
        return None
    return {"step": step, "loss": loss_value, "lr": lr, "elapsed_s": round(time.monotonic() - started, 3)}


def learning_rate(config: TrainConfig, step: int) -> float:
    """Linear warm-up to lr, then cosine down to lr * min_lr_fraction at the last step (step counts from 1)."""
    if step <= config.warmup_steps:
        return config.lr * step / max(1, config.warmup_steps)
    progress = (step - config.warmup_steps) / max(1, config.steps - config.warmup_steps)
    floor = config.lr * config.min_lr_fraction
    return floor + (config.lr - floor) * 0.5 * (1.0 + math.cos(math.pi * min(1.0, progress)))


def prompt_arrays(tokenizer: Tokenizer, texts: list[str], rng: np.random.Generator | None = None,
                  word_dropout: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(ids (B, L), number features (B, L, F)); with `rng`, trained words read as <unk> at `word_dropout`."""
    encoded = [tokenizer.encode(text) for text in texts]
    ids = np.stack([e[0] for e in encoded])
    values = np.stack([e[1] for e in encoded])
    if rng is not None and word_dropout > 0:
        drop = (rng.random(ids.shape) < word_dropout) & np.isin(ids, tokenizer.word_ids)
        ids = np.where(drop, tokenizer.index[UNK], ids)
    return ids, numeric_features(ids, values, tokenizer.index[RATIO], tokenizer.index[COUNT])


def shift_images(images: np.ndarray, rng: np.random.Generator, pixels: int) -> np.ndarray:
    """Random shifts of up to `pixels` (edge-padded, cropped back): one offset per sample and camera, the
    same for all its history frames. images (B, K, C, S, S, 3)."""
    if pixels <= 0:
        return images
    b, k, c, s = images.shape[:4]
    offsets = rng.integers(0, 2 * pixels + 1, size=(b, c, 2))
    padded = np.pad(images, ((0, 0), (0, 0), (0, 0), (pixels, pixels), (pixels, pixels), (0, 0)), mode="edge")
    out = np.empty_like(images)
    for i in range(b):
        for j in range(c):
            y, x = offsets[i, j]
            out[i, :, j] = padded[i, :, j, y:y + s, x:x + s]
    return out


def to_tensors(batch: dict, ids: np.ndarray, numbers: np.ndarray, device: torch.device) -> dict:
    return {"images": torch.from_numpy(np.ascontiguousarray(batch["images"])).to(device),
            "state": torch.from_numpy(batch["state"]).to(device),
            "wrench": torch.from_numpy(batch["wrench"]).to(device),
            "word_ids": torch.from_numpy(ids).to(device),
            "word_numbers": torch.from_numpy(numbers).to(device)}


def masked_l1(predicted: torch.Tensor, target: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
    return ((predicted - target).abs() * mask[..., None]).sum() / (mask.sum() * predicted.shape[-1]).clamp(min=1.0)


def train(data: Path, out: Path, config: TrainConfig, device: str = "cpu", progress: bool = True,
          templates: Path | None = None, log=print) -> dict:
    """Trains into the run folder `out` (resumed when it holds a checkpoint of the same run); returns a
    summary: steps, last loss, wall time, whether it resumed, the checkpoint's path."""
    started = time.monotonic()
    set_deterministic(config.threads)
    torch_device = resolve_device(device)
    out = Path(out)
    data_file = find_robomimic_file(Path(data))
    digest = file_digest(data_file)
    resumed = load_checkpoint(out) if (out / CHECKPOINT).is_file() else None
    if resumed is not None:
        changed = differences(TrainConfig.from_dict(resumed["config"]).identity(), config.identity())
        if resumed["data"]["sha256"] != digest:
            changed.append(f"data: {resumed['data']['file']} (sha256 {resumed['data']['sha256'][:12]}) -> "
                           f"{data_file} (sha256 {digest[:12]})")
        if changed:
            raise RunError(f"{out} holds a run with other settings; use another --out, or the same settings to "
                           f"resume it: {'; '.join(changed)}")
    episodes = load_episodes(data_file, config.model.image_size, "train", config.styles)
    valid_episodes = load_episodes(data_file, config.model.image_size, "valid", config.styles)
    if resumed is not None:
        tokenizer, stats = Tokenizer.from_dict(resumed["tokenizer"]), resumed["normalisation"]
    else:
        tokenizer = Tokenizer.build([t for e in episodes for t in e.instructions], load_templates(templates),
                                    config.model.max_prompt_tokens)
        stats = normalisation(episodes)
    windows = Windows(episodes, config.model.history, config.model.history_stride, config.model.chunk)
    torch.manual_seed(config.seed)
    model = CuttingPolicy(config.model, len(tokenizer.vocabulary), stats).to(torch_device)
    decay = [p for n, p in model.named_parameters() if p.ndim >= 2 and "position" not in n and "type" not in n]
    no_decay = [p for n, p in model.named_parameters() if not (p.ndim >= 2 and "position" not in n and "type" not in n)]
    optimizer = torch.optim.AdamW([{"params": decay, "weight_decay": config.weight_decay},
                                   {"params": no_decay, "weight_decay": 0.0}], lr=config.lr)
    start = resume_state(resumed, model, optimizer, out, config.steps, log)
    out.mkdir(parents=True, exist_ok=True)
    (out / "config.json").write_text(json.dumps({**config.to_dict(), "data": str(data_file), "data_sha256": digest},
                                                indent=2, sort_keys=True) + "\n")
    log_path = out / "log.jsonl"
    _truncate_log(log_path, start)
    meta = {"config": config.to_dict(), "tokenizer": tokenizer.to_dict(), "normalisation": stats,
            "data": {"file": str(data_file), "sha256": digest, "episodes": len(episodes), "frames": windows.frames,
                     "valid_episodes": len(valid_episodes)},
            "torch": torch.__version__}
    kill_at = int(os.environ.get(KILL_AT_STEP_ENV, "0") or 0)
    bar = progress_bar(config.steps, start, progress, config.log_every)
    loss_value = float(resumed["loss"]) if resumed is not None else float("nan")
    if start >= config.steps:
        log(f"{out} is trained: {start} of {config.steps} steps")
    model.train()
    try:
        for step in range(start + 1, config.steps + 1):
            rng = np.random.default_rng(step_seed(config.seed, step))
            flat = rng.integers(0, windows.frames, size=config.batch_size)
            batch = windows.batch(flat, rng.integers(0, 1 << 30, size=config.batch_size))
            batch["images"] = shift_images(batch["images"], rng, config.shift_px)
            ids, numbers = prompt_arrays(tokenizer, batch["texts"], rng, config.word_dropout)
            inputs = to_tensors(batch, ids, numbers, torch_device)
            torch.manual_seed(step_seed(config.seed, step))
            predicted = model(**inputs)
            target = model.normalise_actions(torch.from_numpy(batch["actions"]).to(torch_device))
            loss = masked_l1(predicted, target, torch.from_numpy(batch["action_mask"]).to(torch_device))
            loss_value = optimisation_step(model, optimizer, loss, learning_rate(config, step), config.grad_clip)
            bar.set_postfix_str(f"loss {loss_value:.4f}", refresh=False)
            bar.update(1)
            if step == kill_at:
                os.kill(os.getpid(), signal.SIGKILL)
            record = step_record(step, loss_value, learning_rate(config, step), started, config.log_every,
                                 config.save_every, config.steps)
            if step % config.save_every == 0 or step == config.steps:
                if valid_episodes:
                    record["valid_l1"] = validation_loss(model, valid_episodes, tokenizer, config, torch_device)
                    model.train()
                save_checkpoint(out / CHECKPOINT, {**meta, "step": step, "model": model.state_dict(),
                                                   "optimizer": optimizer.state_dict(), "loss": loss_value})
            if record is not None:
                with open(log_path, "a") as file:
                    file.write(json.dumps(record) + "\n")
    finally:
        bar.close()
    return {"steps": config.steps, "resumed_from": start, "loss": loss_value, "checkpoint": str(out / CHECKPOINT),
            "wall_s": time.monotonic() - started, "episodes": len(episodes), "frames": windows.frames}


def validation_loss(model: CuttingPolicy, episodes, tokenizer: Tokenizer, config: TrainConfig,
                    device: torch.device) -> float:
    """Masked L1 (normalised actions) over a fixed set of windows of the valid episodes, dropout off."""
    windows = Windows(episodes, config.model.history, config.model.history_stride, config.model.chunk)
    rng = np.random.default_rng(step_seed(config.seed, -1))
    flat = rng.permutation(windows.frames)[:VALID_SAMPLES]
    model.eval()
    total, count = 0.0, 0
    with torch.no_grad():
        for first in range(0, len(flat), config.batch_size):
            part = flat[first:first + config.batch_size]
            batch = windows.batch(part, np.zeros(len(part), dtype=np.int64))
            ids, numbers = prompt_arrays(tokenizer, batch["texts"])
            predicted = model(**to_tensors(batch, ids, numbers, device))
            target = model.normalise_actions(torch.from_numpy(batch["actions"]).to(device))
            total += float(masked_l1(predicted, target, torch.from_numpy(batch["action_mask"]).to(device))) * len(part)
            count += len(part)
    return total / max(count, 1)


def _truncate_log(path: Path, step: int) -> None:
    """Drops the log lines after `step` (written by a run killed after its last checkpoint)."""
    if not path.is_file():
        return
    kept = [line for line in path.read_text().splitlines() if line.strip() and json.loads(line)["step"] <= step]
    path.write_text("".join(line + "\n" for line in kept))
