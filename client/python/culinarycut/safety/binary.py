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


def engine_qualities(cc_cut: Path) -> list[str]:
    """The quality presets of cc-cut's engine (`cc-cut --presets`), so no copy of their names is kept here."""
    done = subprocess.run([str(cc_cut), "--presets"], capture_output=True, text=True)
    if done.returncode != 0:
        raise ValueError(f"--cc-cut: {cc_cut} --presets failed ({done.stderr.strip()[:200]}); an older build? "
                         "rebuild it (scripts/build.sh)")
    return [preset["name"] for preset in json.loads(done.stdout)["quality_presets"]]
