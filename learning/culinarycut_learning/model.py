"""The policy: a language-conditioned visuomotor transformer with ACT-style action chunks.

    front, wrist images (history K) -> CNN (shared, from scratch) -> feature map -> P tokens each
                                        (learned queries attending over the map, 2-D sine positions)
    TCP state (6), wrist force (6)   -> one linear token each per frame
    instruction                      -> word embeddings + features of each number's value (language.py)
    [language | frame 1 | ... | frame K] + type, time and position embeddings
        -> transformer encoder -> H learned action queries -> transformer decoder -> (H, 6) actions

Inputs are normalised inside the model with the training set's statistics (buffers saved with the
weights), so the model takes and returns raw values: state in m and rad, the compressed wrench
(features.py), actions in OSC units. ACT's CVAE is left out: the demonstrations come from the scripted
planner and its replays, one motion per instruction and scene, not the multimodal human data the CVAE's
style variable was made for; an L1 loss on whole chunks already gives ACT's smooth, committed motion."""
from __future__ import annotations

import math

import torch
from torch import nn

from culinarycut_learning.config import ModelConfig
from culinarycut_learning.features import ACTION_DIMS, STATE_DIMS, WRENCH_DIMS
from culinarycut_learning.language import NUMBER_FEATURES

CAMERA_COUNT = 2
IMAGE_MEAN, IMAGE_STD = 0.5, 0.25


def _group_norm(channels: int) -> nn.GroupNorm:
    return nn.GroupNorm(min(32, channels // 4), channels)


class SmallCNN(nn.Module):
    """Four 3x3/5x5 stride-2 convolutions with GroupNorm (batch statistics would tie a sample's features
    to its batch): 96 px -> 6 x 6 x 128."""

    channels = 128

    def __init__(self):
        super().__init__()
        layers, previous = [], 3
        for out, kernel in ((32, 5), (64, 3), (128, 3), (128, 3)):
            layers += [nn.Conv2d(previous, out, kernel, stride=2, padding=kernel // 2), _group_norm(out), nn.ReLU()]
            previous = out
        self.net = nn.Sequential(*layers)

    def forward(self, x):
        return self.net(x)


class ResNet18(nn.Module):
    """torchvision's resnet18, weights=None (trained from scratch), GroupNorm in place of BatchNorm, up to
    its last stage: 96 px -> 3 x 3 x 512."""

    channels = 512

    def __init__(self):
        super().__init__()
        import torchvision
        net = torchvision.models.resnet18(weights=None, norm_layer=_group_norm)
        self.net = nn.Sequential(net.conv1, net.bn1, net.relu, net.maxpool, net.layer1, net.layer2, net.layer3,
                                 net.layer4)

    def forward(self, x):
        return self.net(x)


def sine_positions_2d(height: int, width: int, dim: int, device) -> torch.Tensor:
    """(height * width, dim) fixed sine/cosine positions (DETR's), half the channels for y, half for x."""
    quarter = dim // 4
    freq = torch.exp(-math.log(10000.0) * torch.arange(quarter, device=device, dtype=torch.float32) / quarter)
    ys = torch.arange(height, device=device, dtype=torch.float32)[:, None] * freq
    xs = torch.arange(width, device=device, dtype=torch.float32)[:, None] * freq
    y = torch.cat([ys.sin(), ys.cos()], dim=1)[:, None, :].expand(height, width, 2 * quarter)
    x = torch.cat([xs.sin(), xs.cos()], dim=1)[None, :, :].expand(height, width, 2 * quarter)
    pos = torch.cat([y, x], dim=2).reshape(height * width, 4 * quarter)
    return nn.functional.pad(pos, (0, dim - 4 * quarter))


class ImageTokens(nn.Module):
    """An image -> `tokens` vectors: backbone feature map, 1x1 projection, sine positions, then learned
    queries attending over it (attention pooling: any image size, a fixed number of tokens)."""

    def __init__(self, config: ModelConfig):
        super().__init__()
        self.backbone = SmallCNN() if config.encoder == "small_cnn" else ResNet18()
        self.project = nn.Conv2d(self.backbone.channels, config.d_model, 1)
        self.queries = nn.Parameter(torch.randn(config.image_tokens, config.d_model) * 0.02)
        self.attend = nn.MultiheadAttention(config.d_model, config.heads, batch_first=True)
        self.norm = nn.LayerNorm(config.d_model)

    def forward(self, images: torch.Tensor) -> torch.Tensor:
        features = self.project(self.backbone(images))                  # (N, d, h, w)
        n, d, h, w = features.shape
        keys = features.flatten(2).transpose(1, 2) + sine_positions_2d(h, w, d, features.device)
        queries = self.queries.unsqueeze(0).expand(n, -1, -1)
        pooled, _ = self.attend(queries, keys, keys, need_weights=False)
        return self.norm(pooled + queries)                               # (N, tokens, d)


class CuttingPolicy(nn.Module):
    def __init__(self, config: ModelConfig, vocabulary_size: int, normalisation: dict):
        super().__init__()
        self.config = config
        d = config.d_model
        self.images = ImageTokens(config)
        self.state_in = nn.Linear(STATE_DIMS, d)
        self.wrench_in = nn.Linear(WRENCH_DIMS, d)
        self.words = nn.Embedding(vocabulary_size, d, padding_idx=0)
        self.numbers = nn.Linear(NUMBER_FEATURES, d, bias=False)
        self.word_position = nn.Parameter(torch.randn(config.max_prompt_tokens, d) * 0.02)
        # token types: language, one per camera, state, wrench
        self.token_type = nn.Parameter(torch.randn(2 + CAMERA_COUNT + 1, d) * 0.02)
        self.image_slot = nn.Parameter(torch.randn(CAMERA_COUNT, config.image_tokens, d) * 0.02)
        self.frame_time = nn.Parameter(torch.randn(config.history, d) * 0.02)
        encoder_layer = nn.TransformerEncoderLayer(d, config.heads, config.feedforward, config.dropout,
                                                   activation="gelu", batch_first=True, norm_first=True)
        self.encoder = nn.TransformerEncoder(encoder_layer, config.encoder_layers, norm=nn.LayerNorm(d),
                                             enable_nested_tensor=False)
        decoder_layer = nn.TransformerDecoderLayer(d, config.heads, config.feedforward, config.dropout,
                                                   activation="gelu", batch_first=True, norm_first=True)
        self.decoder = nn.TransformerDecoder(decoder_layer, config.decoder_layers, norm=nn.LayerNorm(d))
        self.action_queries = nn.Parameter(torch.randn(config.chunk, d) * 0.02)
        self.action_out = nn.Linear(d, ACTION_DIMS)
        for key in ("state", "wrench", "actions"):
            self.register_buffer(f"{key}_mean", torch.tensor(normalisation[key]["mean"], dtype=torch.float32))
            self.register_buffer(f"{key}_std", torch.tensor(normalisation[key]["std"], dtype=torch.float32))

    def normalise_actions(self, actions: torch.Tensor) -> torch.Tensor:
        return (actions - self.actions_mean) / self.actions_std

    def forward(self, images, state, wrench, word_ids, word_numbers):
        """images (B, K, C, S, S, 3) uint8, state (B, K, 6), wrench (B, K, 6) compressed, word_ids (B, L),
        word_numbers (B, L, NUMBER_FEATURES) -> normalised actions (B, H, 6) (`actions` un-normalises)."""
        b, k, c = images.shape[:3]
        pixels = images.reshape(b * k * c, *images.shape[3:]).permute(0, 3, 1, 2).float()
        pixels = (pixels / 255.0 - IMAGE_MEAN) / IMAGE_STD
        image_tokens = self.images(pixels).reshape(b, k, c, self.config.image_tokens, -1)
        image_tokens = image_tokens + self.image_slot + self.token_type[1:1 + c, None, :]
        image_tokens = image_tokens.reshape(b, k, c * self.config.image_tokens, -1)
        state_token = self.state_in((state - self.state_mean) / self.state_std) + self.token_type[1 + CAMERA_COUNT]
        wrench_token = self.wrench_in((wrench - self.wrench_mean) / self.wrench_std) + self.token_type[2 + CAMERA_COUNT]
        frames = torch.cat([image_tokens, state_token[:, :, None], wrench_token[:, :, None]], dim=2)
        frames = (frames + self.frame_time[None, :, None, :]).reshape(b, -1, frames.shape[-1])
        length = word_ids.shape[1]
        language = (self.words(word_ids) + self.numbers(word_numbers) + self.word_position[:length]
                    + self.token_type[0])
        tokens = torch.cat([language, frames], dim=1)
        padding = torch.cat([word_ids == 0, torch.zeros(b, frames.shape[1], dtype=torch.bool,
                                                        device=word_ids.device)], dim=1)
        memory = self.encoder(tokens, src_key_padding_mask=padding)
        queries = self.action_queries.unsqueeze(0).expand(b, -1, -1)
        decoded = self.decoder(queries, memory, memory_key_padding_mask=padding)
        return self.action_out(decoded)

    def actions(self, normalised: torch.Tensor) -> torch.Tensor:
        return normalised * self.actions_std + self.actions_mean
