"""A stand-in model server by model name: the fake model behind its upstream protocol, not yet started."""
from __future__ import annotations

import json
from pathlib import Path

from culinarycut_policies.standins.fake_models import FakeOcto, FakeOpenPI, FakeOpenVLA, FakeOpenVLAOFT, FakeRDT
from culinarycut_policies.standins.rest_server import JsonNumpyRestServer
from culinarycut_policies.standins.websocket_server import WebsocketPolicyServer
from culinarycut_policies.statistics import load_statistics

MODELS = ("openvla", "openvla-oft", "octo", "rdt", "openpi")


def make_standin(model: str, statistics: str | None = None, unnorm_key: str | None = None, *,
                 host: str = "127.0.0.1", port: int = 0, mode: str = "hash", api_key: str | None = None,
                 layout: str | None = None):
    """(server, fake model). OpenVLA's models un-normalise on the server, so they need the statistics;
    the others answer in the model's own (normalised or unified) space. `layout`: the openpi layout
    the openpi stand-in serves (libero by default)."""
    if layout is not None and model != "openpi":
        raise ValueError(f"a layout is the openpi stand-in's; the {model} stand-in has none")
    if model.startswith("openvla") and not statistics:
        raise ValueError(f"the {model} stand-in un-normalises on the server, as {model} does: give it the "
                         "statistics (--statistics FILE; standins/example_statistics.py writes an example)")
    if model == "openvla":
        keys = json.loads(Path(statistics).read_text())
        fake = FakeOpenVLA({k: load_statistics(statistics, k, policy="openvla stand-in") for k in keys}, mode=mode)
        return JsonNumpyRestServer(fake, host, port), fake
    if model == "openvla-oft":
        fake = FakeOpenVLAOFT(load_statistics(statistics, unnorm_key, policy="openvla-oft stand-in"), mode=mode)
        return JsonNumpyRestServer(fake, host, port), fake
    fakes = {"octo": FakeOcto, "rdt": FakeRDT, "openpi": FakeOpenPI}
    if model not in fakes:
        raise ValueError(f"unknown stand-in model {model!r}; choose one of {', '.join(MODELS)}")
    fake = FakeOpenPI(mode=mode, layout=layout or "libero") if model == "openpi" else fakes[model](mode=mode)
    return WebsocketPolicyServer(fake, fake.metadata, host, port, api_key=api_key), fake
