"""The evaluation protocol: which seeds and which instructions a benchmark run uses.

Seed sets (``--seeds``), fixed here and nowhere else:

* ``dev`` — seeds 0 … 9,999: develop, tune tolerances and prompts, debug on these.
* ``test`` — seeds 100,000 … 109,999, disjoint from ``dev``: report these, never tune on them.

``--seeds test --episodes 20`` runs seeds 100000 … 100019 for every task and attribute split.
An ad-hoc run (``--seed N --episodes K``) runs seeds N … N+K−1 and is labelled ``adhoc``.

Instruction splits (``--instructions``, the paper's SI/UI of Table 2):

* ``seen`` — the prompts keep their few-shot examples of the task being evaluated.
* ``unseen`` — leave-one-task-out: every few-shot example tagged with the evaluated task is
  removed from every prompt (``LMPConfig.held_out_task``). Reference programs are hand-written,
  so ``unseen`` is meaningless (and refused) with them.
"""

from __future__ import annotations

from typing import Final, NamedTuple

from voxposer.errors import ConfigError


class SeedSet(NamedTuple):
    """A named, contiguous range of episode seeds: ``first`` … ``first + size − 1``."""

    name: str
    first: int
    size: int

    @property
    def last(self) -> int:
        """The last seed of the set (inclusive)."""
        return self.first + self.size - 1

    def seeds(self, episodes: int) -> range:
        """The first ``episodes`` seeds of the set; raises ConfigError when it has fewer."""
        if not 1 <= episodes <= self.size:
            raise ConfigError(f"seed set {self.name!r} holds {self.size} seeds "
                              f"({self.first}–{self.last}); got episodes={episodes}")
        return range(self.first, self.first + episodes)

    def holds(self, seed: int) -> bool:
        """Whether ``seed`` lies in the set."""
        return self.first <= seed <= self.last


DEV_SEEDS: Final = SeedSet("dev", 0, 10_000)
TEST_SEEDS: Final = SeedSet("test", 100_000, 10_000)
#: seed-set name → set (the values ``--seeds`` accepts).
SEED_SETS: Final[dict[str, SeedSet]] = {s.name: s for s in (DEV_SEEDS, TEST_SEEDS)}
#: the label of runs whose seeds were given by ``--seed N`` rather than a seed set.
ADHOC: Final = "adhoc"

#: the values ``--instructions`` accepts.
INSTRUCTION_SPLITS: Final[tuple[str, ...]] = ("seen", "unseen", "paraphrased", "vague-relational")
#: the split whose instructions say quantities vaguely and objects by relation.
VAGUE_RELATIONAL: Final = "vague-relational"
#: instruction split → what reports append to a group's name.
INSTRUCTION_LABELS: Final[dict[str, str]] = {
    "seen": "", "unseen": ", unseen instructions", "paraphrased": ", paraphrased instructions",
    VAGUE_RELATIONAL: ", vague and relational instructions"}


def get_seed_set(name: str) -> SeedSet:
    """The seed set called ``name``; raises ConfigError listing the known sets."""
    if name not in SEED_SETS:
        raise ConfigError(f"unknown seed set {name!r}; seed sets are: "
                          + ", ".join(f"{s.name} ({s.first}–{s.last})" for s in SEED_SETS.values()))
    return SEED_SETS[name]


def check_instructions(split: str) -> str:
    """``split`` if it is an instruction split; raises ConfigError listing them otherwise."""
    if split not in INSTRUCTION_SPLITS:
        raise ConfigError(f"unknown instruction split {split!r}; choose one of: "
                          f"{', '.join(INSTRUCTION_SPLITS)}")
    return split
