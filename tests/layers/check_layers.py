#!/usr/bin/env python3
"""Fails when an #include points up a layer (see docs/architecture.md).

Layers, lowest first: sim/core <- sim/robot, sim/mpm, sim/task, sim/render, sim/safety <- sim/world
<- sim/policy <- server/wire <- server. tools build on sim and server/wire (the wire conversions),
never on the services. sim/world may include only the GL-free part of sim/render, so a user of the
world links no EGL; the C++ client includes nothing of the engine or the server.

Usage: check_layers.py REPO_ROOT          check the repository, print every violation, exit 1 if any
       check_layers.py --self-test        check the checker on a fabricated tree
       check_layers.py --links FILE       also check the link list of culinarycut_sim written by CMake
"""
from __future__ import annotations

import argparse
import re
import sys
import tempfile
from pathlib import Path

INCLUDE = re.compile(r'^\s*#\s*include\s+"((?:sim|server|client|tools)/[^"]+)"', re.MULTILINE)

# Which folders a folder may include from (its own folder is always allowed).
ALLOWED = {
    "sim/core": set(),
    "sim/robot": {"sim/core"},
    "sim/mpm": {"sim/core"},
    "sim/task": {"sim/core"},
    "sim/render": {"sim/core"},
    "sim/safety": {"sim/core"},  # the force model, safe speed and guards are logic: the world applies them
    "sim/world": {"sim/core", "sim/robot", "sim/mpm", "sim/task", "sim/render", "sim/safety"},
    "sim/policy": {"sim/core", "sim/robot", "sim/mpm", "sim/task", "sim/render", "sim/safety", "sim/world"},
    "server/wire": {"sim/core", "sim/robot", "sim/mpm", "sim/task", "sim/render", "sim/safety", "sim/world",
                    "sim/policy"},
    "server": {"sim/core", "sim/robot", "sim/mpm", "sim/task", "sim/render", "sim/safety", "sim/world", "sim/policy",
               "server/wire"},
    "tools": {"sim/core", "sim/robot", "sim/mpm", "sim/task", "sim/render", "sim/safety", "sim/world", "sim/policy",
              "server/wire"},
    "client/cpp": set(),
}
# The GL-free headers of sim/render: all that sim/world (and what builds on it) may see of rendering.
GL_FREE_RENDER = {"sim/render/camera.h", "sim/render/camera_images.h", "sim/render/camera_renderer.h",
                  "sim/render/render_scene.h", "sim/render/particle_view.h", "sim/render/render_error.h"}
GL_FREE_USERS = ("sim/world", "sim/safety", "sim/policy")
# Libraries culinarycut_sim must never pull in.
GL_LIBRARIES = ("culinarycut_render;", "culinarycut_render>", "OpenGL", "EGL", "assimp", "opencv")


def layer_of(path: str) -> str | None:
    for layer in sorted(ALLOWED, key=len, reverse=True):
        if path == layer or path.startswith(layer + "/"):
            return layer
    return None


def violations(root: Path) -> list[str]:
    found = []
    for source in sorted(root.rglob("*")):
        if source.suffix not in {".h", ".cc", ".hpp", ".cpp"} or "build" in source.relative_to(root).parts[:1]:
            continue
        relative = source.relative_to(root).as_posix()
        layer = layer_of(relative)
        if layer is None:
            continue  # tests, bench and examples may use anything
        text = source.read_text(encoding="utf-8", errors="replace")
        for match in INCLUDE.finditer(text):
            target = match.group(1)
            target_layer = layer_of(target)
            line = text.count("\n", 0, match.start()) + 1
            if target_layer is None or target_layer == layer:
                continue
            if target_layer not in ALLOWED[layer]:
                found.append(f"{relative}:{line}: includes {target}, but {layer} may include only "
                             f"{', '.join(sorted(ALLOWED[layer])) or 'itself'}")
            elif target_layer == "sim/render" and layer.startswith(GL_FREE_USERS) and target not in GL_FREE_RENDER:
                found.append(f"{relative}:{line}: includes {target}; {layer} may see rendering only through the "
                             f"GL-free headers ({', '.join(sorted(GL_FREE_RENDER))})")
    return found


def link_violations(links_file: Path) -> list[str]:
    links = links_file.read_text()
    return [f"culinarycut_sim links {name.rstrip(';>')} ({links.strip()}): the world must not need GL"
            for name in GL_LIBRARIES if name.lower() in (links + ";").lower()]


def self_test() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        files = {
            "sim/render/camera.h": '#include "sim/core/pose.h"\n',
            "sim/render/bad_upward.h": '#include "sim/world/model.h"\n',          # render -> world: up
            "sim/mpm/bad_robot.h": '#include "sim/robot/kinematics.h"\n',         # mpm -> robot: sideways
            "sim/world/bad_gl.cc": '#include "sim/render/renderer.h"\n',          # world -> EGL renderer
            "sim/world/fine.cc": '#include "sim/render/camera.h"\n#include "sim/mpm/solver.h"\n',
            "client/cpp/src/bad.cc": '#include "server/status.h"\n',              # client -> server
            "server/fine.cc": '#include "sim/world/step.h"\n#include "server/wire/scene.h"\n',
            "server/wire/bad_service.cc": '#include "server/status.h"\n',        # wire -> services: up
            "tools/x/fine.cc": '#include "server/wire/scene.h"\n#include "sim/world/model.h"\n',
            "tools/x/bad_service.cc": '#include "server/session_manager.h"\n',  # tools -> services
        }
        for name, text in files.items():
            (root / name).parent.mkdir(parents=True, exist_ok=True)
            (root / name).write_text(text)
        found = violations(root)
        expected = ["sim/render/bad_upward.h", "sim/mpm/bad_robot.h", "sim/world/bad_gl.cc", "client/cpp/src/bad.cc",
                    "server/wire/bad_service.cc", "tools/x/bad_service.cc"]
        missing = [name for name in expected if not any(v.startswith(name) for v in found)]
        extra = [v for v in found if not any(v.startswith(name) for name in expected)]
        links = root / "links.txt"
        links.write_text("culinarycut_core;culinarycut_render;urdfdom")
        link_found = link_violations(links)
        links.write_text("culinarycut_core;culinarycut_render_scene;urdfdom")
        link_clean = link_violations(links)
    if missing or extra or not link_found or link_clean:
        print(f"self-test failed: missed {missing}, wrongly flagged {extra}, link check {link_found} / {link_clean}")
        return 1
    print(f"self-test passed: {len(found)} fabricated violations caught, clean files and links pass")
    return 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("root", nargs="?", type=Path)
    parser.add_argument("--self-test", action="store_true")
    parser.add_argument("--links", type=Path)
    args = parser.parse_args()
    if args.self_test:
        return self_test()
    if args.root is None:
        parser.error("give the repository root, or --self-test")
    found = violations(args.root)
    if args.links:
        found += link_violations(args.links)
    for violation in found:
        print(violation)
    print(f"{len(found)} layer violations")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
