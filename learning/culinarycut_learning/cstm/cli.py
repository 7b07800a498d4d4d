"""The CSTM's commands of `python -m culinarycut_learning`:

    cstm-classifier train --data EXPORT --out RUN [--camera front] [--image-size 64] [--steps N] ...
    cstm-generator pairs --server HOST:PORT --out PAIRS --food strawberry --style saw [--state middle] [--pairs N]
    cstm-generator train --pairs PAIRS --out RUN [--chunk 10] [--steps N] ...

Both trainers resume: the same command again continues a run folder from its last checkpoint (options not
given are taken from the folder); another setting for the folder is refused, naming it. `pairs` keeps the
pair files already in its folder, so it too goes on where a killed run stopped."""
from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from pathlib import Path

OPTIM_OPTIONS = {  # Optimisation field: (type, help)
    "steps": (int, "optimisation steps (default 2000)"),
    "batch_size": (int, "samples per step (default 32)"),
    "lr": (float, "peak learning rate (default 3e-4)"),
    "warmup_steps": (int, "linear warm-up steps (default 100)"),
    "seed": (int, "seed of the weights and of every batch (default 0)"),
    "threads": (int, "torch threads, part of what makes a run reproducible (default 2)"),
    "save_every": (int, "steps between checkpoints (default 200)"),
    "log_every": (int, "steps between log lines (default 20)"),
}
CLASSIFIER_OPTIONS = {  # ClassifierModel field
    "camera": (str, "the camera C sees: the export's obs/<camera>_image (default front)"),
    "image_size": (int, "square image size C sees, pixels (default 64)"),
    "patch_size": (int, "ViT patch size, pixels (default 8)"),
    "layers": (int, "ViT encoder layers (default 4)"),
    "heads": (int, "attention heads (default 4)"),
    "hidden_dim": (int, "ViT width (default 128)"),
    "mlp_dim": (int, "ViT feed-forward width (default 256)"),
}
GENERATOR_OPTIONS = {  # GeneratorModel field
    "chunk": (int, "actions per chunk (default 10, the learned policy's)"),
    "d_model": (int, "transformer width (default 64)"),
    "layers": (int, "transformer layers (default 2)"),
    "heads": (int, "attention heads (default 4)"),
}


def _add(parser: argparse.ArgumentParser, options: dict) -> None:
    for name, (kind, text) in options.items():
        parser.add_argument("--" + name.replace("_", "-"), dest=name, type=kind, default=None, help=text)


def _given(args, options: dict) -> dict:
    return {k: getattr(args, k) for k in options if getattr(args, k) is not None}


def _config(args, cls, model_options: dict):
    """The defaults, or the run folder's own settings when it holds a checkpoint, with the given options over them."""
    saved = Path(args.out) / "config.json"
    base = cls()
    if (Path(args.out) / "checkpoint.pt").is_file() and saved.is_file():
        base = cls.from_dict({k: v for k, v in json.loads(saved.read_text()).items() if k != "data"})
    return dataclasses.replace(base, model=dataclasses.replace(base.model, **_given(args, model_options)),
                               optim=dataclasses.replace(base.optim, **_given(args, OPTIM_OPTIONS)))


def _train(args, cls, model_options: dict, trainer, data, describe) -> int:
    from culinarycut_learning.data import DataError
    from culinarycut_learning.train import RunError
    prog = f"culinarycut_learning {args.command} train"
    try:
        config = _config(args, cls, model_options)
    except (ValueError, TypeError) as err:
        print(f"{prog}: {err}", file=sys.stderr)
        return 2
    try:
        summary = trainer(data, Path(args.out), config, device=args.device, progress=not args.no_progress,
                          log=lambda text: print(text, file=sys.stderr))
    except (DataError, RunError, FileNotFoundError, ValueError) as err:
        print(f"{prog}: {err}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"\ninterrupted: run the same command again to resume {args.out} from its last checkpoint",
              file=sys.stderr)
        return 130
    print(f"{summary['checkpoint']}: {summary['steps']} steps (from {summary['resumed_from']}), loss "
          f"{summary['loss']:.4f}, {describe(summary)}, {summary['wall_s']:.1f} s")
    return 0


def _held_out(summary: dict) -> str:
    metrics = summary["held_out"]
    if metrics is None:
        return f"no held-out accuracy ({summary['held_out_demos']})"
    return (f"held-out accuracy {metrics['accuracy']:.3f} (balanced {metrics['balanced_accuracy']:.3f}) on "
            f"{metrics['frames']} frames of {metrics['demos']} demos ({metrics['contact_frames']} in contact)")


def cmd_classifier_train(args) -> int:
    from culinarycut_learning.cstm.classifier_train import train_classifier
    from culinarycut_learning.cstm.configs import ClassifierConfig
    return _train(args, ClassifierConfig, CLASSIFIER_OPTIONS, train_classifier, Path(args.data), _held_out)


def cmd_generator_train(args) -> int:
    from culinarycut_learning.cstm.configs import GeneratorConfig
    from culinarycut_learning.cstm.generator_train import train_generator
    return _train(args, GeneratorConfig, GENERATOR_OPTIONS, train_generator, Path(args.pairs),
                  lambda s: (f"{s['windows']} windows ({', '.join(s['styles'])}), held-out L1 "
                             + ("none (fewer than 10 pairs)" if s["valid_l1"] is None else f"{s['valid_l1']:.4f}")))


def cmd_generator_pairs(args) -> int:
    from culinarycut.errors import CulinaryCutError
    from culinarycut_learning.cstm.oracle_pairs import generate_pairs
    try:
        summary = generate_pairs(args.server, Path(args.out), args.food or ["strawberry"], args.style,
                                 args.state or ["middle"], args.pairs, seed=args.seed, quality=args.quality,
                                 max_steps=args.max_steps, log=lambda text: print(text, file=sys.stderr))
    except ValueError as err:
        print(f"culinarycut_learning cstm-generator pairs: {err}", file=sys.stderr)
        return 2
    except CulinaryCutError as err:   # the server refused a scene or a plan, or is not there
        print(f"culinarycut_learning cstm-generator pairs: {args.server}: {err}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"\ninterrupted: run the same command again to go on filling {args.out}", file=sys.stderr)
        return 130
    print(f"{summary['out']}: {summary['made']} pairs recorded, {summary['kept']} already there, "
          f"{summary['wall_s']:.1f} s")
    return 0


def _train_parser(commands, help_text: str, data_flag: str, data_help: str, model_options: dict):
    train = commands.add_parser("train", help=help_text)
    train.add_argument(data_flag, required=True, help=data_help)
    train.add_argument("--out", required=True, help="the run folder: checkpoint.pt, config.json, log.jsonl; one "
                                                    "with a checkpoint is resumed")
    train.add_argument("--device", default="cpu", help="cpu (default), cuda, cuda:N or auto")
    train.add_argument("--no-progress", action="store_true", help="no progress bar")
    _add(train, OPTIM_OPTIONS)
    _add(train, model_options)
    return train


def register(commands) -> dict:
    """Adds cstm-classifier and cstm-generator to the subcommands; returns {command: handler(args)}."""
    classifier = commands.add_parser("cstm-classifier", help="the CSTM's contact classifier C (a ViT)")
    classifier_commands = classifier.add_subparsers(dest="cstm_command", required=True)
    _train_parser(classifier_commands, "train C on a robomimic export's frames and obs/knife_contact", "--data",
                  "an export folder (its robomimic/*.hdf5) or the .hdf5 file", CLASSIFIER_OPTIONS)
    generator = commands.add_parser("cstm-generator", help="the CSTM's style generator f")
    generator_commands = generator.add_subparsers(dest="cstm_command", required=True)
    pairs = generator_commands.add_parser("pairs", help="record (normal, style) oracle cuts of the same scenes "
                                                        "through a server (resumable)")
    pairs.add_argument("--server", default="127.0.0.1:50051", help="a culinarycut-server, HOST:PORT")
    pairs.add_argument("--out", required=True, help="the pairs folder (one .npz per pair)")
    pairs.add_argument("--food", action="append", help="food (repeatable; default strawberry)")
    pairs.add_argument("--style", required=True, choices=("bias", "guillotine", "saw"))
    pairs.add_argument("--state", action="append", help="middle (default), ratio-R or split-N (repeatable)")
    pairs.add_argument("--pairs", type=int, default=10, help="pairs per food and state (default 10)")
    pairs.add_argument("--seed", type=int, default=0, help="seed of the scenes (default 0)")
    pairs.add_argument("--quality", default="draft", help="the server's quality preset (default draft)")
    pairs.add_argument("--max-steps", type=int, default=600, help="control steps per cut at most (default 600)")
    _train_parser(generator_commands, "train f on a pairs folder", "--pairs", "the pairs folder", GENERATOR_OPTIONS)
    return {"cstm-classifier": {"train": cmd_classifier_train},
            "cstm-generator": {"pairs": cmd_generator_pairs, "train": cmd_generator_train}}
