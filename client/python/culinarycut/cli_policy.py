"""`culinarycut policy serve TARGET`: serve a policy over the policy protocol (culinarycut.policy_server;
docs/policy_protocol.md) until Ctrl-C or SIGTERM. TARGET is a policy name (oracle, noop, an installed
plugin's), a module:Class (one instance per episode, made with --policy-option) or a module:function
act(observation, instruction) -> actions."""
from __future__ import annotations

import signal
import sys
import threading

from culinarycut.cli_bench import UsageError, _policy_options


def _camera(text: str) -> dict:
    """NAME or NAME=WIDTHxHEIGHT."""
    name, sep, size = text.partition("=")
    camera = {"name": name}
    if sep:
        width, x, height = size.partition("x")
        if not (x and width.isdigit() and height.isdigit()):
            raise UsageError(f"--camera {text!r}: use NAME or NAME=WIDTHxHEIGHT, e.g. front=256x256")
        camera.update(width=int(width), height=int(height))
    if not name or "/" in name:
        raise UsageError(f"--camera {text!r}: a camera needs a name without '/'")
    return camera


def metadata_overrides(args) -> dict:
    overrides = {key: getattr(args, key) for key in ("name", "version", "control_mode", "action_dim", "chunk_size",
                                                     "rate_hz") if getattr(args, key) is not None}
    if args.camera:
        overrides["cameras"] = [_camera(c) for c in args.camera]
    if args.needs_session:
        overrides["needs_session"] = True
    return overrides


def cmd_serve(args) -> int:
    from culinarycut.policies.registry import UnknownPolicy, policy_class
    from culinarycut.policy_server import serve
    try:
        target = policy_class(args.target)
        server, port = serve(target, args.listen, metadata_overrides(args), _policy_options(args.policy_option),
                             tls_cert=args.tls_cert, tls_key=args.tls_key)
    except (UnknownPolicy, UsageError, ValueError, TypeError) as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    except OSError as err:
        print(f"error: {err}", file=sys.stderr)
        return 1
    metadata = server.servicer.metadata
    host = args.listen.rpartition(":")[0]
    print(f"serving policy {metadata.name} {metadata.version} ({metadata.control_mode}"
          f"{', needs the session' if metadata.needs_session else ''}) on {host}:{port}", flush=True)
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    try:
        stop.wait()
    except KeyboardInterrupt:
        pass
    server.stop(grace=1.0).wait()
    server.servicer.close()
    return 0


def register(sub) -> None:
    policy = sub.add_parser("policy", help="serve a policy over the policy protocol (--policy grpc)")
    policy.set_defaults(func=run_command, timeout=30.0)
    commands = policy.add_subparsers(dest="policy_command", required=True, metavar="{serve}")
    serve = commands.add_parser("serve", help="serve a policy class, instance or act function until Ctrl-C",
                                description=__doc__)
    serve.add_argument("target", help="oracle, noop, random, an installed plugin's name, module:Class or "
                                      "module:function")
    serve.add_argument("--listen", default="127.0.0.1:50061",
                       help="host:port to listen on (default %(default)s; port 0: a free one, printed)")
    serve.add_argument("--policy-option", action="append", default=[], metavar="KEY=VALUE",
                       help="an option for the policy class's constructor (repeatable)")
    group = serve.add_argument_group("metadata (default: the policy's attributes)")
    group.add_argument("--name")
    group.add_argument("--version")
    group.add_argument("--control-mode", help="e.g. pd_ee_delta_pose, pd_ee_pose_quat, pd_joint_pos")
    group.add_argument("--action-dim", type=int)
    group.add_argument("--chunk-size", type=int, help="actions one Act answers at most")
    group.add_argument("--rate-hz", type=float, help="the rate the policy was trained at (0: the simulator's)")
    group.add_argument("--camera", action="append", metavar="NAME[=WxH]",
                       help="a camera the policy reads, instead of its own (repeatable)")
    group.add_argument("--needs-session", action="store_true",
                       help="the policy plans on the simulator: ResetPolicy brings the session and its token")
    serve.add_argument("--tls-cert", help="serve TLS with this certificate (PEM) ...")
    serve.add_argument("--tls-key", help="... and its key")
    serve.set_defaults(policy_func=cmd_serve)


def run_command(args) -> int:
    try:
        return args.policy_func(args)
    except UsageError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2


__all__ = ["register", "run_command"]
