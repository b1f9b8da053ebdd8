"""Online dynamics learning with zero-shot trajectories as exploration prior (paper Sec. 3.4, 4.3).

VoxPoser's zero-shot run of "open the door" gives k trajectories τ₀ (end-effector waypoints,
:mod:`voxposer.learning.zero_shot`) and, per sub-task, the composed value map it planned on
(:mod:`voxposer.learning.task_cost`). The loop (:mod:`voxposer.learning.loop`) alternates data
collection — MPC through the current learned model, actions sampled around τ₀ ("with prior") or
uniformly over the action space ("without prior") — and training of an MLP
g_θ(o_t, a_t) → o_{t+1} (:class:`voxposer.planning.dynamics.mlp.MLPDynamics`).
"""
