"""Training C, the contact classifier: binary cross-entropy on frames of one camera labelled with the
simulator's knife-food contact (contact_data.py), as the policy's trainer runs (train.py): the network built
after torch.manual_seed(seed); each step's batch and image shifts drawn from a generator seeded with (seed,
step), so nothing random outlives a step and a resumed run reaches the weights of an uninterrupted one;
deterministic algorithms at a fixed thread count. Each batch is half contact frames and half others (contact
is the rarer class: about a quarter of a draft strawberry cut's frames). The held-out accuracy (and the balanced
accuracy, the mean of the two classes' recalls) is logged at every checkpoint and returned."""
from __future__ import annotations

import time
from pathlib import Path
from typing import Callable

import numpy as np
import torch

from culinarycut_learning.cstm import runs
from culinarycut_learning.cstm.configs import ClassifierConfig
from culinarycut_learning.cstm.contact_classifier import ContactClassifier
from culinarycut_learning.cstm.contact_data import ContactFrames, load_split
from culinarycut_learning.data import file_digest, find_robomimic_file
from culinarycut_learning.progress import progress_bar
from culinarycut_learning.train import (learning_rate, optimisation_step, resolve_device, resume_state,
                                        set_deterministic, shift_images, step_record, step_seed)

EVAL_BATCH = 256


def balanced_batch(labels: np.ndarray, rng: np.random.Generator, size: int) -> np.ndarray:
    """Frame indices: half (rounded up) with contact, the rest without."""
    positive, negative = np.flatnonzero(labels), np.flatnonzero(labels == 0)
    half = (size + 1) // 2
    return np.concatenate([rng.choice(positive, half), rng.choice(negative, size - half)])


def evaluate(model: ContactClassifier, frames: ContactFrames, device: torch.device) -> dict | None:
    """Accuracy, balanced accuracy and counts on `frames` (threshold 0.5); None without frames."""
    if not len(frames):
        return None
    model.eval()
    predicted = []
    with torch.no_grad():
        for first in range(0, len(frames), EVAL_BATCH):
            images = torch.from_numpy(frames.images[first:first + EVAL_BATCH]).to(device)
            predicted.append((model(images) > 0).cpu().numpy())
    predicted = np.concatenate(predicted).astype(np.uint8)
    truth = frames.labels
    recalls = [float(np.mean(predicted[truth == c] == c)) for c in (0, 1) if np.any(truth == c)]
    return {"accuracy": float(np.mean(predicted == truth)), "balanced_accuracy": float(np.mean(recalls)),
            "frames": int(len(truth)), "contact_frames": int(truth.sum()), "demos": len(frames.demos)}


def train_classifier(data: Path, out: Path, config: ClassifierConfig, device: str = "cpu", progress: bool = True,
                     log=print, on_step: Callable[[int], None] | None = None) -> dict:
    """Trains (or resumes) the run folder `out` on the export `data`; returns a summary with the held-out
    metrics. `on_step(step)` is called after each update (a test stops a run there to check resuming)."""
    started = time.monotonic()
    optim = config.optim
    set_deterministic(optim.threads)
    torch_device = resolve_device(device)
    data_file = find_robomimic_file(Path(data))
    data_info = {"source": str(data_file), "sha256": file_digest(data_file)}
    resumed = runs.open_run(out, runs.CLASSIFIER_FORMAT, config.identity(), data_info,
                            lambda saved: ClassifierConfig.from_dict(saved).identity())
    train_frames, valid_frames, held_out = load_split(data_file, config.model.camera, config.model.image_size)
    log(f"contact classifier: {len(train_frames)} frames ({int(train_frames.labels.sum())} in contact) from "
        f"{len(train_frames.demos)} demos; held out: {len(valid_frames)} frames ({held_out})")
    torch.manual_seed(optim.seed)
    model = ContactClassifier(config.model).to(torch_device)
    optimizer = torch.optim.AdamW(model.parameters(), lr=optim.lr, weight_decay=optim.weight_decay)
    start = resume_state(resumed, model, optimizer, out, optim.steps, log)
    data_info.update(camera=config.model.camera, camera_size=train_frames.camera_size, train_frames=len(train_frames),
                     train_contact_frames=int(train_frames.labels.sum()), held_out=held_out,
                     held_out_frames=len(valid_frames))
    log_path = runs.start_folder(out, config.to_dict(), data_info, start)
    loss_value = float(resumed["loss"]) if resumed is not None else float("nan")
    metrics = resumed.get("held_out") if resumed is not None else None
    loss_fn = torch.nn.BCEWithLogitsLoss()
    bar = progress_bar(optim.steps, start, progress, optim.log_every, desc="cstm-classifier")
    try:
        for step in range(start + 1, optim.steps + 1):
            model.train()
            rng = np.random.default_rng(step_seed(optim.seed, step))
            picked = balanced_batch(train_frames.labels, rng, optim.batch_size)
            images = shift_images(train_frames.images[picked][:, None, None], rng, config.shift_px)[:, 0, 0]
            torch.manual_seed(step_seed(optim.seed, step))   # dropout, when the config has any
            logits = model(torch.from_numpy(np.ascontiguousarray(images)).to(torch_device))
            target = torch.from_numpy(train_frames.labels[picked].astype(np.float32)).to(torch_device)
            loss_value = optimisation_step(model, optimizer, loss_fn(logits, target), learning_rate(optim, step),
                                           optim.grad_clip)
            bar.set_postfix_str(f"loss {loss_value:.4f}", refresh=False)
            bar.update(1)
            record = step_record(step, loss_value, learning_rate(optim, step), started, optim.log_every,
                                 optim.save_every, optim.steps)
            if step % optim.save_every == 0 or step == optim.steps:
                metrics = evaluate(model, valid_frames, torch_device)
                if metrics is not None:
                    record.update(valid_accuracy=metrics["accuracy"],
                                  valid_balanced_accuracy=metrics["balanced_accuracy"])
                runs.save(out, runs.CLASSIFIER_FORMAT,
                          {"config": config.to_dict(), "data": data_info, "step": step, "loss": loss_value,
                           "held_out": metrics, "model": model.state_dict(), "optimizer": optimizer.state_dict()})
            if record is not None:
                runs.append_log(log_path, record)
            if on_step is not None:
                on_step(step)
    finally:
        bar.close()
    return {"steps": optim.steps, "resumed_from": start, "loss": loss_value, "held_out": metrics,
            "held_out_demos": held_out, "checkpoint": str(Path(out) / "checkpoint.pt"),
            "frames": len(train_frames), "wall_s": time.monotonic() - started}


def load_classifier(run_or_file: Path) -> tuple[ContactClassifier, dict]:
    """(the classifier in eval mode on the CPU, its checkpoint)."""
    payload = runs.load(run_or_file, runs.CLASSIFIER_FORMAT)
    config = ClassifierConfig.from_dict(payload["config"])
    model = ContactClassifier(config.model)
    model.load_state_dict(payload["model"])
    model.eval()
    return model, payload
