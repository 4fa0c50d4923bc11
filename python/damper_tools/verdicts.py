"""The diagnosis's verdicts and the one rule of a right one, shared by the scorers (blind_score,
campaign, dyno_score).

`damper diagnose` writes a verdict to summary.json (`verdict`, the strings of `Verdict`) and the
effects it names (`effects`, the best first). Against a truth that hid some catalog effects, the
verdict is right when

- nothing was hidden: the verdict is `none` and nothing is named;
- effects were hidden: the verdict is `effect` and every hidden effect is named (others may be
  named too); with `first`, the hidden effects are also the first ones named (dyno_score: the
  effect that carries a change must lead).

    >>> right((), "none", [])
    True
    >>> right(["seal_friction"], "effect", ["mount_compliance", "seal_friction"])
    True
    >>> right(["seal_friction"], "effect", ["mount_compliance", "seal_friction"], first=True)
    False
"""

import enum
from collections.abc import Collection, Sequence


class Verdict(enum.StrEnum):
    """A diagnosis verdict as summary.json writes it (crates/damper_engine/src/verdict.rs)."""

    NONE = "none"  # the baseline is at the noise floor: nothing is missing
    EFFECT = "effect"  # the named effects explain the record down to the floor
    PARTIAL = "partial"  # the named effects explain part of the error, the rest is outside the catalog
    DOES_NOT_FIT = "does_not_fit"  # the model, even with the catalog's effects, is far from the damper
    UNEXPLAINED = "unexplained"  # above the floor, and no effect explains it


def right(expected: Collection[str], verdict: str | None, named: Sequence[str], first: bool = False) -> bool:
    """Whether `verdict` with the effects `named` (in summary.json's order) is right for a record
    that hid the effects `expected` (module docstring). `verdict` may be any string (or None): one
    that is not a Verdict, such as a failed run's, is never right."""
    if not expected:
        return verdict == Verdict.NONE and not named
    if verdict != Verdict.EFFECT or not all(e in named for e in expected):
        return False
    return not first or set(named[:len(expected)]) == set(expected)
