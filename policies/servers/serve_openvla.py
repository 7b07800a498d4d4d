"""Serve a real OpenVLA checkpoint with OpenVLA's REST protocol (POST /act, json-numpy), as upstream's
vla-scripts/deploy.py does, without FastAPI: the model is loaded through Hugging Face's AutoClasses, the
prompt is openvla_prompt(instruction), and actions are un-normalised by the model's predict_action with
the request's unnorm_key. Needs a GPU machine with torch, transformers (and flash-attn for the default
attention); not run in CI. Next to the simulator:

    python policies/servers/serve_openvla.py --checkpoint openvla/openvla-7b --port 8000 \
        --statistics runs/dataset/dataset_statistics.json
    culinarycut bench run smoke --policy openvla --policy-url http://GPU_HOST:8000 \
        --policy-option statistics=runs/dataset/dataset_statistics.json --policy-option unnorm_key=KEY

Upstream's own deploy.py speaks the same protocol and works with the openvla adapter unchanged.
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from culinarycut_policies.openvla import openvla_prompt
from culinarycut_policies.standins.rest_server import JsonNumpyRestServer


class OpenVLAModel:
    def __init__(self, checkpoint: str, statistics: str | None, attention: str):
        import torch
        from transformers import AutoModelForVision2Seq, AutoProcessor
        self.torch = torch
        self.device = torch.device("cuda:0") if torch.cuda.is_available() else torch.device("cpu")
        self.processor = AutoProcessor.from_pretrained(checkpoint, trust_remote_code=True)
        self.vla = AutoModelForVision2Seq.from_pretrained(checkpoint, attn_implementation=attention,
                                                          torch_dtype=torch.bfloat16, low_cpu_mem_usage=True,
                                                          trust_remote_code=True).to(self.device)
        self.v01 = "v01" in checkpoint
        # deploy.py: a fine-tuned run directory brings its dataset_statistics.json; --statistics overrides.
        local = Path(checkpoint) / "dataset_statistics.json"
        if statistics or local.is_file():
            self.vla.norm_stats = json.loads(Path(statistics or local).read_text())

    def __call__(self, payload: dict) -> np.ndarray:
        from PIL import Image
        prompt = openvla_prompt(payload["instruction"], v01=self.v01)
        image = Image.fromarray(payload["image"]).convert("RGB")
        inputs = self.processor(prompt, image).to(self.device, dtype=self.torch.bfloat16)
        return self.vla.predict_action(**inputs, unnorm_key=payload.get("unnorm_key"), do_sample=False)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--checkpoint", default="openvla/openvla-7b", help="HF Hub id or local run directory")
    parser.add_argument("--statistics", help="dataset_statistics.json to un-normalise with (default: the model's)")
    parser.add_argument("--attention", default="flash_attention_2", help="attn_implementation (sdpa, eager, ...)")
    parser.add_argument("--host", default="0.0.0.0")
    parser.add_argument("--port", type=int, default=8000)
    args = parser.parse_args()
    server = JsonNumpyRestServer(OpenVLAModel(args.checkpoint, args.statistics, args.attention), args.host, args.port)
    print(f"OpenVLA {args.checkpoint} on {server.url}/act", flush=True)
    server.serve_forever()


if __name__ == "__main__":
    main()
