"""How many editing-benchmark entries of each kind a synthetic dataset was asked for, how many it made, and why
any are missing.

Each sequence asks for ``edit_pairs`` edit entries and ``occluder_pairs`` occluder-removed entries
(:class:`~sdn3d.data.synth.generate.SynthConfig`). A pair the generator cannot draw (the sequence's test frames have
no partly hidden car, say) is still written, as an entry *without operations* (its target re-renders the source) so
that the frame numbering stays the same, and ``sdn3d-bench`` skips such entries: without a report a kind would be
scored on fewer entries than asked for, or on none, and nobody would know. So:

- the generator records each missing entry's reason (:class:`Missing`) per sequence, writes the counts into
  ``synth_manifest.json`` (``benchmark_entries``, :func:`manifest_counts`) and prints :func:`shortfall_lines`
  on stderr;
- ``sdn3d-bench`` counts what its benchmark file holds against what the dataset's manifest asked for
  (:func:`benchmark_shortfall`) and warns once.
"""

from __future__ import annotations

import json
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import Any

from sdn3d.data.edit_benchmark import BenchmarkEntry
from sdn3d.data.sources import SYNTH_MANIFEST
from sdn3d.errors import UserInputError

__all__ = ["Missing", "MissingEntry", "KindCount", "manifest_counts", "benchmark_shortfall", "shortfall_lines",
           "shortfall_sentences", "counts_json", "MANIFEST_KEY"]

#: The key of ``synth_manifest.json`` holding :func:`manifest_counts`.
MANIFEST_KEY = "benchmark_entries"
#: The manifest's config field that asks for each entry kind (every one of ``ENTRY_KINDS``) per sequence.
_ASKED_BY = {"edit": "edit_pairs", "occluder_removed": "occluder_pairs"}


class Missing(str, Enum):
    """Why a sequence's benchmark pair was not made (the value is the manifest's ``reason``)."""

    #: An edit pair's source frame has no car that can be edited (well visible, unambiguous centre).
    NO_EDITABLE_CAR = "no_editable_car"
    #: Every drawn edit of the source frame hid an edited car in the target.
    EDIT_HIDES_CAR = "edit_hides_car"
    #: No test frame has a partly hidden car (a small visible share, enough pixels, little truncation).
    NO_HIDDEN_CAR = "no_hidden_car"
    #: Partly hidden cars, but no car in front of one that a ``from`` point can pick.
    NO_OCCLUDER = "no_occluder"
    #: Candidate pairs, but deleting the occluder reveals too little of the hidden car in each.
    TOO_LITTLE_REVEALED = "too_little_revealed"


@dataclass(frozen=True)
class MissingEntry:
    """One pair a sequence asked for and did not get: its kind (``'edit'``, ``'occluder_removed'``), sequence,
    reason and the details (frames, thresholds) as a sentence."""

    kind: str
    world: str
    variation: str
    reason: Missing
    why: str


@dataclass(frozen=True)
class KindCount:
    """Entries of one kind: asked for, made (with operations, what ``sdn3d-bench`` scores) and, per sequence,
    why some are missing (``[{world, variation, missing, reason, why}]``)."""

    kind: str
    asked: int
    made: int
    short: tuple[dict, ...] = ()

    def to_json(self) -> dict:
        return {"asked": self.asked, "made": self.made, "short": list(self.short)}

    @classmethod
    def from_json(cls, kind: str, raw: dict) -> KindCount:
        """The count :meth:`to_json` wrote (``results.json``'s ``info.benchmark_short``)."""
        return cls(kind, int(raw["asked"]), int(raw["made"]), tuple(raw.get("short") or ()))


def _made(entries: Sequence[BenchmarkEntry], kind: str) -> int:
    return sum(1 for e in entries if e.kind == kind and not e.is_identity)


def manifest_counts(entries: Sequence[BenchmarkEntry], missing: Sequence[MissingEntry], sequences: int,
                    config: dict[str, Any]) -> dict[str, KindCount]:
    """Every kind's :class:`KindCount` of a generated benchmark: ``config``'s pairs per sequence (``edit_pairs``,
    ``occluder_pairs``; the manifest's ``config``) x ``sequences`` asked, the ``entries`` with operations made,
    ``missing`` grouped by sequence and reason (in their order)."""
    counts = {}
    for kind in _ASKED_BY:
        grouped = Counter((m.world, m.variation, m.reason, m.why) for m in missing if m.kind == kind)
        short = tuple({"world": w, "variation": v, "missing": n, "reason": r.value, "why": why}
                      for (w, v, r, why), n in grouped.items())
        counts[kind] = KindCount(kind, int(config[_ASKED_BY[kind]]) * sequences, _made(entries, kind), short)
    return counts


def shortfall_lines(counts: dict[str, KindCount], who: str) -> list[str]:
    """One warning line per kind with fewer entries made than asked for (none when every kind is complete),
    naming the sequences per reason; ``who`` starts each line (``sdn3d-synth``, ``sdn3d-bench``)."""
    return [f"{who}: warning: {sentence}" for sentence in shortfall_sentences(counts)]


def shortfall_sentences(counts: dict[str, KindCount]) -> list[str]:
    """:func:`shortfall_lines` without their prefix: one sentence per short kind (``table1.md`` prints them)."""
    sentences = []
    for kind, count in counts.items():
        if count.made >= count.asked:
            continue
        by_why: dict[str, list[dict]] = {}
        for s in count.short:
            by_why.setdefault(s["why"], []).append(s)
        reasons = "; ".join(f"{sum(s['missing'] for s in short)} missing in "
                            f"{', '.join(s['world'] + '/' + s['variation'] for s in short)}: {why}"
                            for why, short in by_why.items())
        sentences.append(f"{count.made} of the {count.asked} '{kind}' benchmark entries asked for were made "
                         f"({reasons or 'the reasons are not recorded'}); each missing one is an entry without "
                         "operations, which sdn3d-bench skips")
    return sentences


def benchmark_shortfall(path: Path, entries: Sequence[BenchmarkEntry]) -> dict[str, KindCount]:
    """Kinds of a synthetic benchmark file with fewer scorable entries than its dataset asked for: ``{kind:
    KindCount}`` counted from ``entries`` (the file as loaded) against ``synth_manifest.json`` beside ``path``
    (``config``'s pairs per sequence x its sequences), with the generator's reasons where the manifest has them.
    Empty when ``path`` is not a generated benchmark (no manifest naming it beside it: the paper's file, a copy).

    Raises:
        UserInputError: the manifest beside ``path`` names it but cannot be read.
    """
    manifest_path = path.parent / SYNTH_MANIFEST
    if not manifest_path.is_file():
        return {}
    try:
        manifest = json.loads(manifest_path.read_text(encoding="utf-8"))
        if manifest.get("benchmark") != path.name:
            return {}
        config, sequences = manifest["config"], len(manifest["sequences"])
        recorded = manifest.get(MANIFEST_KEY) or {}
        asked = {kind: int(config[field]) * sequences for kind, field in _ASKED_BY.items()}
        short = {kind: tuple((recorded.get(kind) or {}).get("short") or ()) for kind in _ASKED_BY}
    except (ValueError, KeyError, TypeError, AttributeError) as exc:
        raise UserInputError(f"{str(manifest_path)!r}: cannot read the benchmark's entry counts: {exc}") from exc
    counts = {kind: KindCount(kind, asked[kind], _made(entries, kind), short[kind]) for kind in _ASKED_BY}
    return {kind: count for kind, count in counts.items() if count.made < count.asked}


def counts_json(counts: dict[str, KindCount]) -> dict[str, Any]:
    """``{kind: {asked, made, short}}`` as the manifest and ``results.json`` record it."""
    return {kind: count.to_json() for kind, count in counts.items()}
