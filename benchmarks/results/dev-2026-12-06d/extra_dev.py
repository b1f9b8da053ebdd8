"""Dev check with extra dev phrasings written for it (never the test ones): the dev
positions of the named tasks' phrasings replaced in this process, bench run in process."""
import sys
from voxposer.bench import paraphrases as P

EXTRA = {
    "move_to_pos_min_distance": (
        "make your way to the [pos] without ever getting closer than [dist]cm to the [obj]",
        "reach the [pos]; the [obj] should never be nearer than [dist] cm to your hand",
        "go to the [pos], and don't let the gripper come within [dist]cm of the [obj]",
        "I need the hand at the [pos], giving the [obj] a berth of [dist] cm or more",
        "navigate to the [pos] maintaining a gap of no less than [dist]cm from the [obj]",
        "travel over to the [pos] with at least [dist] cm between you and the [obj]",
    ),
    "move_to_pos_velocity_near_obj": (
        "make your way to the [pos], and whenever you're inside [dist]cm of the [obj] move at [velocity]",
        "reach the [pos]; near the [obj] (closer than [dist] cm) use [velocity]",
        "head over to the [pos]. Within [dist]cm of the [obj], switch to [velocity]",
        "go to the [pos] - once you are [dist] cm or less from the [obj], travel at [velocity]",
        "navigate to the [pos], moving at [velocity] while within [dist]cm of the [obj]",
        "the gripper should go to the [pos]; use [velocity] in the [dist]cm around the [obj]",
    ),
}
for task, dev in EXTRA.items():
    test = P.PARAPHRASES[task][1::2]
    assert not set(dev) & set(test)
    P.PARAPHRASES[task] = tuple(x for pair in zip(dev, test) for x in pair)
from voxposer.cli import main
sys.argv = ["voxposer", *sys.argv[1:]]
sys.exit(main())
