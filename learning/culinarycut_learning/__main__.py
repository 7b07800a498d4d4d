"""`python -m culinarycut_learning train|serve|info` (also the `culinarycut-learning` command).

    train --data EXPORT --out RUN [--steps N] [--device cpu|cuda|auto] ...   train, or resume RUN
    serve --checkpoint RUN --port P                                          the openpi websocket server
    info  --checkpoint RUN                                                   what a checkpoint holds
    cstm-classifier train ... / cstm-generator pairs|train ...               the CSTM (cstm/cli.py)

Exit codes: 0 done; 1 a run that cannot go on (unreadable data, a run folder of other settings, no
checkpoint); 2 bad arguments; 130 interrupted (run the same train command again to resume)."""
from __future__ import annotations

import argparse
import dataclasses
import json
import os
import sys
from pathlib import Path

# cuBLAS reads this at its first call: deterministic GEMMs on a GPU (train.set_deterministic).
os.environ.setdefault("CUBLAS_WORKSPACE_CONFIG", ":4096:8")

MODEL_OPTIONS = {  # ModelConfig field: (type, help); --image-size sets image_size
    "image_size": (int, "square image size the model sees, pixels (default 96)"),
    "encoder": (str, "image encoder: small_cnn (default) or resnet18 (torchvision, weights=None)"),
    "d_model": (int, "transformer width (default 128)"),
    "encoder_layers": (int, "transformer encoder layers (default 3)"),
    "decoder_layers": (int, "transformer decoder layers (default 2)"),
    "history": (int, "frames the model sees (default 2)"),
    "history_stride": (int, "control steps between them: the adapter's replan_steps (default 5)"),
    "chunk": (int, "actions per query (default 10)"),
}
TRAIN_OPTIONS = {  # TrainConfig field: (type, help)
    "steps": (int, "optimisation steps (default 20000)"),
    "batch_size": (int, "samples per step (default 32)"),
    "lr": (float, "peak learning rate (default 3e-4)"),
    "warmup_steps": (int, "linear warm-up steps (default 500)"),
    "seed": (int, "seed of the weights and of every batch (default 0)"),
    "threads": (int, "torch threads, part of what makes a run reproducible (default 2)"),
    "save_every": (int, "steps between checkpoints (default 500)"),
    "log_every": (int, "steps between log lines (default 50)"),
}


def _add_options(parser: argparse.ArgumentParser, options: dict) -> None:
    for name, (kind, text) in options.items():
        parser.add_argument("--" + name.replace("_", "-"), dest=name, type=kind, default=None, help=text)


def train_config(args: argparse.Namespace):
    """The defaults, or the run folder's own settings when it holds a checkpoint, with the given options over them."""
    from culinarycut_learning.config import ModelConfig, TrainConfig
    saved = Path(args.out) / "config.json"
    base = TrainConfig()
    if (Path(args.out) / "checkpoint.pt").is_file() and saved.is_file():
        data = json.loads(saved.read_text())
        base = TrainConfig.from_dict({k: v for k, v in data.items() if k not in ("data", "data_sha256")})
    model = dataclasses.replace(base.model, **{k: getattr(args, k) for k in MODEL_OPTIONS if getattr(args, k) is not None})
    styles = {} if getattr(args, "styles", None) is None else {"styles": args.styles}
    return dataclasses.replace(base, model=model, **styles,
                               **{k: getattr(args, k) for k in TRAIN_OPTIONS if getattr(args, k) is not None})


def cmd_train(args) -> int:
    from culinarycut_learning.data import DataError
    from culinarycut_learning.train import RunError, train
    try:
        config = train_config(args)
    except ValueError as err:
        print(f"culinarycut_learning train: {err}", file=sys.stderr)
        return 2
    try:
        summary = train(Path(args.data), Path(args.out), config, device=args.device, progress=not args.no_progress,
                        templates=args.templates, log=lambda text: print(text, file=sys.stderr))
    except (DataError, RunError, FileNotFoundError) as err:
        print(f"culinarycut_learning train: {err}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"\ninterrupted: run the same command again to resume {args.out} from its last checkpoint",
              file=sys.stderr)
        return 130
    print(f"{summary['checkpoint']}: {summary['steps']} steps (from {summary['resumed_from']}), loss "
          f"{summary['loss']:.4f}, {summary['episodes']} episodes / {summary['frames']} frames, "
          f"{summary['wall_s']:.1f} s")
    return 0


def cmd_serve(args) -> int:
    from culinarycut_learning.serve import make_server
    try:
        server, policy = make_server(Path(args.checkpoint), args.host, args.port, device=args.device,
                                     threads=args.threads, api_key=args.api_key)
    except (FileNotFoundError, ValueError) as err:
        print(f"culinarycut_learning serve: {err}", file=sys.stderr)
        return 1
    from culinarycut_policies.standins.serving import serve_until_stopped
    serve_until_stopped(server, lambda: f"listening on {server.url} ({policy.metadata['checkpoint']}, "
                                        f"step {policy.metadata['step']})")
    return 0


def cmd_info(args) -> int:
    from culinarycut_learning.checkpoint import load_checkpoint
    try:
        payload = load_checkpoint(Path(args.checkpoint))
    except (FileNotFoundError, ValueError) as err:
        print(f"culinarycut_learning info: {err}", file=sys.stderr)
        return 1
    parameters = sum(v.numel() for v in payload["model"].values())
    print(json.dumps({"step": payload["step"], "loss": payload["loss"], "config": payload["config"],
                      "data": payload["data"], "torch": payload["torch"], "tensors": parameters,
                      "vocabulary": len(payload["tokenizer"]["vocabulary"]),
                      "trained_words": len(payload["tokenizer"]["trained"])}, indent=2))
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m culinarycut_learning", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(dest="command", required=True)
    train = commands.add_parser("train", help="train a policy on a `culinarycut data export` folder (resumable)")
    train.add_argument("--data", required=True, help="an export folder (its robomimic/*.hdf5) or the .hdf5 file")
    train.add_argument("--out", required=True, help="the run folder: checkpoint.pt, config.json, log.jsonl; "
                                                    "one with a checkpoint is resumed")
    train.add_argument("--device", default="cpu", help="cpu (default), cuda, cuda:N or auto")
    train.add_argument("--templates", help="instruction_templates.json (default: $CULINARYCUT_ASSETS_DIR/language/, "
                                           "else the checkout's assets/language/)")
    train.add_argument("--no-progress", action="store_true", help="no progress bar")
    _add_options(train, TRAIN_OPTIONS)
    _add_options(train, MODEL_OPTIONS)
    train.add_argument("--styles", type=lambda text: tuple(s for s in text.split(",") if s), default=None,
                       help="comma list: train only on the demos of these cut styles (default: every demo)")
    serve = commands.add_parser("serve", help="serve a checkpoint over openpi's websocket protocol (LIBERO layout)")
    serve.add_argument("--checkpoint", required=True, help="a run folder (its checkpoint.pt) or a checkpoint file")
    serve.add_argument("--host", default="127.0.0.1")
    serve.add_argument("--port", type=int, default=8000, help="0: a free one (printed)")
    serve.add_argument("--device", default="cpu", help="cpu (default) or cuda")
    serve.add_argument("--threads", type=int, default=1, help="torch threads (default 1)")
    serve.add_argument("--api-key", help="require Authorization: Api-Key KEY (the adapter's api_key option)")
    info = commands.add_parser("info", help="print what a checkpoint holds")
    info.add_argument("--checkpoint", required=True)
    from culinarycut_learning.cstm.cli import register as register_cstm
    cstm = register_cstm(commands)
    args = parser.parse_args(argv)
    if args.command in cstm:
        return cstm[args.command][args.cstm_command](args)
    return {"train": cmd_train, "serve": cmd_serve, "info": cmd_info}[args.command](args)


if __name__ == "__main__":
    sys.exit(main())
