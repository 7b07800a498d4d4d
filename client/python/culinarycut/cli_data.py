"""`culinarycut data`: generate a dataset (sharded on Dask, resumable), export it, verify it, describe
it in a card, and record demonstrations by teleoperation in the browser."""
from __future__ import annotations

import contextlib
import sys
from pathlib import Path

EXIT_USAGE = 2
EXIT_FAILED = 1
EXIT_INTERRUPTED = 130
MAX_TELEOP_BODY = 64 * 1024  # the largest teleoperation request body (an action is ~100 bytes)


def _states(text: str) -> list[dict]:
    """'all' or a comma list of middle, ratio-0.3 (from the left), ratio-0.3-right, split-4."""
    from culinarycut.datasets.jobs import RATIOS, SPLITS
    if text == "all":
        return ([{"state": "ratio", "ratio": r, "reference": "left"} for r in RATIOS] + [{"state": "middle"}]
                + [{"state": "split", "split_pieces": n} for n in SPLITS])
    states = []
    for item in text.split(","):
        kind, _, value = item.strip().partition("-")
        try:
            if kind == "middle" and not value:
                states.append({"state": "middle"})
            elif kind == "ratio":
                ratio, _, side = value.partition("-")
                if side not in ("", "left", "right"):
                    raise ValueError
                states.append({"state": "ratio", "ratio": float(ratio), "reference": side or "left"})
            elif kind == "split":
                states.append({"state": "split", "split_pieces": int(value)})
            else:
                raise ValueError
        except ValueError:
            raise ValueError(f"--states: {item!r} is not middle, ratio-R[-left|-right] (e.g. ratio-0.3, "
                             "ratio-0.3-right) or split-N") from None
    return states


def _scenes(text: str) -> tuple[str, ...]:
    from culinarycut.datasets.jobs import SCENES
    scenes = tuple(dict.fromkeys(s.strip() for s in text.split(",") if s.strip()))
    unknown = sorted(set(scenes) - set(SCENES))
    if not scenes or unknown:
        raise ValueError(f"--scenes: {', '.join(unknown) or 'none given'}; choose from {', '.join(SCENES)}")
    return scenes


def config_from_args(args):
    from culinarycut.datasets.jobs import STYLES, DatasetConfig, Randomisation
    styles = STYLES if args.styles == "all" else tuple(s.strip() for s in args.styles.split(","))
    unknown = set(styles) - set(STYLES)
    if unknown:
        raise ValueError(f"--styles: unknown {sorted(unknown)}; choose from {', '.join(STYLES)} or all")
    tasks = tuple({"style": style, **state, "target_object": food}
                  for food in args.food or ["cucumber"] for style in styles for state in _states(args.states))
    randomisation = Randomisation(foods=tuple(args.randomise_food or ()))
    return DatasetConfig(name=args.name, seed=args.seed, tasks=tasks, episodes_per_task=args.episodes_per_task,
                         demos=tuple(str(Path(d).resolve()) for d in args.demo or ()), randomisation=randomisation,
                         quality=args.quality, cameras=tuple(args.cameras.split(",")), image_size=args.image_size,
                         max_episode_steps=args.max_steps, paraphrase_endpoint=args.paraphrase_endpoint or "",
                         paraphrase_model=args.paraphrase_model or "", scenes=_scenes(args.scenes),
                         topology=args.topology == "on")


@contextlib.contextmanager
def _servers(args):
    """The servers given, or --local-servers started here for the run."""
    if not args.local_servers:
        yield args.server or ["127.0.0.1:50051"]
        return
    from culinarycut.launch import local_servers
    with local_servers(args.local_servers, max_sessions=4) as servers:  # sharing this machine's cores
        yield [server.address for server in servers]


def cmd_generate(args) -> int:
    from culinarycut.bench.preflight import server_infos, server_versions
    from culinarycut.bench.run_errors import RunError
    from culinarycut.datasets.generate import RetryPolicy, generate
    config = config_from_args(args)
    if args.attempts < 1:
        raise ValueError(f"--attempts: must be at least 1, got {args.attempts}")
    if args.retry_backoff < 0:
        raise ValueError(f"--retry-backoff: must be >= 0 s, got {args.retry_backoff}")
    with _servers(args) as servers:
        try:
            versions = server_versions(server_infos(servers))
        except RunError as err:
            print(f"error: {err}", file=sys.stderr)
            return EXIT_FAILED
        summary = generate(config, Path(args.out), servers, workers=args.workers, shard_size=args.shard_size,
                           scheduler=args.scheduler, progress=not args.no_progress,
                           provenance={"servers": {s: list(v) for s, v in versions.items()}},
                           retry=RetryPolicy(attempts=args.attempts, backoff_s=args.retry_backoff))
    print(f"{args.out}: {summary.kept} kept of {summary.already_done + summary.ran} finished jobs "
          f"({summary.jobs} in the dataset); this run: {summary.ran} in {summary.wall_s:.1f} s")
    if summary.errors:
        print(f"error: {summary.errors} jobs failed with transient server errors on every try (see "
              f"{Path(args.out) / 'errors'}); run the same command again to retry them", file=sys.stderr)
        return EXIT_FAILED
    return 0


def cmd_export(args) -> int:
    from culinarycut.datasets.export import export
    written = export(Path(args.dataset), Path(args.out), tuple(args.format.split(",")), name=args.name)
    for kind, path in written.items():
        print(f"{kind:<10} {path}")
    return 0


def cmd_verify(args) -> int:
    from culinarycut.datasets.verify import verify
    replay = None if args.replay < 0 else args.replay
    report = verify(Path(args.dataset), args.server, replay)
    print(f"{args.dataset}: {report.jobs} jobs, {report.kept} kept, {report.rejected} rejected, "
          f"{report.replayed} replayed")
    for problem in report.problems:
        print(f"  problem: {problem}")
    print("ok" if report.ok else f"{len(report.problems)} problem(s)")
    return 0 if report.ok else EXIT_FAILED


def cmd_card(args) -> int:
    from culinarycut.datasets.card import write_card
    print(f"wrote {write_card(Path(args.dataset), Path(args.out) if args.out else None)}")
    return 0


def cmd_teleop(args) -> int:
    """Serves the teleoperation page until Ctrl-C; demonstrations go to --out."""
    import tornado.httpserver
    import tornado.ioloop
    import tornado.netutil
    from culinarycut.client import Client
    from culinarycut.datasets.jobs import DatasetConfig, job_scene
    from culinarycut.datasets.teleop.access import WILDCARD_BINDS, AccessPolicy, is_loopback, new_token, url_host
    from culinarycut.datasets.teleop.app import make_app
    from culinarycut.datasets.teleop.session import TeleopSession
    sockets = tornado.netutil.bind_sockets(args.port, address=args.host)  # first: --port 0 picks the port
    port = sockets[0].getsockname()[1]
    client = Client(args.server, timeout_s=600.0)
    spec = client.tasks.parse_instruction(args.instruction)["spec"]
    config = DatasetConfig(name="teleop", seed=args.seed, tasks=(spec,), episodes_per_task=1, quality=args.quality,
                           image_size=args.image_size)
    variation = {"position_m": [0.5, 0.0], "yaw_deg": 0.0, "scale": 1.0, "food": spec["target_object"],
                 "scene": args.scene}
    scene = {**job_scene(config, variation, args.seed), "task": {"instruction": args.instruction}}
    session = TeleopSession(client, scene, spec, args.seed, Path(args.out), operator=args.operator)
    access = AccessPolicy(args.host, port, new_token(), tuple(args.allow_host or ()))
    server = tornado.httpserver.HTTPServer(make_app(client, session, access), max_body_size=MAX_TELEOP_BODY)
    server.add_sockets(sockets)
    shown = "127.0.0.1" if args.host in WILDCARD_BINDS else url_host(args.host)
    print(f"teleoperation of session {session.session_id}: http://{shown}:{port}/?token={access.token} "
          f"(read-only view: /watch/{session.session_id}); demonstrations go to {args.out}", flush=True)
    if not is_loopback(args.host):
        print(f"warning: --host {args.host} serves the page to other machines over plain HTTP: the token in its "
              "URL crosses the network unencrypted, and whoever holds it drives the robot (prefer the default "
              f"127.0.0.1 and an SSH tunnel: ssh -L {port}:127.0.0.1:{port} THIS_MACHINE)", file=sys.stderr,
              flush=True)
    try:
        tornado.ioloop.IOLoop.current().start()
    finally:
        session.close()
        client.close()
    return 0


def register(sub) -> None:
    data = sub.add_parser("data", help="datasets: generate, export, verify, card, teleop")
    data.set_defaults(func=run_command, timeout=30.0)
    commands = data.add_subparsers(dest="data_command", required=True, metavar="{generate,export,verify,card,teleop}")

    gen = commands.add_parser("generate", help="generate (or resume) a dataset on one or more servers")
    gen.add_argument("--out", required=True, help="dataset folder; an existing one of the same config is resumed")
    gen.add_argument("--name", default="culinarycut", help="dataset name (default %(default)s)")
    gen.add_argument("--seed", type=int, default=0, help="dataset seed: every episode's seed derives from it")
    gen.add_argument("--food", action="append", help="target food of the tasks (repeatable; default cucumber)")
    gen.add_argument("--styles", default="all", help="comma list of normal, bias, guillotine, saw, or all")
    gen.add_argument("--states", default="all",
                     help="comma list of middle, ratio-R (from the left), ratio-R-right, split-N, or all")
    gen.add_argument("--episodes-per-task", type=int, default=1, help="planner episodes per task and per demo")
    gen.add_argument("--demo", action="append", help="a demonstration file to replay on randomised scenes (repeatable)")
    gen.add_argument("--randomise-food", action="append", metavar="FOOD",
                     help="draw each episode's object type from these foods (repeatable; default: the task's)")
    gen.add_argument("--quality", default="draft", help="MPM preset (draft, standard, ...)")
    gen.add_argument("--scenes", default="table,kitchen",
                     help="comma list of table, kitchen: each episode draws one (default both, as the paper collects)")
    gen.add_argument("--topology", choices=("on", "off"), default="on",
                     help="track pieces while cutting (off: data for the topology ablation; default on)")
    gen.add_argument("--cameras", default="front,left,right", help="comma list of camera names")
    gen.add_argument("--image-size", type=int, default=224, help="square camera images, pixels")
    gen.add_argument("--max-steps", type=int, default=600, help="control steps per episode at most")
    gen.add_argument("--paraphrase-endpoint", help="an OpenAI-compatible endpoint (e.g. http://localhost:8000/v1) "
                                                 "whose paraphrases, checked by the server's parser, are added")
    gen.add_argument("--paraphrase-model", help="the endpoint's model name")
    gen.add_argument("--server", action="append", metavar="HOST:PORT", help="a culinarycut-server (repeatable)")
    gen.add_argument("--local-servers", type=int, default=0, help="start this many servers here for the run; they share the machine's cores (--step-cores = cores / N each)")
    gen.add_argument("--workers", type=int, default=1, help="Dask workers of the local cluster")
    gen.add_argument("--shard-size", type=int, default=4, help="episodes per shard")
    gen.add_argument("--scheduler", help="a Dask scheduler, tcp://HOST:PORT (default: a local cluster)")
    gen.add_argument("--attempts", type=int, default=3,
                     help="tries per server of a job the server fails transiently (default %(default)s)")
    gen.add_argument("--retry-backoff", type=float, default=2.0, metavar="SECONDS",
                     help="wait before the second try, doubled before each next one (default %(default)s)")
    gen.add_argument("--no-progress", action="store_true")
    gen.set_defaults(data_func=cmd_generate)

    exp = commands.add_parser("export", help="robomimic HDF5, LIBERO HDF5, LeRobot v2.1, RDT HDF5 and "
                                             "dataset_statistics.json")
    exp.add_argument("dataset", help="a generated dataset folder")
    exp.add_argument("--out", required=True, help="export folder")
    exp.add_argument("--format", default="robomimic,lerobot,rdt",
                     help="comma list of robomimic, libero, lerobot, rdt (default %(default)s; libero needs "
                          "end-effector control data)")
    exp.add_argument("--name", default="culinarycut", help="dataset name in the statistics and the robomimic file")
    exp.set_defaults(data_func=cmd_export)

    ver = commands.add_parser("verify", help="counts, schema, files; episodes replayed from seed and scene")
    ver.add_argument("dataset", help="a generated dataset folder")
    ver.add_argument("--server", metavar="HOST:PORT", help="server for the replays")
    ver.add_argument("--replay", type=int, default=-1, help="episodes to replay (default all; 0 none)")
    ver.set_defaults(data_func=cmd_verify)

    card = commands.add_parser("card", help="a dataset card (README.md) with counts, filter rate and pictures")
    card.add_argument("dataset", help="a generated dataset folder")
    card.add_argument("--out", help="folder for README.md and its pictures (default: the dataset folder)")
    card.set_defaults(data_func=cmd_card)

    tel = commands.add_parser("teleop", help="drive the knife from the browser and record demonstrations")
    tel.add_argument("--server", default="127.0.0.1:50051", metavar="HOST:PORT", help="the simulator")
    tel.add_argument("--out", required=True, help="folder for the demonstration files")
    tel.add_argument("--instruction", default="cut the cucumber at 0.3 ratio from the left",
                     help="the task demonstrated (its cut spec is stored with the demonstration)")
    tel.add_argument("--seed", type=int, default=0, help="the scene's reset seed")
    tel.add_argument("--quality", default="draft", help="MPM preset")
    tel.add_argument("--scene", choices=("table", "kitchen"), default="table", help="where the food stands")
    tel.add_argument("--image-size", type=int, default=224, help="square camera images, pixels")
    tel.add_argument("--host", default="127.0.0.1",
                     help="address the page is served on (default loopback: only this machine reaches it)")
    tel.add_argument("--port", type=int, default=8008, help="port the page is served on (0 picks a free one)")
    tel.add_argument("--allow-host", action="append", metavar="NAME",
                     help="another name browsers reach the page by (e.g. this machine's DNS name); repeatable")
    tel.add_argument("--operator", default="", help="who demonstrates (stored in the file)")
    tel.set_defaults(data_func=cmd_teleop)


def run_command(args) -> int:
    try:
        return args.data_func(args)
    except ValueError as err:
        print(f"error: {err}", file=sys.stderr)
        return EXIT_USAGE
    except RuntimeError as err:  # a dataset of another config, all servers lost
        print(f"error: {err}", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        print("\nstopped; run the same command again to resume", file=sys.stderr)
        return EXIT_INTERRUPTED


__all__ = ["register", "run_command"]
