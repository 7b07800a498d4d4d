"""The configuration of a training run: the model's shape and the optimisation. Saved in the run folder
(config.json) and in every checkpoint; a run folder is resumed only with the same configuration."""
from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass, field

from culinarycut.datasets.jobs import STYLES

ENCODERS = ("small_cnn", "resnet18")
# Fields that do not change the weights a run arrives at: they may differ when a run is resumed.
RUNTIME_FIELDS = ("save_every", "log_every")


@dataclass(frozen=True)
class ModelConfig:
    image_size: int = 96           # pixels, square; the adapter's 224 x 224 frames are resized to it
    encoder: str = "small_cnn"     # small_cnn (4 conv layers, GroupNorm) or resnet18 (torchvision, weights=None)
    image_tokens: int = 4          # tokens per image: learned queries attending over the feature map
    d_model: int = 128
    heads: int = 4
    encoder_layers: int = 3
    decoder_layers: int = 2
    feedforward: int = 512
    dropout: float = 0.1
    history: int = 2               # frames the model sees: now and history - 1 earlier ones ...
    history_stride: int = 5        # ... this many control steps apart (the openpi adapter's replan_steps)
    chunk: int = 10                # actions predicted per query (ACT's chunk; the adapter executes 5)
    max_prompt_tokens: int = 32

    def __post_init__(self):
        if self.encoder not in ENCODERS:
            raise ValueError(f"encoder {self.encoder!r}; choose one of {', '.join(ENCODERS)}")
        if self.d_model % self.heads:
            raise ValueError(f"d_model {self.d_model} is not a multiple of heads {self.heads}")
        for name in ("image_size", "image_tokens", "history", "history_stride", "chunk", "max_prompt_tokens"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be at least 1, got {getattr(self, name)}")
        if self.image_size < 32:
            raise ValueError(f"image_size must be at least 32 pixels, got {self.image_size}")


@dataclass(frozen=True)
class TrainConfig:
    model: ModelConfig = field(default_factory=ModelConfig)
    steps: int = 20000
    batch_size: int = 32
    lr: float = 3e-4
    weight_decay: float = 1e-4
    warmup_steps: int = 500
    min_lr_fraction: float = 0.1   # cosine decay from lr to lr * this at the last step
    grad_clip: float = 1.0
    seed: int = 0
    threads: int = 2               # torch intra-op threads: part of what makes a run reproducible
    shift_px: int = 4              # random image shift (pad and crop), the same for every frame of a sample
    word_dropout: float = 0.1      # a training word read as <unk>
    save_every: int = 500
    log_every: int = 50
    styles: tuple = ()             # cut styles of the demos trained on (their cut_spec's); empty: every demo

    def __post_init__(self):
        object.__setattr__(self, "styles", tuple(self.styles))  # a list from JSON compares equal to the tuple
        unknown = set(self.styles) - set(STYLES)
        if unknown:
            raise ValueError(f"styles: {', '.join(sorted(unknown))} is not a cut style ({', '.join(STYLES)})")
        for name in ("steps", "batch_size", "threads", "save_every", "log_every"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be at least 1, got {getattr(self, name)}")
        if not 0.0 <= self.word_dropout < 1.0:
            raise ValueError(f"word_dropout must lie in [0, 1), got {self.word_dropout}")

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> "TrainConfig":
        data = dict(data)
        model = ModelConfig(**data.pop("model", {}))
        return cls(model=model, **data)

    def identity(self) -> dict:
        """What must match for a run folder to be resumed."""
        data = self.to_dict()
        for name in RUNTIME_FIELDS:
            data.pop(name)
        return data


def differences(saved: dict, wanted: dict, prefix: str = "") -> list[str]:
    """'name: saved -> wanted' for every field that differs (nested configs flattened with dots)."""
    out = []
    for key in sorted(set(saved) | set(wanted)):
        a, b = saved.get(key), wanted.get(key)
        if isinstance(a, dict) and isinstance(b, dict):
            out += differences(a, b, f"{prefix}{key}.")
        elif a != b:
            out.append(f"{prefix}{key}: {json.dumps(a)} -> {json.dumps(b)}")
    return out
