"""Episodes on Dask workers: each worker is bound to one server; where a server stops answering the
episode moves on to the next server, and Dask itself reruns the episodes of a worker that died.

Without a scheduler address the runner starts a local cluster (threads in this process: the work is
on the servers, the workers mostly wait on gRPC). With `--scheduler tcp://HOST:PORT` episodes go to
that cluster's workers; a worker started with CULINARYCUT_SERVER=HOST:PORT in its environment uses
that server, any other is bound to one of the runner's servers by its name.
"""
from __future__ import annotations

import io
import logging
import os
import zlib
from dataclasses import dataclass

from culinarycut.bench.episode import EpisodeOptions, EpisodeResult, ServerLost, run_episode
from culinarycut.bench.episode_scene import EpisodeSpec

GIF_FRAME_S = 0.1  # failure videos at 10 frames per second of wall time (every second control step)


class AllServersLost(RuntimeError):
    """No server answered for this episode."""


@dataclass
class WorkerResult:
    result: EpisodeResult
    video_gif: bytes | None  # the failure video, encoded on the worker so only bytes travel


def _worker_server_order(servers: list[str]) -> list[str]:
    """This worker's server first, then the others in turn. CULINARYCUT_SERVER binds a worker only when it
    is an address: launch.py (and ctest) read the same variable as the server binary's path, and taking a
    path for an address had sent every worker past it to the same first server."""
    bound = os.environ.get("CULINARYCUT_SERVER")
    if bound and ":" in bound and not os.path.exists(bound):
        return [bound] + [s for s in servers if s != bound]
    try:
        from distributed import get_worker
        name = str(get_worker().name)
    except (ImportError, ValueError):
        name = "0"
    first = int(name) % len(servers) if name.isdigit() else zlib.crc32(name.encode()) % len(servers)
    return servers[first:] + servers[:first]


def encode_gif(frames) -> bytes:
    from PIL import Image  # Debian's python3-pil (a dependency of matplotlib)
    images = [Image.fromarray(frame) for frame in frames[::2]]
    buffer = io.BytesIO()
    # Durations as a list: Pillow merges identical frames (a knife held still) and adds up their time,
    # which with one number it drops when a single frame is left.
    images[0].save(buffer, format="GIF", save_all=True, append_images=images[1:],
                   duration=[int(GIF_FRAME_S * 1000)] * len(images), loop=0)
    return buffer.getvalue()


def run_on_worker(spec: EpisodeSpec, servers: list[str], options: EpisodeOptions) -> WorkerResult:
    """Runs the episode on the first server that answers; raises AllServersLost if none does."""
    lost = []
    for attempt, server in enumerate(_worker_server_order(servers), start=1):
        try:
            result = run_episode(spec, server, options)
        except ServerLost as err:
            lost.append(str(err))
            continue
        result.row["attempts"] = attempt
        video = None
        if options.record_video and result.row["outcome"] != "success" and result.frames:
            video = encode_gif(result.frames)
        result.frames = []
        return WorkerResult(result, video)
    raise AllServersLost("no server answered: " + "; ".join(lost))


def start_cluster(scheduler: str | None, workers: int):
    """A Dask client: to the given scheduler, or to a local cluster of `workers` single-thread workers."""
    from distributed import Client, LocalCluster
    if scheduler:
        return Client(scheduler, timeout="10s"), None
    # No dashboard, and the scheduler's HTTP routes on a free loopback port: None alone still binds :8787 on
    # every interface (and warns when it is taken). A failed task is reported by the runner, not logged here.
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=False, dashboard_address=None,
                           scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}, silence_logs=logging.CRITICAL)
    return Client(cluster), cluster
