"""Serve a real OpenVLA-OFT checkpoint with its REST protocol (POST /act with full_image, wrist_image,
state, instruction; the answer is the action chunk). Loads the model with openvla-oft's own
experiments/robot/openvla_utils.py (clone github.com/moojink/openvla-oft and `pip install -e .` it),
exactly as its vla-scripts/deploy.py does; upstream's deploy.py itself also works with the adapter.
Not run in CI.

    python policies/servers/serve_openvla_oft.py --checkpoint PATH --unnorm-key KEY --port 8777
    culinarycut bench run smoke --policy openvla-oft --policy-url http://GPU_HOST:8777 \
        --policy-option statistics=PATH/dataset_statistics.json --policy-option unnorm_key=KEY
"""
from __future__ import annotations

import argparse
from types import SimpleNamespace

from culinarycut_policies.standins.rest_server import JsonNumpyRestServer


class OpenVLAOFTModel:
    def __init__(self, cfg: SimpleNamespace):
        from experiments.robot import openvla_utils
        from prismatic.vla.constants import PROPRIO_DIM
        self.utils, self.cfg = openvla_utils, cfg
        self.vla = openvla_utils.get_vla(cfg)
        self.proprio_projector = (openvla_utils.get_proprio_projector(cfg, self.vla.llm_dim, PROPRIO_DIM)
                                  if cfg.use_proprio else None)
        self.action_head = (openvla_utils.get_action_head(cfg, self.vla.llm_dim)
                            if cfg.use_l1_regression or cfg.use_diffusion else None)
        if cfg.unnorm_key not in self.vla.norm_stats:
            raise SystemExit(f"--unnorm-key {cfg.unnorm_key!r} is not in the model's norm_stats "
                             f"({', '.join(self.vla.norm_stats)})")
        self.processor = openvla_utils.get_processor(cfg)

    def __call__(self, payload: dict) -> list:
        return self.utils.get_vla_action(self.cfg, self.vla, self.processor, payload, payload["instruction"],
                                         action_head=self.action_head, proprio_projector=self.proprio_projector,
                                         use_film=self.cfg.use_film)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--checkpoint", required=True)
    parser.add_argument("--unnorm-key", required=True)
    parser.add_argument("--images", type=int, default=2, help="num_images_in_input: 1 (front) or 2 (+ wrist)")
    parser.add_argument("--no-center-crop", action="store_true", help="for a model trained without crop augmentation")
    parser.add_argument("--diffusion", action="store_true", help="diffusion action head instead of L1 regression")
    parser.add_argument("--film", action="store_true")
    parser.add_argument("--lora-rank", type=int, default=32)
    parser.add_argument("--host", default="0.0.0.0")
    parser.add_argument("--port", type=int, default=8777)
    args = parser.parse_args()
    # The fields of openvla-oft's DeployConfig that its openvla_utils read.
    cfg = SimpleNamespace(model_family="openvla", pretrained_checkpoint=args.checkpoint,
                          use_l1_regression=not args.diffusion, use_diffusion=args.diffusion,
                          num_diffusion_steps_train=50, num_diffusion_steps_inference=50, use_film=args.film,
                          num_images_in_input=args.images, use_proprio=True, center_crop=not args.no_center_crop,
                          lora_rank=args.lora_rank, unnorm_key=args.unnorm_key, use_relative_actions=False,
                          load_in_8bit=False, load_in_4bit=False, seed=7)
    server = JsonNumpyRestServer(OpenVLAOFTModel(cfg), args.host, args.port)
    print(f"OpenVLA-OFT {args.checkpoint} on {server.url}/act", flush=True)
    server.serve_forever()


if __name__ == "__main__":
    main()
