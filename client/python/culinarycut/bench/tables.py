"""Result tables from stored episode rows: success per task, style, state, food or group, with 95 %
Wilson intervals; the paper's split partial-success table. Plain data, printed as text or Markdown."""
from __future__ import annotations

from collections import Counter, defaultdict
from dataclasses import dataclass
from typing import Callable, Iterable

from culinarycut.bench.stats import wilson_interval


@dataclass(frozen=True)
class RateRow:
    key: str
    episodes: int
    successes: int
    errors: int

    @property
    def rate(self) -> float:
        return self.successes / self.episodes if self.episodes else 0.0

    @property
    def interval(self) -> tuple[float, float]:
        return wilson_interval(self.successes, self.episodes)


def success_by(rows: Iterable[dict], key: Callable[[dict], str] | str) -> list[RateRow]:
    """Success per value of `key` (a column name or a function of the row), in first-seen order."""
    key_of = (lambda row: str(row[key])) if isinstance(key, str) else key
    groups: dict[str, list[dict]] = defaultdict(list)
    for row in rows:
        groups[key_of(row)].append(row)
    return [RateRow(k, len(g), sum(r["outcome"] == "success" for r in g), sum(r["outcome"] == "error" for r in g))
            for k, g in groups.items()]


def split_partial(rows: Iterable[dict]) -> list[dict]:
    """The paper's partial-success table: per food and split, the share of episodes in which exactly k
    of the required cuts lie within the position tolerance (k = 0 .. pieces - 1)."""
    table: dict[tuple[str, int], Counter] = defaultdict(Counter)
    for row in rows:
        if row["state"] != "split":
            continue
        table[(row["food"], row["pieces_required"])][row["cuts_within_tolerance"] or 0] += 1
    result = []
    for (food, pieces), counts in sorted(table.items()):
        total = sum(counts.values())
        result.append({"food": food, "split": f"1/{pieces}", "episodes": total,
                       "share_with_k": {k: counts.get(k, 0) / total for k in range(pieces)}})
    return result


def _percent(value: float) -> str:
    return f"{100 * value:.0f} %"


def rate_cells(row: RateRow) -> list[str]:
    low, high = row.interval
    return [row.key, f"{row.successes}/{row.episodes}", _percent(row.rate), f"{_percent(low)} - {_percent(high)}",
            str(row.errors)]


RATE_HEADER = ["", "success", "rate", "95 % CI (Wilson)", "errors"]


def markdown_table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(cells) + " |" for cells in rows]
    return "\n".join(lines)


def text_table(header: list[str], rows: list[list[str]]) -> str:
    widths = [max(len(str(c)) for c in column) for column in zip(header, *rows)]
    def line(cells):
        return "  ".join(str(c).ljust(w) if i == 0 else str(c).rjust(w) for i, (c, w) in enumerate(zip(cells, widths)))
    return "\n".join([line(header), "  ".join("-" * w for w in widths)] + [line(r) for r in rows])


def results_text(rows: list[dict], title: str) -> str:
    """The table the runner prints: success per task, then overall."""
    per_task = [rate_cells(r) for r in success_by(rows, "task")]
    overall = success_by(rows, lambda _: "all")
    body = per_task + ([rate_cells(overall[0])] if overall else [])
    return f"{title}\n" + text_table(["task"] + RATE_HEADER[1:], body)
