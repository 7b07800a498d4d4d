"""`python -m culinarycut_policies.standins MODEL --port PORT [--statistics FILE]`: serve a stand-in model
until SIGINT/SIGTERM; prints `listening on URL` once the port is bound."""
from __future__ import annotations

import argparse
import logging
import sys

from culinarycut_policies.standins.launch import MODELS, make_standin
from culinarycut_policies.standins.serving import serve_until_stopped


def _logged(model):
    count = 0

    def logged(request):
        nonlocal count
        count += 1
        print(f"query {count}", flush=True)
        return model(request)
    return logged


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m culinarycut_policies.standins", description=__doc__)
    parser.add_argument("model", choices=MODELS)
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=0, help="0: a free port (printed)")
    parser.add_argument("--statistics", help="dataset_statistics.json (openvla, openvla-oft)")
    parser.add_argument("--unnorm-key", help="the dataset key (openvla-oft; openvla takes it per request)")
    parser.add_argument("--mode", choices=("hash", "zero"), default="hash")
    parser.add_argument("--layout", choices=("libero", "droid", "aloha"),
                        help="openpi: the observation layout it serves (default libero)")
    parser.add_argument("--api-key", help="require Authorization: Api-Key KEY (websocket models)")
    parser.add_argument("--log-queries", action="store_true", help="print `query N` as each query arrives")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)
    try:
        server, _ = make_standin(args.model, args.statistics, args.unnorm_key, host=args.host, port=args.port,
                                 mode=args.mode, api_key=args.api_key, layout=args.layout)
    except ValueError as err:
        parser.error(str(err))
    if args.log_queries:
        server.model = _logged(server.model)
    serve_until_stopped(server, lambda: f"listening on {server.url}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
