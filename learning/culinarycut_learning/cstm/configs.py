"""The configurations of the two CSTM training runs: each network's shape and the optimisation. Saved in the
run folder (config.json) and in every checkpoint; a run folder is resumed only with the same configuration
(the fields in RUNTIME_FIELDS aside)."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from culinarycut_learning.config import RUNTIME_FIELDS


@dataclass(frozen=True)
class ClassifierModel:
    """torchvision's VisionTransformer, small enough to train and run on a CPU at 64-96 px."""
    camera: str = "front"        # the camera C sees (the export's obs/<camera>_image; the policy's option camera)
    image_size: int = 64         # pixels, square; frames are resized as the learned policy's are (features.model_image)
    patch_size: int = 8          # pixels: 64 px -> 8 x 8 = 64 patches
    layers: int = 4
    heads: int = 4
    hidden_dim: int = 128
    mlp_dim: int = 256
    dropout: float = 0.0

    def __post_init__(self):
        if self.image_size % self.patch_size:
            raise ValueError(f"image_size {self.image_size} is not a multiple of patch_size {self.patch_size}")
        if self.hidden_dim % self.heads:
            raise ValueError(f"hidden_dim {self.hidden_dim} is not a multiple of heads {self.heads}")
        for name in ("image_size", "patch_size", "layers", "heads", "hidden_dim", "mlp_dim"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be at least 1, got {getattr(self, name)}")


@dataclass(frozen=True)
class GeneratorModel:
    """A transformer encoder over the chunk's actions (one token per step)."""
    chunk: int = 10              # actions per chunk: the learned policy's chunk (config.ModelConfig.chunk)
    d_model: int = 64
    heads: int = 4
    layers: int = 2
    feedforward: int = 128
    dropout: float = 0.0
    # Periods (control steps) of the sine features of the steps since contact began: a saw stroke at 1-2 Hz
    # is 10-20 steps at 20 Hz.
    phase_periods: tuple = (6.0, 10.0, 14.0, 20.0, 28.0, 40.0, 80.0)

    def __post_init__(self):
        object.__setattr__(self, "phase_periods", tuple(float(p) for p in self.phase_periods))
        if self.d_model % self.heads:
            raise ValueError(f"d_model {self.d_model} is not a multiple of heads {self.heads}")
        for name in ("chunk", "d_model", "heads", "layers", "feedforward"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be at least 1, got {getattr(self, name)}")


@dataclass(frozen=True)
class Optimisation:
    steps: int = 2000
    batch_size: int = 32
    lr: float = 3e-4
    weight_decay: float = 1e-4
    warmup_steps: int = 100
    min_lr_fraction: float = 0.1   # cosine decay from lr to lr * this at the last step
    grad_clip: float = 1.0
    seed: int = 0
    threads: int = 2               # torch intra-op threads: part of what makes a run reproducible
    save_every: int = 200
    log_every: int = 20

    def __post_init__(self):
        for name in ("steps", "batch_size", "threads", "save_every", "log_every"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be at least 1, got {getattr(self, name)}")
        if self.warmup_steps < 0:
            raise ValueError(f"warmup_steps must be 0 or more, got {self.warmup_steps}")


@dataclass(frozen=True)
class ClassifierConfig:
    model: ClassifierModel = field(default_factory=ClassifierModel)
    optim: Optimisation = field(default_factory=Optimisation)
    shift_px: int = 4              # random image shift (edge-padded), as the policy's training does

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> "ClassifierConfig":
        data = dict(data)
        return cls(model=ClassifierModel(**data.pop("model", {})), optim=Optimisation(**data.pop("optim", {})), **data)

    def identity(self) -> dict:
        return _identity(self.to_dict())


@dataclass(frozen=True)
class GeneratorConfig:
    model: GeneratorModel = field(default_factory=GeneratorModel)
    optim: Optimisation = field(default_factory=Optimisation)
    max_gap: int = 2               # contact gaps of up to this many steps do not split a contact segment
    min_steps: int = 3             # contact runs shorter than this are flicker, not a cut
    valid_every: int = 10          # every valid_every-th pair is held out (none with fewer pairs)

    def to_dict(self) -> dict:
        data = dataclasses.asdict(self)
        data["model"]["phase_periods"] = list(self.model.phase_periods)
        return data

    @classmethod
    def from_dict(cls, data: dict) -> "GeneratorConfig":
        data = dict(data)
        return cls(model=GeneratorModel(**data.pop("model", {})), optim=Optimisation(**data.pop("optim", {})), **data)

    def identity(self) -> dict:
        return _identity(self.to_dict())


def _identity(data: dict) -> dict:
    """What must match for a run folder to be resumed: all but the logging and checkpoint cadence."""
    for name in RUNTIME_FIELDS:
        data["optim"].pop(name)
    return data
