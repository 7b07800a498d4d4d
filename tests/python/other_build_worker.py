"""Dask worker preload for the benchmark tests (`dask worker --preload other_build_worker`): the servers
this worker talks to answer as version 0.0.1, build elsewhere, as a worker bound by CULINARYCUT_SERVER to a
server of another build would see; the episodes themselves run on the real server."""
from __future__ import annotations

from culinarycut.client import Client

OTHER_VERSION, OTHER_BUILD = "0.0.1", "elsewhere"
_real_server_info = Client.server_info


def _other_build_server_info(self):
    info = _real_server_info(self)
    info.version, info.build_id = OTHER_VERSION, OTHER_BUILD
    return info


Client.server_info = _other_build_server_info
