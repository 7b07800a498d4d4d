"""The instruction tokenizer: words over the vocabulary of CulinaryCut's instruction generator (its
templates and lexical pools, assets/language/instruction_templates.json, and the foods) and of the
training instructions (which hold the paraphrases of a dataset generated with a paraphrase endpoint),
with numbers kept as values.

A quantity ("0.3", "30%", "thirty percent", "three tenths", "the 3/10 mark", "halfway") becomes one
`<ratio>` token carrying its value, a piece count ("3", "three", "into thirds") one `<count>` token
carrying its count; the model adds features of the value to the token's embedding (model.py), so "0.3"
and "three tenths" are the same input and 0.35, never seen, lies between 0.3 and 0.4. The number phrases
come from the templates' own pools (fractions, fixed-value quantity and piece forms, counts), read the
way the server's parser reads them (docs/language.md): lower case, hyphens and punctuation separate
words, "%" is "percent".

Words that never occur in the training instructions (the held-out wording, an unknown paraphrase) are
read as `<unk>`: their embeddings would never be trained. Word dropout during training teaches the model
what `<unk>` means."""
from __future__ import annotations

import json
import math
import os
import re
from pathlib import Path
from typing import Iterable, Sequence

import numpy as np

PAD, UNK, RATIO, COUNT = "<pad>", "<unk>", "<ratio>", "<count>"
SPECIALS = (PAD, UNK, RATIO, COUNT)
FOODS = ("apple", "banana", "cucumber", "melon", "orange", "peach", "strawberry")
# Number words the generator writes ({percent_words}: "twenty five" after the hyphen split) and counts.
UNITS = {w: i for i, w in enumerate("zero one two three four five six seven eight nine ten eleven twelve thirteen "
                                    "fourteen fifteen sixteen seventeen eighteen nineteen".split())}
TENS = {w: 10 * (i + 2) for i, w in enumerate("twenty thirty forty fifty sixty seventy eighty ninety".split())}
NUMBER_FEATURES = 11  # numeric_features(): ratio value, its Fourier features, count features
_TOKEN = re.compile(r"\d+/\d+|\d*\.\d+|\d+|[a-z]+")
CHECKOUT_TEMPLATES = Path(__file__).resolve().parents[2] / "assets" / "language" / "instruction_templates.json"


def templates_path() -> Path:
    """$CULINARYCUT_ASSETS_DIR/language/instruction_templates.json, else the checkout's (what the server reads)."""
    assets = os.environ.get("CULINARYCUT_ASSETS_DIR")
    return Path(assets) / "language" / "instruction_templates.json" if assets else CHECKOUT_TEMPLATES


def words(text: str) -> list[str]:
    """Lower case; hyphens and punctuation separate words; "%" is the word "percent"."""
    text = text.lower().replace("%", " percent ").replace("-", " ")
    return _TOKEN.findall(text)


def _strip_placeholders(text: str) -> str:
    return re.sub(r"\{[a-z_]+\}", " ", text)


def number_phrases(templates: dict) -> dict[tuple[str, ...], tuple[str, float]]:
    """(words) -> (kind, value) from the templates' pools: fraction words ("three tenths" -> ratio 0.3),
    quantity forms with a fixed value ("halfway"), piece forms with one ("into thirds" -> count 3), counts."""
    pools = templates["pools"]
    phrases: dict[tuple[str, ...], tuple[str, float]] = {}
    for entry in pools["fraction"]:
        phrases[tuple(words(entry["text"]))] = (RATIO, entry["value"][0] / entry["value"][1])
    for entry in pools["quantity"]:
        if "value" in entry:
            phrases[tuple(words(entry["text"]))] = (RATIO, entry["value"][0] / entry["value"][1])
    for entry in pools["pieces"]:
        if "value" in entry:
            phrases[tuple(words(entry["text"]))] = (COUNT, float(entry["value"]))
    for entry in pools["count"]:
        phrases[tuple(words(entry["text"]))] = (COUNT, float(entry["value"]))
    return phrases


def generator_words(templates: dict) -> set[str]:
    """Every word the generator can write: templates, pools (placeholders left out) and the foods."""
    texts: list[str] = []
    for state in templates["states"].values():
        texts += [t["text"] for t in state["templates"]]

    def collect(node):
        if isinstance(node, dict):
            if "text" in node:
                texts.append(node["text"])
            for value in node.values():
                if isinstance(value, (dict, list)):
                    collect(value)
        elif isinstance(node, list):
            for item in node:
                collect(item)
    collect(templates["pools"])
    found = set(FOODS)
    for text in texts:
        found.update(w for w in words(_strip_placeholders(text)) if not w[0].isdigit())
    return found


def _number_word(tokens: Sequence[str], at: int) -> tuple[int, int]:
    """(value, length) of a number in words at `at` ("twenty five", "thirty", "seven"), (-1, 0) if none."""
    word = tokens[at]
    if word in TENS:
        if at + 1 < len(tokens) and tokens[at + 1] in UNITS and 0 < UNITS[tokens[at + 1]] < 10:
            return TENS[word] + UNITS[tokens[at + 1]], 2
        return TENS[word], 1
    if word in UNITS:
        return UNITS[word], 1
    return -1, 0


class Tokenizer:
    """Words -> (ids, values). `vocabulary`: the generator's words and the training instructions' words;
    `trained`: those that occur in the training instructions (any other reads as <unk>)."""

    def __init__(self, vocabulary: Sequence[str], trained: Iterable[str], phrases: dict, max_tokens: int):
        self.vocabulary = list(SPECIALS) + sorted(set(vocabulary) - set(SPECIALS))
        self.index = {word: i for i, word in enumerate(self.vocabulary)}
        self.trained = set(trained) & set(self.vocabulary)
        self.phrases = {tuple(k): tuple(v) for k, v in phrases.items()}
        self.longest = max((len(k) for k in self.phrases), default=1)
        self.max_tokens = int(max_tokens)

    @classmethod
    def build(cls, instructions: Iterable[str], templates: dict, max_tokens: int) -> "Tokenizer":
        phrases = number_phrases(templates)
        probe = cls(generator_words(templates), (), phrases, max_tokens)
        seen = {word for text in instructions for word, _ in probe.pieces(text) if word not in SPECIALS}
        return cls(generator_words(templates) | seen, seen, phrases, max_tokens)

    def to_dict(self) -> dict:
        return {"vocabulary": self.vocabulary, "trained": sorted(self.trained), "max_tokens": self.max_tokens,
                "phrases": [[list(k), list(v)] for k, v in sorted(self.phrases.items())]}

    @classmethod
    def from_dict(cls, data: dict) -> "Tokenizer":
        return cls(data["vocabulary"], data["trained"], {tuple(k): v for k, v in data["phrases"]}, data["max_tokens"])

    def pieces(self, text: str) -> list[tuple[str, float]]:
        """(word or <ratio>/<count>, value) in order; values are 0 for words."""
        tokens = words(text)
        out: list[tuple[str, float]] = []
        i = 0
        while i < len(tokens):
            token = tokens[i]
            # a percentage in digits or words: "30 percent" (from "30%"), "twenty five percent"
            value, length = (int(token), 1) if token.isdigit() else _number_word(tokens, i)
            if length and i + length < len(tokens) and tokens[i + length] == "percent":
                out.append((RATIO, value / 100.0))
                i += length + 1
                continue
            match = next((n for n in range(min(self.longest, len(tokens) - i), 0, -1)
                          if tuple(tokens[i:i + n]) in self.phrases), 0)
            if match:
                kind, number = self.phrases[tuple(tokens[i:i + match])]
                out.append((kind, float(number)))
                i += match
                continue
            if "/" in token:
                numerator, denominator = (int(p) for p in token.split("/"))
                out.append((RATIO, numerator / denominator if denominator else 0.0))
            elif "." in token:
                out.append((RATIO, float(token)))
            elif token.isdigit():
                out.append((COUNT, float(token)))
            else:
                out.append((token, 0.0))
            i += 1
        return out

    def encode(self, text: str) -> tuple[np.ndarray, np.ndarray]:
        """(ids (max_tokens,) int64, values (max_tokens,) float32), padded with <pad>; cut at max_tokens."""
        ids = np.full(self.max_tokens, self.index[PAD], dtype=np.int64)
        values = np.zeros(self.max_tokens, dtype=np.float32)
        for n, (word, value) in enumerate(self.pieces(text)[: self.max_tokens]):
            known = word in (RATIO, COUNT) or word in self.trained
            ids[n] = self.index[word] if known else self.index[UNK]
            values[n] = value
        return ids, values

    @property
    def word_ids(self) -> np.ndarray:
        """Ids that word dropout may replace with <unk> (not pads, not numbers)."""
        return np.array([self.index[w] for w in sorted(self.trained)], dtype=np.int64)


def numeric_features(ids: np.ndarray, values: np.ndarray, ratio_id: int, count_id: int) -> np.ndarray:
    """(..., NUMBER_FEATURES) float32: for <ratio> its value and sin/cos(2 pi k v), k = 1..4; for <count>
    n / 5 and 1 / n; zeros for words."""
    ratio = (ids == ratio_id).astype(np.float32)[..., None]
    count = (ids == count_id).astype(np.float32)[..., None]
    v = values.astype(np.float32)[..., None]
    k = np.arange(1, 5, dtype=np.float32)
    ratio_features = np.concatenate([v, np.sin(2 * math.pi * k * v), np.cos(2 * math.pi * k * v)], axis=-1)
    count_features = np.concatenate([v / 5.0, 1.0 / np.maximum(v, 1.0)], axis=-1)
    return np.concatenate([ratio * ratio_features, count * count_features], axis=-1)


def load_templates(path: Path | None = None) -> dict:
    path = Path(path) if path else templates_path()
    try:
        return json.loads(path.read_text())
    except OSError as err:
        raise FileNotFoundError(f"instruction templates {path}: cannot be read ({err.strerror}); set "
                                "CULINARYCUT_ASSETS_DIR to the assets/ folder or pass --templates") from None
