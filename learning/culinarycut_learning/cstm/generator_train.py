"""Training f, the style generator, by behaviour cloning on paired contact segments (pairs.py) from a pairs
folder (oracle_pairs.py): masked L1 on the normalised style chunk, as the policy's trainer trains its chunks.
Seeded and resumable as the other trainers (train.py): the network built after torch.manual_seed(seed), each
step's batch drawn from a generator seeded with (seed, step), deterministic algorithms at a fixed thread count.
Every `valid_every`-th pair file is held out; its L1 is logged at each checkpoint."""
from __future__ import annotations

import time
from pathlib import Path
from typing import Callable

import numpy as np
import torch

from culinarycut_learning.cstm import runs
from culinarycut_learning.cstm.configs import GeneratorConfig
from culinarycut_learning.cstm.oracle_pairs import load_pair, pair_files, pairs_digest
from culinarycut_learning.cstm.pairs import pair_windows
from culinarycut_learning.cstm.style_generator import StyleGenerator
from culinarycut_learning.cstm.styles import STYLES
from culinarycut_learning.data import STD_FLOOR
from culinarycut_learning.progress import progress_bar
from culinarycut_learning.train import (learning_rate, masked_l1, optimisation_step, resolve_device,
                                        resume_state, set_deterministic, step_record, step_seed)


def normalisation(windows: dict[str, torch.Tensor]) -> dict[str, list[float]]:
    """Mean and standard deviation (floored) of every action the windows hold, inputs and targets together."""
    mask = windows["mask"].bool()
    values = torch.cat([windows["inputs"][mask], windows["targets"][mask]]).double()
    return {"mean": values.mean(0).tolist(), "std": values.std(0, unbiased=False).clamp(min=STD_FLOOR).tolist()}


def windows_loss(model: StyleGenerator, windows: dict, picked: torch.Tensor, device: torch.device) -> torch.Tensor:
    batch = {key: value[picked].to(device) for key, value in windows.items()}
    predicted = model(batch["inputs"], batch["style"], batch["contact_step"])
    return masked_l1(predicted, model.normalise(batch["targets"]), batch["mask"])


def split_files(files: list[Path], every: int) -> tuple[list[Path], list[Path]]:
    valid = [f for i, f in enumerate(files) if every and i % every == every - 1]
    return [f for f in files if f not in valid], valid


def train_generator(pairs: Path, out: Path, config: GeneratorConfig, device: str = "cpu", progress: bool = True,
                    log=print, on_step: Callable[[int], None] | None = None) -> dict:
    """Trains (or resumes) the run folder `out` on the pairs folder `pairs`; returns a summary."""
    started = time.monotonic()
    optim = config.optim
    set_deterministic(optim.threads)
    torch_device = resolve_device(device)
    files = pair_files(Path(pairs))
    data_info = {"source": str(pairs), "sha256": pairs_digest(files), "pair_files": len(files)}
    resumed = runs.open_run(out, runs.GENERATOR_FORMAT, config.identity(), data_info,
                            lambda saved: GeneratorConfig.from_dict(saved).identity())
    train_files, valid_files = split_files(files, config.valid_every)

    def windows_of(chosen):
        loaded = [load_pair(f)[:2] for f in chosen]
        return pair_windows(loaded, config.model.chunk, max_gap=config.max_gap, min_steps=config.min_steps), loaded

    windows, loaded = windows_of(train_files)
    valid = windows_of(valid_files)[0] if valid_files else None
    styles = sorted({t.style for pair in loaded for t in pair}, key=STYLES.index)
    log(f"style generator: {len(windows['inputs'])} windows from {len(train_files)} pairs "
        f"(styles {', '.join(styles)}); "
        f"held out: {len(valid_files)} pairs")
    stats = resumed["normalisation"] if resumed is not None else normalisation(windows)
    torch.manual_seed(optim.seed)
    model = StyleGenerator(config.model, stats).to(torch_device)
    optimizer = torch.optim.AdamW(model.parameters(), lr=optim.lr, weight_decay=optim.weight_decay)
    start = resume_state(resumed, model, optimizer, out, optim.steps, log)
    data_info.update(train_pairs=len(train_files), valid_pairs=len(valid_files), windows=len(windows["inputs"]),
                     styles=styles)
    log_path = runs.start_folder(out, config.to_dict(), data_info, start)
    loss_value = float(resumed["loss"]) if resumed is not None else float("nan")
    valid_l1 = resumed.get("valid_l1") if resumed is not None else None
    bar = progress_bar(optim.steps, start, progress, optim.log_every, desc="cstm-generator")
    try:
        for step in range(start + 1, optim.steps + 1):
            model.train()
            rng = np.random.default_rng(step_seed(optim.seed, step))
            picked = torch.from_numpy(rng.integers(0, len(windows["inputs"]), size=optim.batch_size))
            torch.manual_seed(step_seed(optim.seed, step))   # dropout, when the config has any
            loss_value = optimisation_step(model, optimizer, windows_loss(model, windows, picked, torch_device),
                                           learning_rate(optim, step), optim.grad_clip)
            bar.set_postfix_str(f"loss {loss_value:.4f}", refresh=False)
            bar.update(1)
            record = step_record(step, loss_value, learning_rate(optim, step), started, optim.log_every,
                                 optim.save_every, optim.steps)
            if step % optim.save_every == 0 or step == optim.steps:
                if valid is not None:
                    model.eval()
                    with torch.no_grad():
                        valid_l1 = float(windows_loss(model, valid, torch.arange(len(valid["inputs"])), torch_device))
                    record["valid_l1"] = valid_l1
                runs.save(out, runs.GENERATOR_FORMAT,
                          {"config": config.to_dict(), "data": data_info, "normalisation": stats, "styles": styles,
                           "step": step, "loss": loss_value, "valid_l1": valid_l1, "model": model.state_dict(),
                           "optimizer": optimizer.state_dict()})
            if record is not None:
                runs.append_log(log_path, record)
            if on_step is not None:
                on_step(step)
    finally:
        bar.close()
    return {"steps": optim.steps, "resumed_from": start, "loss": loss_value, "valid_l1": valid_l1,
            "checkpoint": str(Path(out) / "checkpoint.pt"), "windows": len(windows["inputs"]), "styles": styles,
            "wall_s": time.monotonic() - started}


def load_generator(run_or_file: Path) -> tuple[StyleGenerator, dict]:
    """(the generator in eval mode on the CPU, its checkpoint)."""
    payload = runs.load(run_or_file, runs.GENERATOR_FORMAT)
    config = GeneratorConfig.from_dict(payload["config"])
    model = StyleGenerator(config.model, payload["normalisation"])
    model.load_state_dict(payload["model"])
    model.eval()
    return model, payload
