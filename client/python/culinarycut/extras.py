"""Which optional extra of the culinarycut package (pyproject's optional-dependencies) brings a module that
a command imported and did not find, so the command can say what to install instead of a traceback."""
from __future__ import annotations

import re
from importlib.metadata import PackageNotFoundError, requires

# Import names that differ from the name of the distribution that provides them.
DISTRIBUTION_OF_MODULE = {"PIL": "Pillow", "cv2": "opencv-python"}
# The extras each command is built on, the one named after it first (`data` also runs bench's Dask and progress).
COMMAND_EXTRAS = {"bench": ("bench",), "data": ("datasets", "bench"), "safety": ("safety",)}
_REQUIREMENT = re.compile(r"^\s*([A-Za-z0-9][A-Za-z0-9._-]*).*extra\s*==\s*['\"]([^'\"]+)['\"]")


def _canonical(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def extras_providing(module: str) -> list[str]:
    """The package's extras that install the top-level module `module` (by its distribution's name)."""
    wanted = _canonical(DISTRIBUTION_OF_MODULE.get(module, module))
    try:
        requirements = requires("culinarycut") or []
    except PackageNotFoundError:  # run from sources that were never installed: no metadata to read
        return []
    found = (_REQUIREMENT.match(requirement) for requirement in requirements)
    return sorted({m.group(2) for m in found if m and _canonical(m.group(1)) == wanted})


def missing_extra_message(err: ModuleNotFoundError, command: str) -> str | None:
    """`command needs MODULE: pip install 'culinarycut[EXTRA]'`, or None when no extra provides the module
    (a missing module of the package itself is a bug, not a missing extra)."""
    module = (err.name or "").split(".")[0]
    extras = extras_providing(module)
    if not extras:
        return None
    preferred = [extra for extra in COMMAND_EXTRAS.get(command, ()) if extra in extras]
    choice = f"'culinarycut[{preferred[0]}]'" if preferred else " or ".join(f"'culinarycut[{e}]'" for e in extras)
    return f"`culinarycut {command}` needs {module}, which is not installed: pip install {choice}"
