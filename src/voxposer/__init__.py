"""VoxPoser: language model programs compose 3D voxel value maps that a planner turns into motion.

Package layout follows the paper's Figure 2: ``lmp`` (programs, prompts, LLM backends, sandbox)
→ ``valuemaps`` (grid, maps, cost) → ``planning`` (path search, trajectory) → ``control``
(closed-loop executor), with ``envs`` (MuJoCo world) and ``perception`` feeding ``detect()``.
"""

from voxposer.errors import VoxPoserError

__all__ = ["VoxPoserError", "__version__"]
__version__ = "0.1.0"
