"""Dev check with a second set of extra dev phrasings written for it (never the test ones, nor
the dev or extra_dev7 ones, asserted below): the dev positions of the named tasks' phrasings
replaced in this process, bench run in process."""
import sys
from voxposer.bench import paraphrases as P

EXTRA = {
    "move_to_pos_staying_on_preposition": (
        "can you go to the [pos]? stay on the [preposition] the [obj] as you do",
        "on your way to the [pos], keep to the [preposition] the [obj]",
        "I need the gripper at the [pos]; it must stay on the [preposition] the [obj]",
        "move over to the [pos] and don't leave the [preposition] the [obj]",
        "steer the hand to the [pos], keeping it on the [preposition] the [obj]",
        "go towards the [pos] while remaining on the [preposition] the [obj]",
    ),
    "move_to_pos_velocity_in_region": (
        "can you go to the [pos]? move at [velocity] over the [region]",
        "on your way to the [pos], use [velocity] on the [region]",
        "I need the gripper at the [pos]; go at [velocity] while over the [region]",
        "move over to the [pos], and over the [region] change your speed to [velocity]",
        "steer the hand to the [pos], with [velocity] above the [region]",
        "go towards the [pos]; whenever you are over the [region] use [velocity]",
    ),
}
for task, dev in EXTRA.items():
    assert not set(dev) & set(P.PARAPHRASES[task]), task
    test = P.PARAPHRASES[task][1::2]
    P.PARAPHRASES[task] = tuple(x for pair in zip(dev, test) for x in pair)
if __name__ == "__main__":
    from voxposer.cli import main
    sys.argv = ["voxposer", *sys.argv[1:]]
    sys.exit(main())
