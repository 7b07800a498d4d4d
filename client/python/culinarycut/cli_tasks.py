"""Task commands of the CLI: parse, instructions, oracle (all run their logic on the server)."""
from __future__ import annotations

import argparse
import json
import os

import numpy as np

from culinarycut.client import Client
from culinarycut.tasks import SPLITS

# The default demo object: a cucumber-sized box lying across the board (along y), bottom on the
# board top (z = 0.02 m). World frame: robot base at the origin looking along +x, left = +y.
DEFAULT_OBJECT = {"name": "cucumber_0", "food": "cucumber", "position": [0.5, 0.02, 0.04],
                  "quaternion": [np.cos(np.pi / 4), 0.0, 0.0, np.sin(np.pi / 4)],
                  "extent_m": [0.20, 0.04, 0.04]}


def cmd_parse(args) -> int:
    with Client(args.address, timeout_s=args.timeout) as client:
        parsed = client.tasks.parse_instruction(args.instruction)
    if args.json:
        print(json.dumps(parsed, indent=2))
    else:
        print(f"{parsed['description']}; cuts at {', '.join(f'{f:.3f}' for f in parsed['target_fractions'])} "
              "of the length from the left end")
    return 0


def _spec_from_args(args) -> dict:
    spec = {"style": args.style, "state": args.state, "target_object": args.object, "reference": args.side}
    if args.state == "ratio":
        spec["ratio"] = args.ratio
    if args.state == "split":
        spec["split_pieces"] = args.pieces
    return spec


def cmd_instructions(args) -> int:
    spec = _spec_from_args(args)
    with Client(args.address, timeout_s=args.timeout) as client:
        instructions = client.tasks.generate_instructions(spec, seed=args.seed, count=args.count, split=args.split)
        for line in instructions:
            print(line)
        if args.paraphrase_endpoint:
            from culinarycut.paraphrase import paraphrase
            kept, rejected = paraphrase(client.tasks, instructions, args.paraphrase_endpoint, args.paraphrase_model,
                                        api_key=os.environ.get("OPENAI_API_KEY"))
            for line in kept:
                print(line)
            print(f"# paraphrases: kept {len(kept)}, rejected {len(rejected)} that changed the meaning",
                  flush=True)
    return 0


def cmd_oracle(args) -> int:
    """Runs the scripted oracle on a robot-only session and reports how well the knife followed the plan."""
    from culinarycut.policies import ScriptedOracle
    with Client(args.address, timeout_s=args.timeout) as client:
        sid = client.create_session(None).session_id
        try:
            client.reset(sid, seed=args.seed)
            oracle = ScriptedOracle(client, sid)
            plan = oracle.reset(args.instruction, objects=[DEFAULT_OBJECT], control_mode=args.control_mode,
                                seed=args.seed)
            positions = ", ".join(f"{cut['fraction_from_left']:.3f}" for cut in plan["cuts"])
            print(f"plan: {plan['spec']['style']} cut of {plan['target_name']}, {len(plan['cuts'])} cut(s) at "
                  f"{positions} from the left, {plan['duration_s']:.2f} s", flush=True)
            planned, actual, phase, steps = [], [], "", 0
            while True:
                mode, values = oracle.act()
                if oracle.finished:
                    break
                response = client.step(sid, mode, values)
                steps += 1
                actual.append(np.asarray(response.observation.tcp_pose))
                if oracle.phase != phase:
                    phase = oracle.phase
                    tcp = actual[-1][:3] * 1e3
                    print(f"  t={response.stamp.sim_time:6.2f} s  {phase:<9} TCP [{tcp[0]:6.1f}, {tcp[1]:6.1f}, "
                          f"{tcp[2]:6.1f}] mm", flush=True)
            lowest = min(a[2] for a in actual) if actual else float("nan")
            bottom = DEFAULT_OBJECT["position"][2] - DEFAULT_OBJECT["extent_m"][2] / 2
            print(f"done: {steps} steps, lowest TCP z {lowest * 1e3:.1f} mm (object bottom {bottom * 1e3:.1f} mm)")
        finally:
            client.close_session(sid)
    return 0


def register(sub, common: argparse.ArgumentParser) -> None:
    parse = sub.add_parser("parse", parents=[common], help="instruction text -> cut spec")
    parse.add_argument("instruction")
    parse.add_argument("--json", action="store_true")
    parse.set_defaults(func=cmd_parse)

    gen = sub.add_parser("instructions", parents=[common], help="generate instructions for a cut spec")
    gen.add_argument("--object", default="cucumber", help="food (default %(default)s)")
    gen.add_argument("--style", default="normal", choices=["normal", "bias", "guillotine", "saw"])
    gen.add_argument("--state", default="middle", choices=["middle", "ratio", "split"])
    gen.add_argument("--ratio", type=float, default=0.3, help="ratio cuts: fraction in [0.1, 0.9]")
    gen.add_argument("--side", default="none", choices=["none", "left", "right", "top", "along_length"],
                     help="directional reference (ratio cuts: left or right; default %(default)s)")
    gen.add_argument("--pieces", type=int, default=3, help="split cuts: 3, 4 or 5")
    gen.add_argument("--count", type=int, default=5)
    gen.add_argument("--seed", type=int, default=0)
    gen.add_argument("--split", default="train", choices=SPLITS, help="template set (default %(default)s)")
    gen.add_argument("--paraphrase-endpoint", default="",
                     help="OpenAI-compatible base URL (e.g. http://localhost:8000/v1); off by default")
    gen.add_argument("--paraphrase-model", default="gpt-4o-mini")
    gen.set_defaults(func=cmd_instructions)

    oracle = sub.add_parser("oracle", parents=[common],
                            help="run the scripted oracle on a robot-only session (a cucumber-sized box)")
    oracle.add_argument("instruction", nargs="?", default="cut the cucumber at 0.3 ratio from the left")
    oracle.add_argument("--control-mode", default="pd_ee_delta_pose",
                        choices=["pd_ee_delta_pose", "pd_ee_pose", "pd_ee_pose_quat", "pd_joint_pos", "pd_joint_delta_pos"])
    oracle.add_argument("--seed", type=int, default=0)
    oracle.set_defaults(func=cmd_oracle)
