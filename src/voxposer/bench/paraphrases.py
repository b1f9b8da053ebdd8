"""Reworded instructions for every task: the paraphrase split (``--instructions paraphrased``).

Each task has twelve phrasings a person might use — other verbs, word order, politeness, spelled
out units — with the same slots as its template, so the task's own check still judges them.
Even-numbered phrasings are the **dev** phrasings (for prompt and program work), odd-numbered
ones the **test** phrasings (for reported figures only); an episode on a dev seed gets a dev
phrasing, one on a test seed a test phrasing, chosen by its seed.
"""

from __future__ import annotations

import re
from typing import Final, Literal

from voxposer.errors import ConfigError

PhrasingSplit = Literal["dev", "test"]
_SLOT = re.compile(r"\[(\w+)\]")

#: task name → twelve phrasings (slots in brackets, as in the task's template).
PARAPHRASES: Final[dict[str, tuple[str, ...]]] = {
    "move_to_preposition": (
        "go to the [preposition] the [obj]",
        "could you move the gripper to the [preposition] the [obj]",
        "put your hand at the [preposition] the [obj]",
        "bring the end effector to the [preposition] the [obj]",
        "please go to the [preposition] the [obj]",
        "move your gripper over to the [preposition] the [obj]",
        "head to the [preposition] the [obj]",
        "place the gripper at the [preposition] the [obj]",
        "I want the gripper at the [preposition] the [obj]",
        "position the hand at the [preposition] the [obj]",
        "get to the [preposition] the [obj], please",
        "take the end effector to the [preposition] the [obj]",
    ),
    "move_to_pos_staying_on_preposition": (
        "go to the [pos], keeping to the [preposition] the [obj] on the way",
        "move the gripper to the [pos] and stay on the [preposition] the [obj] while you go",
        "while staying on the [preposition] the [obj], move to the [pos]",
        "head for the [pos]; pass on the [preposition] the [obj]",
        "please move to the [pos], staying on the [preposition] the [obj]",
        "bring the hand to the [pos] while keeping on the [preposition] the [obj]",
        "go over to the [pos] and keep to the [preposition] the [obj] as you pass it",
        "move to the [pos], going by the [preposition] the [obj]",
        "take the gripper to the [pos] but stay on the [preposition] the [obj]",
        "travel to the [pos] on the [preposition] the [obj]",
        "get to the [pos] while you stay on the [preposition] the [obj]",
        "move the end effector to the [pos], keeping on the [preposition] the [obj]",
    ),
    "move_to_pos_velocity_near_obj": (
        "go to the [pos] and move at [velocity] whenever you are within [dist]cm of the [obj]",
        "move the gripper to the [pos]; within [dist] cm of the [obj], go at [velocity]",
        "when you are closer than [dist]cm to the [obj], move at [velocity]; go to the [pos]",
        "head to the [pos], switching to [velocity] within [dist] centimeters of the [obj]",
        "please move to the [pos], at [velocity] when within [dist]cm from the [obj]",
        "bring the hand to the [pos]; near the [obj] (within [dist]cm) use [velocity]",
        "travel to the [pos] and, within [dist] cm of the [obj], move at [velocity]",
        "go to the [pos], moving at [velocity] whenever the [obj] is within [dist]cm",
        "move to the [pos]; inside [dist]cm of the [obj] your speed is [velocity]",
        "take the gripper to the [pos] at [velocity] while within [dist]cm of the [obj]",
        "get to the [pos], going at [velocity] when you come within [dist] cm of the [obj]",
        "move the end effector to the [pos] and use [velocity] within [dist]cm of the [obj]",
    ),
    "close_drawer": (
        "push the [deixis] drawer shut",
        "shut the [deixis] drawer by pushing it",
        "please close the [deixis] drawer",
        "push the [deixis] drawer closed",
        "could you close the [deixis] drawer by pushing it in",
        "close the [deixis] drawer",
        "push in the [deixis] drawer",
        "shut the [deixis] drawer",
        "the [deixis] drawer is open; push it closed",
        "close up the [deixis] drawer by pushing",
        "push the [deixis] drawer until it is closed",
        "go and shut the [deixis] drawer",
    ),
    "push_along_line": (
        "slide the [obj] along the [line]",
        "push the [obj] all the way along the [line]",
        "move the [obj] along the [line] by pushing it",
        "please push the [obj] along the [line]",
        "push the [obj] so it travels along the [line]",
        "slide the [obj] down the [line]",
        "keep the [obj] on the [line] while you push it along",
        "push the [obj] along the length of the [line]",
        "nudge the [obj] along the [line]",
        "could you push the [obj] along the [line]",
        "push the [obj] following the [line]",
        "move the [obj] along the [line]",
    ),
    "grasp_at_velocity": (
        "pick up the [obj] at [velocity]",
        "grab the [obj] from the table at [velocity]",
        "at [velocity], grasp the [obj]",
        "please pick the [obj] up off the table at [velocity]",
        "grasp the [obj] at [velocity]",
        "take the [obj] from the table, moving at [velocity]",
        "lift the [obj] off the table at [velocity]",
        "get hold of the [obj] at [velocity]",
        "pick up the [obj] from the table, going at [velocity]",
        "grab the [obj] at [velocity]",
        "could you grasp the [obj] at [velocity]",
        "using [velocity], pick up the [obj]",
    ),
    "drop_to_pos": (
        "drop the [obj] at the [pos]",
        "let the [obj] fall onto the [pos]",
        "put the [obj] down at the [pos]",
        "please drop the [obj] on the [pos]",
        "release the [obj] over the [pos]",
        "drop the [obj] onto the [pos]",
        "take the [obj] to the [pos] and drop it there",
        "drop the [obj] off at the [pos]",
        "bring the [obj] to the [pos] and let it go",
        "place the [obj] at the [pos] by dropping it",
        "could you drop the [obj] at the [pos]",
        "move the [obj] to the [pos] and release it",
    ),
    "push_stay_on_region": (
        "push the [obj] but keep it on the [region]",
        "push the [obj], making sure it stays on the [region]",
        "slide the [obj] while it stays on the [region]",
        "please push the [obj] and keep it on the [region]",
        "push the [obj] without letting it leave the [region]",
        "nudge the [obj] so that it stays on the [region]",
        "push the [obj] around but keep it on the [region]",
        "push the [obj]; it must stay on the [region]",
        "move the [obj] by pushing, keeping it on the [region]",
        "push the [obj] while keeping it on the [region]",
        "could you push the [obj] and let it stay on the [region]",
        "push the [obj] and make sure it remains on the [region]",
    ),
    "move_to_region": (
        "go to the [region]",
        "move the gripper to the [region]",
        "please move over to the [region]",
        "head to the [region]",
        "bring the hand to the [region]",
        "take the end effector to the [region]",
        "move your gripper to the [region]",
        "get over to the [region]",
        "could you go to the [region]",
        "position the gripper on the [region]",
        "move to the [region], please",
        "travel to the [region]",
    ),
    "move_to_pos_min_distance": (
        "go to the [pos] and keep at least [dist]cm away from the [obj]",
        "move the gripper to the [pos], never coming within [dist] cm of the [obj]",
        "while keeping [dist]cm or more from the [obj], move to the [pos]",
        "head to the [pos] but stay at least [dist] centimeters from the [obj]",
        "please move to the [pos], staying at least [dist]cm from the [obj]",
        "bring the hand to the [pos] without getting closer than [dist]cm to the [obj]",
        "go to the [pos]; keep a distance of at least [dist] cm from the [obj]",
        "move to the [pos] and do not come closer than [dist]cm to the [obj]",
        "take the gripper to the [pos] and keep [dist]cm clear of the [obj]",
        "travel to the [pos], always at least [dist]cm from the [obj]",
        "get to the [pos] while staying [dist] cm or more away from the [obj]",
        "move the end effector to the [pos], keeping at least [dist]cm from the [obj]",
    ),
    "move_to_pos_velocity_in_region": (
        "go to the [pos] and move at [velocity] while on the [region]",
        "move the gripper to the [pos]; on the [region] go at [velocity]",
        "while you are over the [region], move at [velocity]; go to the [pos]",
        "head to the [pos], using [velocity] in the [region]",
        "please move to the [pos] at [velocity] in the [region]",
        "bring the hand to the [pos], and in the [region] move at [velocity]",
        "travel to the [pos]; when in the [region], your speed is [velocity]",
        "go to the [pos], moving at [velocity] through the [region]",
        "move to the [pos] and go at [velocity] whenever you are in the [region]",
        "take the gripper to the [pos], at [velocity] inside the [region]",
        "get to the [pos], moving at [velocity] when over the [region]",
        "move the end effector to the [pos] and keep [velocity] in the [region]",
    ),
    "push_to_pos_avoid_obstacle": (
        "push the [obj] to the [pos] and keep it away from the [obstacle]",
        "slide the [obj] to the [pos] without going near the [obstacle]",
        "while avoiding the [obstacle], push the [obj] to the [pos]",
        "please push the [obj] to the [pos], staying clear of the [obstacle]",
        "push the [obj] over to the [pos] but keep away from the [obstacle]",
        "move the [obj] to the [pos] by pushing it, avoiding the [obstacle]",
        "push the [obj] to the [pos]; stay away from the [obstacle]",
        "nudge the [obj] to the [pos] while keeping clear of the [obstacle]",
        "push the [obj] to the [pos] and go around the [obstacle]",
        "could you push the [obj] to the [pos] while avoiding the [obstacle]",
        "push the [obj] to the [pos], keeping it well away from the [obstacle]",
        "slide the [obj] to the [pos] and steer clear of the [obstacle]",
    ),
    "push_to_pos": (
        "slide the [obj] to the [pos]",
        "push the [obj] over to the [pos]",
        "please push the [obj] to the [pos]",
        "move the [obj] to the [pos] by pushing it",
        "nudge the [obj] to the [pos]",
        "push the [obj] until it is at the [pos]",
        "could you push the [obj] to the [pos]",
        "shove the [obj] to the [pos]",
        "push the [obj] all the way to the [pos]",
        "get the [obj] to the [pos] by pushing it",
        "slide the [obj] over to the [pos]",
        "push the [obj] so it ends up at the [pos]",
    ),
}


def phrasings(task: str, split: PhrasingSplit) -> tuple[str, ...]:
    """The dev (even-numbered) or test (odd-numbered) phrasings of ``task``.

    Raises:
        ConfigError: an unknown task or split (listing the known ones).
    """
    if task not in PARAPHRASES:
        raise ConfigError(f"task {task!r} has no paraphrases; tasks with paraphrases: "
                          f"{', '.join(PARAPHRASES)}")
    if split not in ("dev", "test"):
        raise ConfigError(f"unknown phrasing split {split!r}; splits are: dev, test")
    return PARAPHRASES[task][0 if split == "dev" else 1::2]


def paraphrase(task: str, attrs: dict[str, str], split: PhrasingSplit, seed: int) -> str:
    """The instruction of an episode: phrasing ``seed mod 6`` of ``split``, slots filled."""
    options = phrasings(task, split)
    return _SLOT.sub(lambda m: attrs[m.group(1)], options[seed % len(options)])


__all__ = ["PARAPHRASES", "PhrasingSplit", "paraphrase", "phrasings"]
