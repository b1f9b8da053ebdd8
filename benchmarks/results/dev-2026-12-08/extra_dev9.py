"""Dev check with a third set of extra dev phrasings written for it (never the test ones, nor
the dev, extra_dev7 or extra_dev8 ones, asserted below) for the two tasks v4.2, v4.3 and v4.7
left short of the paraphrase target: the dev positions of the named tasks' phrasings replaced in
this process, bench run in process."""
import sys
from pathlib import Path

from voxposer.bench import paraphrases as P

EXTRA = {
    "move_to_pos_staying_on_preposition": (
        "head for the [pos], and stay on the [preposition] the [obj] the whole way",
        "please take the gripper to the [pos]; keep on the [preposition] the [obj]",
        "the end effector should end at the [pos] and remain on the [preposition] the [obj]",
        "get to the [pos] without leaving the [preposition] the [obj]",
        "move your hand to the [pos], staying on the [preposition] the [obj] throughout",
        "reach the [pos] but keep to the [preposition] the [obj] on the way",
    ),
    "move_to_pos_velocity_near_obj": (
        "head for the [pos], and go at [velocity] whenever you are within [dist]cm of the [obj]",
        "please take the gripper to the [pos]; near the [obj] (closer than [dist]cm) use [velocity]",
        "the end effector should end at the [pos], moving at [velocity] within [dist]cm of the [obj]",
        "get to the [pos], slowing or speeding to [velocity] once [dist]cm from the [obj]",
        "move your hand to the [pos] and use [velocity] inside [dist]cm of the [obj]",
        "reach the [pos]; when the [obj] is less than [dist]cm away, move at [velocity]",
    ),
}
HERE = Path(__file__).resolve().parent
OLDER = [HERE.parent / "dev-2026-12-06h/extra_dev7.py", HERE.parent / "dev-2026-12-07/extra_dev8.py"]
for task, dev in EXTRA.items():
    assert not set(dev) & set(P.PARAPHRASES[task]), task
    assert not any(p in f.read_text() for f in OLDER for p in dev), task
    test = P.PARAPHRASES[task][1::2]
    P.PARAPHRASES[task] = tuple(x for pair in zip(dev, test) for x in pair)
if __name__ == "__main__":
    from voxposer.cli import main
    sys.argv = ["voxposer", *sys.argv[1:]]
    sys.exit(main())
