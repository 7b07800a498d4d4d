"""f(a_hat chunk, style): the CSTM's cut-style generator (the CulinaryCut paper's CSTM: "a cut-style generator f
converts the predicted trajectory into a style-specific trajectory").

    chunk of H normal-style actions (H, 6), OSC units -> one token per step: linear(normalised action)
        + a learned position + a learned style embedding (normal, bias, guillotine, saw)
        + linear(phase features of the steps since contact began: t / 100, sin and cos of 2 pi t / P)
    -> transformer encoder (2 layers, width 64) -> linear -> the style's chunk (H, 6), as a residual on the input

The output layer starts at zero, so an untrained f returns its input: a_hat unchanged. Inputs and outputs
are normalised with the training pairs' mean and standard deviation (buffers saved with the weights); the
model takes and returns raw OSC units through `stylise`."""
from __future__ import annotations

import math

import torch
from torch import nn

from culinarycut_learning.cstm.configs import GeneratorModel
from culinarycut_learning.cstm.styles import STYLES
from culinarycut_learning.features import ACTION_DIMS

PHASE_SCALE_STEPS = 100.0   # t / this: the linear phase feature stays near [0, 1] over a cut (about 20-150 steps)


def phase_features(steps: torch.Tensor, periods: tuple) -> torch.Tensor:
    """(..., 1 + 2 len(periods)): t / 100, sin and cos of 2 pi t / P for each period P (control steps)."""
    periods_t = torch.tensor(periods, dtype=torch.float32, device=steps.device)
    angle = 2.0 * math.pi * steps[..., None] / periods_t
    return torch.cat([steps[..., None] / PHASE_SCALE_STEPS, angle.sin(), angle.cos()], dim=-1)


class StyleGenerator(nn.Module):
    def __init__(self, config: GeneratorModel, normalisation: dict):
        super().__init__()
        self.config = config
        d = config.d_model
        self.action_in = nn.Linear(ACTION_DIMS, d)
        self.phase_in = nn.Linear(1 + 2 * len(config.phase_periods), d)
        self.style = nn.Embedding(len(STYLES), d)
        self.position = nn.Parameter(torch.randn(config.chunk, d) * 0.02)
        layer = nn.TransformerEncoderLayer(d, config.heads, config.feedforward, config.dropout, activation="gelu",
                                           batch_first=True, norm_first=True)
        self.encoder = nn.TransformerEncoder(layer, config.layers, norm=nn.LayerNorm(d), enable_nested_tensor=False)
        self.out = nn.Linear(d, ACTION_DIMS)
        nn.init.zeros_(self.out.weight)   # f starts as the identity
        nn.init.zeros_(self.out.bias)
        self.register_buffer("actions_mean", torch.tensor(normalisation["mean"], dtype=torch.float32))
        self.register_buffer("actions_std", torch.tensor(normalisation["std"], dtype=torch.float32))

    def normalise(self, actions: torch.Tensor) -> torch.Tensor:
        return (actions - self.actions_mean) / self.actions_std

    def forward(self, chunk: torch.Tensor, style: torch.Tensor, contact_step: torch.Tensor) -> torch.Tensor:
        """chunk (B, H, 6) OSC units, style (B,) indices into STYLES, contact_step (B,) steps since contact
        began at the chunk's first action -> the style's chunk (B, H, 6), normalised."""
        h = chunk.shape[1]
        if h != self.config.chunk:
            raise ValueError(f"the generator takes chunks of {self.config.chunk} actions, got {h}")
        normalised = self.normalise(chunk)
        steps = contact_step.float()[:, None] + torch.arange(h, device=chunk.device, dtype=torch.float32)
        tokens = (self.action_in(normalised) + self.phase_in(phase_features(steps, self.config.phase_periods))
                  + self.position + self.style(style)[:, None, :])
        return normalised + self.out(self.encoder(tokens))

    def actions(self, normalised: torch.Tensor) -> torch.Tensor:
        return normalised * self.actions_std + self.actions_mean

    @torch.no_grad()
    def stylise(self, chunk: torch.Tensor, style: int, contact_step: int) -> torch.Tensor:
        """One chunk (H, 6) OSC units -> the style's (H, 6) OSC units."""
        batch = chunk[None].float()
        out = self(batch, torch.tensor([style]), torch.tensor([float(contact_step)]))
        return self.actions(out)[0]
