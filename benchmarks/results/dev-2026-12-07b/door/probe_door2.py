import math, sys, numpy as np
sys.path.insert(0, "/work/main")
from scipy.spatial.transform import Rotation
from tests.envs.articulated.articulated_motions import grasp_handle, follow
from voxposer.envs.articulated import ArticulatedWorld
w = ArticulatedWorld("door")
deg = lambda st: {k: round(math.degrees(v), 1) for k, v in st.items()}
for press in (0.06, 0.07):
    for turn in (False, True):
        w.reset(np.random.default_rng(10))
        n = Rotation.from_euler("z", w.placement.object_yaw).apply([1.0, 0, 0])
        pos, rot = grasp_handle(w)
        for k in range(1, 4):
            follow(w, pos - [0, 0, press * k / 3], rot, max_steps=20)
        st0 = deg(w.articulation_state())
        p = pos - [0, 0, press]
        trace = []
        for k in range(1, 11):
            r = rot
            if turn:
                r = Rotation.from_rotvec([0, 0, w.articulation_state()["door_angle"]]) * rot
            follow(w, p - 0.025 * k * n, r, max_steps=20)
            trace.append(deg(w.articulation_state())["door_angle"])
        print(f"press {press*100:.0f} cm turn={turn}: after press {st0}; door angle per 2.5 cm: {trace}; {w.success()[0]}")
