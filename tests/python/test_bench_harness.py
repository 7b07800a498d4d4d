"""The benchmark harness (bench/): the registry agrees with docs/, the timing and output helpers, the index, and
the engine's accuracy table is what the stored study gives. No server: the smoke pass itself is the ctest
bench_quick_pass."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.append(str(ROOT))  # the checkout's bench package, after everything pytest put first

from bench import cli, registry  # noqa: E402
from bench.harness import Docs, fastest, interleaved, percentiles, spread, stamp_of  # noqa: E402
from bench.index import markdown as index_markdown  # noqa: E402


def test_registry_and_docs_agree():
    """Every page has its JSON and every JSON its page, every file in docs/benchmarks/ is a benchmark's, and
    every benchmark left out of the smoke pass says why."""
    assert cli.check() == []


def test_every_script_is_a_module_with_main():
    import importlib
    for b in registry.BENCHMARKS:
        assert callable(importlib.import_module(f"bench.{b.module}").main), b.name


def test_interleaved_runs_settings_in_turn():
    order = []
    runs = interleaved({"a": lambda: order.append("a") or len(order), "b": lambda: order.append("b") or len(order)},
                       3)
    assert order == ["a", "b"] * 3
    assert runs == {"a": [1, 3, 5], "b": [2, 4, 6]}


def test_spread_fastest_and_percentiles():
    assert spread([3.0, 1.0, 2.0]) == {"min": 1.0, "median": 2.0, "max": 3.0, "runs": [3.0, 1.0, 2.0]}
    assert fastest([{"wall_s": 2.0, "n": 1}, {"wall_s": 1.5, "n": 2}]) == {"wall_s": 1.5, "n": 2}
    assert percentiles([1.0, 2.0, 3.0], (50,)) == {"p50_ms": 2.0}


def test_publish_writes_page_and_json_side_by_side(tmp_path):
    docs = Docs(tmp_path)
    script = ROOT / "bench" / "tls_overhead.py"
    docs.publish("benchmarks/tls_overhead.md", "# Title\n", "benchmarks/tls_overhead.json", {"results": {}}, script)
    stored = json.loads((tmp_path / "benchmarks" / "tls_overhead.json").read_text())
    assert stored["generated"]["script"] == "bench/tls_overhead.py"
    assert {"date", "build_id", "machine"} <= set(stored["generated"])
    page = (tmp_path / "benchmarks" / "tls_overhead.md").read_text()
    assert "`python -m bench run tls_overhead`" in page and "[tls_overhead.json](tls_overhead.json)" in page


def test_a_scripts_own_out_folder_holds_its_page(tmp_path):
    docs = Docs(tmp_path / "docs", tmp_path / "pages")
    assert docs.path("benchmarks/x.md") == tmp_path / "pages" / "x.md"
    assert docs.image("x.png") == tmp_path / "docs" / "images" / "x.png"


def test_stamps_of_json_written_before_the_harness():
    assert stamp_of({"machine": {"cpu_model": "CPU", "cores": 2, "date": "2026-11-27"}})["date"] == "2026-11-27"
    assert stamp_of({"timestamp": "2026-11-22T13:24:25+0000"})["date"] == "2026-11-22"
    old = stamp_of({"machine": {"processor": "CPU", "cpu_count": 2, "date": "2026-11-26"}})  # suite_throughput's
    assert old["machine"] == {"cpu_model": "CPU", "cores": 2}


def test_index_lists_every_page():
    text = index_markdown(Docs())
    for b in registry.BENCHMARKS:
        assert b.name in text


def test_quick_needs_another_folder_than_docs():
    """A smoke pass's numbers mean nothing: a script refuses to write them over docs/."""
    from bench.harness import arguments, docs_for
    with pytest.raises(SystemExit):
        docs_for(arguments("x").parse_args(["--quick"]))


def test_the_engine_table_is_what_the_stored_study_gives():
    done = subprocess.run([sys.executable, str(ROOT / "tools" / "gen_accuracy_table.py"), "--check"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
