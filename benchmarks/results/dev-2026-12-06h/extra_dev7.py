"""Dev check with extra dev phrasings written for it (never the test ones): the dev
positions of the named tasks' phrasings replaced in this process, bench run in process."""
import sys
from voxposer.bench import paraphrases as P

EXTRA = {
    "move_to_pos_staying_on_preposition": (
        "make your way to the [pos], staying to the [preposition] the [obj] the whole time",
        "reach the [pos]; your path should stay on the [preposition] the [obj]",
        "I'd like the hand at the [pos], passing the [obj] on its [preposition] side",
        "go to the [pos] but remain on the [preposition] the [obj] throughout",
        "navigate to the [pos] keeping yourself on the [preposition] the [obj]",
        "the gripper should end at the [pos], never leaving the [preposition] the [obj]",
    ),
    "move_to_pos_velocity_in_region": (
        "make your way to the [pos]; over the [region] travel at [velocity]",
        "reach the [pos], and use [velocity] whenever the hand is above the [region]",
        "go to the [pos]. In the [region], switch to [velocity]",
        "navigate to the [pos] moving at [velocity] while you cross the [region]",
        "head over to the [pos]; your speed over the [region] should be [velocity]",
        "I want you at the [pos], going at [velocity] within the [region]",
    ),
    "push_to_pos_avoid_obstacle": (
        "shove the [obj] to the [pos], but don't let it get near the [obstacle]",
        "push the [obj] until it reaches the [pos], keeping clear of the [obstacle]",
        "get the [obj] to the [pos] by pushing, and give the [obstacle] a wide berth",
        "I need the [obj] pushed to the [pos] without touching the [obstacle]",
        "move the [obj] to the [pos] with pushes, steering it around the [obstacle]",
        "push the [obj] toward the [pos], avoiding the [obstacle] along the way",
    ),
}
for task, dev in EXTRA.items():
    test = P.PARAPHRASES[task][1::2]
    assert not set(dev) & set(test)
    P.PARAPHRASES[task] = tuple(x for pair in zip(dev, test) for x in pair)
if __name__ == "__main__":
    from voxposer.cli import main
    sys.argv = ["voxposer", *sys.argv[1:]]
    sys.exit(main())
