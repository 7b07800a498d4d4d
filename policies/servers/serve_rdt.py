"""Serve a real RDT-1B with the openpi websocket protocol, for the rdt adapter. Run from a clone of
github.com/thu-ml/RoboticsDiffusionTransformer (its requirements installed) so `models` and `configs`
import. The body of scripts/agilex_model.py's step() without the robot-specific formatting: the adapter
sends the 128-D unified state and its mask already built; here the six images (None -> the encoder's
mean colour) go through SigLIP, and RDTRunner.predict_action samples the (1, 64, 128) chunk. Language
comes as precomputed T5-XXL embeddings (scripts/encode_lang.py), or as text when --t5 is given. Not run
in CI.

    cd RoboticsDiffusionTransformer && python /path/to/policies/servers/serve_rdt.py \
        --config configs/base.yaml --checkpoint robotics-diffusion-transformer/rdt-1b --port 8000
    culinarycut bench run smoke --policy rdt --policy-url ws://GPU_HOST:8000 \
        --policy-option language_embeddings=instructions.npz
"""
from __future__ import annotations

import argparse

import numpy as np

from culinarycut_policies.standins.websocket_server import WebsocketPolicyServer

VISION_ENCODER = "google/siglip-so400m-patch14-384"


class RDTServerModel:
    def __init__(self, config_path: str, checkpoint: str, t5: str | None):
        import torch
        import yaml
        from models.multimodal_encoder.siglip_encoder import SiglipVisionTower
        from models.rdt_runner import RDTRunner
        self.torch, self.device, self.dtype = torch, "cuda", torch.bfloat16
        with open(config_path) as file:
            self.config = yaml.safe_load(file)
        self.vision = SiglipVisionTower(vision_tower=VISION_ENCODER, args=None)
        self.vision.eval()
        self.vision.to(self.device, dtype=self.dtype)
        self.policy = RDTRunner.from_pretrained(checkpoint)
        self.policy.eval()
        self.policy.to(self.device, dtype=self.dtype)
        self.t5 = None
        if t5:
            from models.multimodal_encoder.t5_encoder import T5Embedder
            self.t5 = T5Embedder(from_pretrained=t5, model_max_length=self.config["dataset"]["tokenizer_max_length"],
                                 device=self.device)

    def metadata(self) -> dict:
        return {"model_family": "rdt", "action_horizon": int(self.config["common"]["action_chunk_size"]),
                "state_dim": int(self.config["model"]["state_token_dim"]), "image_size": 384,
                "language": "text_embeds or instruction" if self.t5 else "text_embeds"}

    def _language(self, request: dict):
        if "text_embeds" in request:
            return self.torch.as_tensor(np.asarray(request["text_embeds"])).to(self.device, dtype=self.dtype)
        if self.t5 is None:
            raise ValueError("send text_embeds (start the server with --t5 to send the instruction as text)")
        tokens = self.t5.tokenizer(request["instruction"], return_tensors="pt", padding="longest",
                                   truncation=True)["input_ids"].to(self.device)
        return self.t5.model(tokens.view(1, -1)).last_hidden_state.detach().to(dtype=self.dtype)

    def __call__(self, request: dict) -> dict:
        from PIL import Image
        torch, processor = self.torch, self.vision.image_processor
        background = np.array([int(x * 255) for x in processor.image_mean], dtype=np.uint8).reshape(1, 1, 3)
        blank = np.ones((processor.size["height"], processor.size["width"], 3), dtype=np.uint8) * background
        with torch.no_grad():
            pixels = [processor.preprocess(Image.fromarray(blank if image is None else np.asarray(image)),
                                           return_tensors="pt")["pixel_values"][0] for image in request["images"]]
            image_embeds = self.vision(torch.stack(pixels).to(self.device, dtype=self.dtype)).detach()
            image_embeds = image_embeds.reshape(-1, self.vision.hidden_size).unsqueeze(0)
            state = torch.as_tensor(np.asarray(request["state"])).to(self.device, dtype=self.dtype)
            mask = torch.as_tensor(np.asarray(request["state_elem_mask"])).to(self.device, dtype=self.dtype)
            language = self._language(request)
            trajectory = self.policy.predict_action(
                lang_tokens=language, lang_attn_mask=torch.ones(language.shape[:2], dtype=torch.bool, device=self.device),
                img_tokens=image_embeds, state_tokens=state, action_mask=mask.unsqueeze(1),
                ctrl_freqs=torch.tensor([float(request["ctrl_freq"])], device=self.device))
        return {"actions": trajectory.to(torch.float32).cpu().numpy()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--config", default="configs/base.yaml")
    parser.add_argument("--checkpoint", default="robotics-diffusion-transformer/rdt-1b")
    parser.add_argument("--t5", help="T5-XXL path (google/t5-v1_1-xxl) to accept instructions as text")
    parser.add_argument("--api-key", help="require Authorization: Api-Key KEY")
    parser.add_argument("--host", default="0.0.0.0")
    parser.add_argument("--port", type=int, default=8000)
    args = parser.parse_args()
    model = RDTServerModel(args.config, args.checkpoint, args.t5)
    server = WebsocketPolicyServer(model, model.metadata(), args.host, args.port, api_key=args.api_key)
    print(f"RDT {args.checkpoint} on ws://{args.host}:{args.port}", flush=True)
    server.serve_forever()


if __name__ == "__main__":
    main()
