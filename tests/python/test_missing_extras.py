"""A command whose optional extra is not installed ends with one line naming the extra to install (exit 1),
not a traceback: `bench run` without tqdm, `bench list` without jsonschema, as a user meets them."""
from __future__ import annotations

import subprocess
import sys

from culinarycut.extras import extras_providing

# Runs the CLI in a fresh interpreter where importing `module` fails, as if it were not installed.
HIDDEN_MODULE = """
import sys
sys.modules[sys.argv[1]] = None
from culinarycut.cli import main
sys.exit(main(sys.argv[2:]))
"""


def without(module: str, *argv: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", HIDDEN_MODULE, module, *argv], capture_output=True, text=True,
                          timeout=120)


def test_bench_run_without_tqdm_names_the_bench_extra(address, tmp_path):
    done = without("tqdm", "bench", "run", "smoke", "--trials", "1", "--server", address, "--out", str(tmp_path))
    assert done.returncode == 1 and "Traceback" not in done.stderr, done.stderr
    assert done.stderr.strip() == ("error: `culinarycut bench` needs tqdm, which is not installed: "
                                   "pip install 'culinarycut[bench]'")


def test_bench_list_without_jsonschema_names_the_bench_extra():
    done = without("jsonschema", "bench", "list")
    assert done.returncode == 1 and "Traceback" not in done.stderr, done.stderr
    assert "needs jsonschema, which is not installed: pip install 'culinarycut[bench]'" in done.stderr


def test_extras_are_read_from_the_package_metadata_by_distribution_name():
    assert extras_providing("tqdm") == ["bench", "safety"]
    assert extras_providing("PIL") == ["bench"]          # Pillow
    assert extras_providing("cv2") == ["datasets"]       # opencv-python
    assert extras_providing("grpc") == []                # a core dependency: no extra brings it
