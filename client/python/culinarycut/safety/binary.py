"""Where cc-cut is: $CULINARYCUT_CC_CUT, else this checkout's build tree, else PATH; and the presets it knows."""
from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

from culinarycut.launch import CHECKOUT_ROOT

CC_CUT_NAME = "cc-cut"


def cc_cut_binary() -> Path:
    env = os.environ.get("CULINARYCUT_CC_CUT")
    if env:
        return Path(env)
    if (CHECKOUT_ROOT / "tools" / "cc_cut").is_dir():
        return CHECKOUT_ROOT / "build" / "tools" / "cc_cut" / CC_CUT_NAME
    return Path(shutil.which(CC_CUT_NAME) or CC_CUT_NAME)


MPM_LIBRARY = "libculinarycut_mpm.so"


def _build_root(cc_cut: Path) -> Path | None:
    """The build tree whose lib/ holds cc-cut's MPM library; None for a build that links it statically."""
    return next((p for p in Path(cc_cut).resolve().parents if (p / "lib" / MPM_LIBRARY).is_file()), None)


def engine_files(cc_cut: Path) -> list[Path]:
    """What the engine cc-cut runs is made of: the binary and every build of the MPM library beside it."""
    build = _build_root(cc_cut)
    libraries = sorted(p for p in (build / "lib").rglob(MPM_LIBRARY)) if build else []
    return [Path(cc_cut), *libraries]


def snapshot_cc_cut(cc_cut: Path, folder: Path) -> Path:
    """A copy of cc-cut in `folder` that a rebuild cannot change: with the build's MPM library (lib/, one build per
    x86-64 level) where the binary finds it, at the same place relative to the binary as in the build tree."""
    cc_cut = Path(cc_cut).resolve()
    build = _build_root(cc_cut)
    if build is None:  # one static build: the binary is all of it
        return Path(shutil.copy2(cc_cut, folder / CC_CUT_NAME))
    copy = folder / cc_cut.relative_to(build)
    copy.parent.mkdir(parents=True, exist_ok=True)
    shutil.copytree(build / "lib", folder / "lib")
    return Path(shutil.copy2(cc_cut, copy))


def cc_cut_presets(cc_cut: Path) -> dict:
    """The engine's quality presets and MPM bounds as `cc-cut --presets` prints them (GetServerInfo's fields),
    so no copy of them is kept here. ValueError naming --cc-cut when the binary cannot say."""
    try:
        done = subprocess.run([str(cc_cut), "--presets"], capture_output=True, text=True)
    except OSError as err:
        raise ValueError(f"--cc-cut: cannot run {cc_cut} ({err}); build it (scripts/build.sh)") from None
    if done.returncode != 0:
        raise ValueError(f"--cc-cut: {cc_cut} --presets failed ({done.stderr.strip()[:200]}); an older build? "
                         "rebuild it (scripts/build.sh)")
    return json.loads(done.stdout)


def engine_qualities(cc_cut: Path) -> list[str]:
    """The names of the quality presets of cc-cut's engine."""
    return [preset["name"] for preset in cc_cut_presets(cc_cut)["quality_presets"]]
