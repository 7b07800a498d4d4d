"""Serve a real Octo model with the openpi websocket protocol, for the octo adapter. Loads it with the
upstream package (github.com/octo-models/octo, `pip install -e .` with its JAX requirements):
OctoModel.load_pretrained, create_tasks(texts=[prompt]) and sample_actions(observation, tasks,
rng=...) with a fresh key per call derived from --seed. Actions go out normalised (no statistics
passed to sample_actions); the adapter un-normalises them with the dataset statistics it is given,
which --write-statistics can export from the checkpoint. Not run in CI.

    python policies/servers/serve_octo.py --checkpoint hf://rail-berkeley/octo-base-1.5 --port 8000 \
        --write-statistics octo_statistics.json
    culinarycut bench run smoke --policy octo --policy-url ws://GPU_HOST:8000 \
        --policy-option statistics=octo_statistics.json --policy-option unnorm_key=bridge_dataset
"""
from __future__ import annotations

import argparse
import json

import numpy as np

from culinarycut_policies.standins.websocket_server import WebsocketPolicyServer


class OctoServerModel:
    def __init__(self, checkpoint: str, seed: int):
        import jax
        from octo.model.octo_model import OctoModel
        self.jax = jax
        self.model = OctoModel.load_pretrained(checkpoint)
        self.key = jax.random.PRNGKey(seed)
        self.calls = 0
        self.tasks: dict[str, dict] = {}

    def metadata(self) -> dict:
        example = self.model.example_batch["observation"]
        return {"model_family": "octo", "window": int(example["timestep_pad_mask"].shape[1]),
                "action_horizon": int(self.model.config["model"]["heads"]["action"]["kwargs"]["action_horizon"]),
                "observation_keys": sorted(k for k in example if k.startswith("image_")), "normalized_actions": True}

    def __call__(self, request: dict) -> dict:
        prompt = request["prompt"]
        if prompt not in self.tasks:
            self.tasks[prompt] = self.model.create_tasks(texts=[prompt])
        self.calls += 1
        rng = self.jax.random.fold_in(self.key, self.calls)  # a fresh key per call, reproducible from --seed
        actions = self.model.sample_actions(request["observation"], self.tasks[prompt], rng=rng)
        return {"actions": np.asarray(actions, dtype=np.float32)}


def write_statistics(model, path: str) -> None:
    """The checkpoint's dataset_statistics in the layout the adapter reads ({key: {action, proprio, ...}})."""
    statistics = model.dataset_statistics
    if "action" in statistics:  # a single-dataset (fine-tuned) model: name it
        statistics = {"octo_finetuned": statistics}
    plain = json.loads(json.dumps(statistics, default=lambda a: np.asarray(a).tolist()))
    with open(path, "w") as file:
        json.dump(plain, file, indent=1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--checkpoint", default="hf://rail-berkeley/octo-base-1.5")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--write-statistics", metavar="PATH", help="export the model's dataset statistics and go on")
    parser.add_argument("--api-key", help="require Authorization: Api-Key KEY")
    parser.add_argument("--host", default="0.0.0.0")
    parser.add_argument("--port", type=int, default=8000)
    args = parser.parse_args()
    model = OctoServerModel(args.checkpoint, args.seed)
    if args.write_statistics:
        write_statistics(model.model, args.write_statistics)
    server = WebsocketPolicyServer(model, model.metadata(), args.host, args.port, api_key=args.api_key)
    print(f"Octo {args.checkpoint} on ws://{args.host}:{args.port}", flush=True)
    server.serve_forever()


if __name__ == "__main__":
    main()
