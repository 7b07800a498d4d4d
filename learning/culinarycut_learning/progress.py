"""A progress bar: tqdm when it is installed (the `progress` extra, as culinarycut's `bench` extra brings
it), else a line every `every` steps on stderr."""
from __future__ import annotations

import sys
import time


class _Lines:
    def __init__(self, total: int, initial: int, every: int, desc: str):
        self.total, self.n, self.every, self.desc = total, initial, every, desc
        self.started = time.monotonic()
        self.postfix = ""

    def update(self, count: int = 1) -> None:
        self.n += count
        if self.n % self.every == 0 or self.n == self.total:
            rate = self.n / max(time.monotonic() - self.started, 1e-9)
            print(f"{self.desc}: {self.n}/{self.total} {self.postfix} ({rate:.2f} steps/s)", file=sys.stderr,
                  flush=True)

    def set_postfix_str(self, text: str, refresh: bool = True) -> None:
        self.postfix = text

    def close(self) -> None:
        pass


def progress_bar(total: int, initial: int, enabled: bool, every: int, desc: str = "train"):
    if not enabled:
        return _Lines(total, initial, every=10 ** 12, desc=desc)
    try:
        from tqdm import tqdm
    except ModuleNotFoundError:
        return _Lines(total, initial, every, desc)
    return tqdm(total=total, initial=initial, unit="step", desc=desc, dynamic_ncols=True)
