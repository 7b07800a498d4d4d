"""Where cc-cut is: $CULINARYCUT_CC_CUT, else this checkout's build tree, else PATH."""
from __future__ import annotations

import os
import shutil
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
