import math, sys, numpy as np
sys.path.insert(0, "/work/main")
from scipy.spatial.transform import Rotation
from tests.envs.articulated.articulated_motions import grasp_handle, turn_grip, follow
from voxposer.envs.articulated import ArticulatedWorld
w = ArticulatedWorld("door")
for seed in (10, 11):
    w.reset(np.random.default_rng(seed))
    n = Rotation.from_euler("z", w.placement.object_yaw).apply([1.0, 0, 0])
    pose = grasp_handle(w)
    pressed = turn_grip(w, "handle_angle", pose, 40.0, step=5.0)
    st = w.articulation_state(); print(seed, "after press", {k: round(math.degrees(v), 1) for k, v in st.items()})
    pos, rot = pressed
    for k in range(1, 11):  # straight pull, 2.5 cm a step
        follow(w, pos - 0.025 * k * n, rot, max_steps=20)
        st = w.articulation_state()
        print("  pull %4.1f cm" % (2.5 * k), {kk: round(math.degrees(v), 1) for kk, v in st.items()})
    print(seed, w.success())
