"""Optional paraphrasing of generated instructions by an OpenAI-compatible chat endpoint.

Off by default: nothing here runs unless a caller passes an endpoint. Every paraphrase is parsed
back by the server and kept only if it asks for the same cut (style, state, food and cut
positions), so a model that changes a ratio, a side or the food cannot corrupt a dataset.
"""
from __future__ import annotations

import json
import re
import urllib.error
import urllib.request
from typing import Sequence

from culinarycut.errors import CulinaryCutError
from culinarycut.tasks import TaskClient

PROMPT = (
    "Rewrite each robot instruction below in {n} different natural ways. Keep the food, the cut "
    "style, the position (numbers, fractions, sides) and the number of pieces exactly. "
    "Answer with one instruction per line and nothing else.\n\n{instructions}"
)


# "1. ", "2) ", "- ", "* " at the start of a line: list markers, not part of the instruction.
LIST_MARKER = re.compile(r"^(?:\d{1,3}[.)]\s+|[-*\u2022]\s+)")


class ParaphraseError(RuntimeError):
    """The endpoint could not be reached or answered something that is not a chat completion."""


def request_paraphrases(instructions: Sequence[str], endpoint: str, model: str, *, per_instruction: int = 2,
                        api_key: str | None = None, timeout_s: float = 60.0) -> list[str]:
    """Raw candidate lines from `endpoint` (e.g. http://localhost:8000/v1): POST /chat/completions."""
    body = {
        "model": model,
        "temperature": 0.7,
        "messages": [{"role": "user", "content": PROMPT.format(
            n=per_instruction, instructions="\n".join(instructions))}],
    }
    headers = {"Content-Type": "application/json"}
    if api_key:
        headers["Authorization"] = f"Bearer {api_key}"
    url = endpoint.rstrip("/") + "/chat/completions"
    request = urllib.request.Request(url, data=json.dumps(body).encode(), headers=headers, method="POST")
    try:
        with urllib.request.urlopen(request, timeout=timeout_s) as response:
            reply = json.loads(response.read().decode())
        content = reply["choices"][0]["message"]["content"]
    except (urllib.error.URLError, OSError) as err:
        raise ParaphraseError(f"paraphrase endpoint {url} unreachable: {err}") from None
    except (ValueError, KeyError, IndexError, TypeError) as err:
        raise ParaphraseError(f"paraphrase endpoint {url} did not answer a chat completion: {err!r}") from None
    lines = (LIST_MARKER.sub("", line.strip()).strip() for line in str(content).splitlines())
    return [line for line in lines if line]


def _meaning(parsed: dict) -> tuple:
    """What a cut instruction asks for: style, state, food and where the cuts go (not how it is
    phrased, nor which end a position is measured from)."""
    spec = parsed["spec"]
    return (spec["style"], spec["state"], spec["target_object"],
            tuple(round(f, 9) for f in parsed["target_fractions"]))


def paraphrase(tasks: TaskClient, instructions: Sequence[str], endpoint: str, model: str,
               **kwargs) -> tuple[list[str], list[str]]:
    """(kept, rejected) paraphrases of `instructions`, which must all ask for the same cut: kept ones
    parse to the same style, state, food and cut positions; the rest changed the meaning or do not
    parse."""
    if not instructions:
        raise ValueError("give at least one instruction to paraphrase")
    wanted = _meaning(tasks.parse_instruction(instructions[0]))
    kept, rejected = [], []
    for candidate in request_paraphrases(instructions, endpoint, model, **kwargs):
        try:
            same = _meaning(tasks.parse_instruction(candidate)) == wanted
        except CulinaryCutError:
            same = False
        new = candidate not in instructions and candidate not in kept
        (kept if same and new else rejected).append(candidate)
    return kept, rejected
