"""RDT-1B's precomputed T5-XXL language embeddings: instruction -> (L, 4096) float32.

Read from what RDT's scripts/encode_lang.py writes, one `.pt` file per task holding a dict with `name`,
`instruction` and `embeddings` ((1, L, 4096) or (L, 4096)), loaded as agilex_inference.py does
(torch.load, here with weights_only=True: nothing is unpickled), given as one file, a folder of them
or several paths separated by commas; or from an `.npz` with one array per instruction text, which
`python -m culinarycut_policies.rdt_language OUT.npz IN.pt...` writes on a machine that has torch.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

EMBEDDING_DIM = 4096  # T5-XXL's hidden size


def _as_matrix(values, where: str) -> np.ndarray:
    array = np.asarray(values, dtype=np.float32)
    if array.ndim == 3 and array.shape[0] == 1:
        array = array[0]
    if array.ndim != 2 or array.shape[1] != EMBEDDING_DIM:
        raise ValueError(f"{where}: expected embeddings (1, L, {EMBEDDING_DIM}) or (L, {EMBEDDING_DIM}), "
                         f"got {array.shape}")
    return array


def _load_torch():
    try:
        import torch
    except ImportError:
        raise ValueError("reading RDT's encode_lang.py .pt files needs torch, which is not importable here (pip "
                         "install torch, or Debian's python3-torch); or convert them where torch is: python -m "
                         "culinarycut_policies.rdt_language OUT.npz IN.pt...") from None
    return torch


def read_pt(path: Path) -> tuple[str, np.ndarray]:
    """(instruction, (L, 4096)) of one encode_lang.py file."""
    torch = _load_torch()
    try:
        saved = torch.load(path, map_location="cpu", weights_only=True)
    except Exception as err:  # torch raises many types for a bad file
        raise ValueError(f"{path}: not a torch file of RDT's encode_lang.py ({err})") from None
    if not isinstance(saved, dict) or "instruction" not in saved or "embeddings" not in saved:
        raise ValueError(f"{path}: expected encode_lang.py's dict with 'instruction' and 'embeddings', got "
                         f"{sorted(saved) if isinstance(saved, dict) else type(saved).__name__}")
    embeddings = saved["embeddings"]
    values = embeddings.float().numpy() if hasattr(embeddings, "numpy") else embeddings
    return str(saved["instruction"]), _as_matrix(values, f"{path}: embeddings")


def _read_npz(path: Path) -> dict[str, np.ndarray]:
    with np.load(path, allow_pickle=False) as archive:
        return {key: _as_matrix(archive[key], f"{path}[{key!r}]") for key in archive.files}


def load_embeddings(option: str | None) -> dict[str, np.ndarray]:
    """instruction -> (L, 4096) from option language_embeddings (see the module's docstring)."""
    if not option:
        return {}
    paths: list[Path] = []
    for part in str(option).split(","):
        path = Path(part.strip())
        paths.extend(sorted(path.glob("*.pt")) if path.is_dir() else [path])
    embeddings: dict[str, np.ndarray] = {}
    try:
        for path in paths:
            if path.suffix == ".npz":
                embeddings.update(_read_npz(path))
            elif path.suffix == ".pt":
                instruction, values = read_pt(path)
                embeddings[instruction] = values
            else:
                raise ValueError(f"{path}: expected encode_lang.py's .pt files, a folder of them, or an .npz")
    except (OSError, ValueError) as err:
        raise ValueError(f"policy rdt: option language_embeddings={option}: {err}") from None
    if not embeddings:
        raise ValueError(f"policy rdt: option language_embeddings={option} holds no embeddings")
    return embeddings


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m culinarycut_policies.rdt_language",
                                     description="encode_lang.py's .pt files -> one .npz keyed by instruction")
    parser.add_argument("out", type=Path)
    parser.add_argument("inputs", nargs="+")
    args = parser.parse_args(argv)
    try:
        embeddings = load_embeddings(",".join(args.inputs))
    except ValueError as err:
        print(f"error: {err}", file=sys.stderr)
        return 1
    np.savez(args.out, **embeddings)
    print(f"{args.out}: {len(embeddings)} instructions")
    return 0


if __name__ == "__main__":
    sys.exit(main())
