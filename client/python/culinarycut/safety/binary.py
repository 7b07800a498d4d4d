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
