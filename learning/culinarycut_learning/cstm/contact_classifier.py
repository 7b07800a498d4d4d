"""C(I_t): the CSTM's knife-food contact classifier, a ViT over one camera image (the CulinaryCut paper's CSTM
uses a ViT-based binary classifier). torchvision's VisionTransformer built from scratch (no weights: nothing
is downloaded) at the small size of configs.ClassifierModel (64 px, 8 px patches, 4 layers, width 128: about
0.55 M parameters), one logit: contact when sigmoid(logit) > the threshold.

Frames are prepared exactly as the learned policy's are (features.model_image: the openpi adapter's resize
with pad to 224, then a bilinear resize to image_size), in training and in the policy wrapper alike, so a
camera rendered at any size gives C the same picture."""
from __future__ import annotations

import numpy as np
import torch
from torch import nn
from torchvision.models.vision_transformer import VisionTransformer

from culinarycut_learning.cstm.configs import ClassifierModel
from culinarycut_learning.features import model_image
from culinarycut_learning.model import IMAGE_MEAN, IMAGE_STD


class ContactClassifier(nn.Module):
    def __init__(self, config: ClassifierModel):
        super().__init__()
        self.config = config
        self.vit = VisionTransformer(image_size=config.image_size, patch_size=config.patch_size,
                                     num_layers=config.layers, num_heads=config.heads, hidden_dim=config.hidden_dim,
                                     mlp_dim=config.mlp_dim, dropout=config.dropout, attention_dropout=config.dropout,
                                     num_classes=1)

    def forward(self, images: torch.Tensor) -> torch.Tensor:
        """images (B, S, S, 3) uint8, S = image_size -> contact logits (B,)."""
        pixels = images.permute(0, 3, 1, 2).float()
        pixels = (pixels / 255.0 - IMAGE_MEAN) / IMAGE_STD
        return self.vit(pixels)[:, 0]

    @torch.no_grad()
    def contact_probability(self, frame: np.ndarray) -> float:
        """One camera frame (H x W x 3 uint8, any size) -> P(knife touches food)."""
        image = torch.from_numpy(np.array(model_image(frame, self.config.image_size)))[None]   # a writable copy
        return float(torch.sigmoid(self(image))[0])
