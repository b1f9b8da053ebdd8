"""The Franka Panda with its gripper, read from the robosuite 1.5.2 asset files.

The robot and gripper XML files come from the robosuite wheel (installed with
``pip install --no-deps robosuite==1.5.2``). robosuite itself is never imported: its folder is
located with :func:`importlib.util.find_spec`, which does not execute the package.

Changes made to the robosuite model so it suits a position-controlled simulation:

* the arm's torque motors are replaced by joint position servos (``kp``/``kv`` per joint) and every
  robot body gets ``gravcomp=1`` (gravity compensation, like the real Panda's controller);
* collision meshes move to geom group 3 (not rendered by default; a fast low-poly stand-in for
  the visual meshes when a renderer swaps groups 1 and 3) and collide only with the environment
  (``contype=2, conaffinity=1``: no self-collision, contact with every ``contype=1`` geom);
* sites move to group 5 (hidden in images);
* the end-effector site ``ee_site`` sits between the finger pads; its local +z is the approach
  (pointing) axis and the fingers close along its local x axis.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import Final

import mujoco

from voxposer.errors import MissingAssetError

#: Prefix of every robot element once attached into a scene by :func:`add_panda`.
PREFIX: Final = "panda_"
#: Names of the seven arm joints, base to wrist (in a scene built by :func:`add_panda`).
ARM_JOINTS: Final = tuple(f"{PREFIX}joint{i}" for i in range(1, 8))
#: Names of the two finger slide joints (each 0..0.04 m; the second one is negated).
FINGER_JOINTS: Final = (f"{PREFIX}hand_finger_joint1", f"{PREFIX}hand_finger_joint2")
#: Arm servo actuators, in the order of :data:`ARM_JOINTS`.
ARM_ACTUATORS: Final = tuple(f"{j}_servo" for j in ARM_JOINTS)
#: Finger servo actuators, in the order of :data:`FINGER_JOINTS`.
FINGER_ACTUATORS: Final = (
    f"{PREFIX}hand_gripper_finger_joint1",
    f"{PREFIX}hand_gripper_finger_joint2",
)
#: The end-effector site (grasp centre between the finger pads).
EE_SITE: Final = f"{PREFIX}hand_ee_site"
#: Root body of the robot.
BASE_BODY: Final = f"{PREFIX}base"
_HAND_PREFIX: Final = "hand_"
#: Collision bits: robot geoms hit the environment but not each other.
ROBOT_CONTYPE: Final = 2
ROBOT_CONAFFINITY: Final = 1
#: Geom group of collision meshes (hidden by MuJoCo's default visualisation options).
COLLISION_GROUP: Final = 3
#: Site group that no camera renders.
HIDDEN_SITE_GROUP: Final = 5

#: Joint position servo gains per arm joint: (kp [N m/rad], kv [N m s/rad], torque limit [N m]).
_SERVO: Final = (
    (4500.0, 450.0, 87.0),
    (4500.0, 450.0, 87.0),
    (3500.0, 350.0, 87.0),
    (3500.0, 350.0, 87.0),
    (2000.0, 200.0, 12.0),
    (2000.0, 200.0, 12.0),
    (2000.0, 200.0, 12.0),
)
#: Gripper servo: gain [N/m] and force limit [N] per finger.
GRIPPER_KP: Final = 1000.0
GRIPPER_FORCE: Final = 40.0
#: Finger travel [m] per finger (0 = closed, 0.04 = open).
FINGER_OPEN: Final = 0.04


def robosuite_assets_dir() -> Path:
    """Folder ``robosuite/models/assets`` of the installed robosuite wheel (not imported)."""
    spec = importlib.util.find_spec("robosuite")
    if spec is None or not spec.submodule_search_locations:
        raise MissingAssetError(
            "the Panda model files come from the robosuite wheel; install them with "
            "`pip install --no-deps robosuite==1.5.2`"
        )
    root = Path(next(iter(spec.submodule_search_locations))) / "models" / "assets"
    if not (root / "robots" / "panda" / "robot.xml").is_file():
        raise MissingAssetError(f"robosuite is installed but {root}/robots/panda/robot.xml is missing")
    return root


def _absolute_mesh_paths(spec: mujoco.MjSpec, folder: Path) -> None:
    for mesh in spec.meshes:
        mesh.file = str((folder / mesh.file).resolve())
    spec.meshdir = ""


def panda_spec(*, with_fingers: bool = True) -> mujoco.MjSpec:
    """A spec of the Panda arm with its gripper attached, base body ``base`` at the origin.

    Args:
        with_fingers: if False the finger joints and their actuators are removed (a 7-DoF model
            for inverse kinematics, in which nothing but the arm can move).

    Returns:
        An uncompiled :class:`mujoco.MjSpec` (attach it into a scene or compile it alone).
    """
    assets = robosuite_assets_dir()
    robot_xml = assets / "robots" / "panda" / "robot.xml"
    gripper_xml = assets / "grippers" / "panda_gripper.xml"
    robot = mujoco.MjSpec.from_file(str(robot_xml))
    gripper = mujoco.MjSpec.from_file(str(gripper_xml))
    _absolute_mesh_paths(robot, robot_xml.parent)
    _absolute_mesh_paths(gripper, gripper_xml.parent)

    for actuator in list(robot.actuators):
        robot.delete(actuator)
    for sensor in list(gripper.sensors):
        gripper.delete(sensor)
    for camera in list(robot.cameras):
        robot.delete(camera)

    eef = gripper.body("eef")
    # Grasp centre: midway along the finger pads (pad centres are 0.0934 m below the hand base).
    eef.add_site(name="ee_site", pos=[0.0, 0.0, -0.0036], size=[0.005, 0.005, 0.005])
    if not with_fingers:
        for actuator in list(gripper.actuators):
            gripper.delete(actuator)
        for name in ("finger_joint1", "finger_joint2"):
            gripper.delete(gripper.joint(name))

    frame = robot.body("right_hand").add_frame()
    robot.attach(gripper, frame=frame, prefix=_HAND_PREFIX)

    for k, (kp, kv, limit) in enumerate(_SERVO):
        joint_name = f"joint{k + 1}"
        joint = robot.joint(joint_name)
        joint.armature = 0.1
        act = robot.add_actuator(name=f"{joint_name}_servo", target=joint_name)
        act.trntype = mujoco.mjtTrn.mjTRN_JOINT
        act.set_to_position(kp=kp, kv=kv)
        act.ctrllimited = 1
        act.ctrlrange = list(joint.range)
        act.forcelimited = 1
        act.forcerange = [-limit, limit]
    if with_fingers:
        for act in robot.actuators:
            if act.target.endswith(("finger_joint1", "finger_joint2")):
                act.gainprm[0] = GRIPPER_KP
                act.biasprm[1] = -GRIPPER_KP
                act.forcerange = [-GRIPPER_FORCE, GRIPPER_FORCE]

    for body in robot.bodies:
        body.gravcomp = 1.0
    for geom in robot.geoms:
        if geom.contype == 0 and geom.conaffinity == 0:
            continue  # visual mesh: rendered, never collides
        geom.group = COLLISION_GROUP
        geom.rgba = [0.92, 0.92, 0.92, 1.0] if geom.type == mujoco.mjtGeom.mjGEOM_MESH else [
            0.3, 0.3, 0.3, 1.0]
        geom.contype = ROBOT_CONTYPE
        geom.conaffinity = ROBOT_CONAFFINITY
    for site in robot.sites:
        site.group = HIDDEN_SITE_GROUP
    _name_unnamed(robot)
    return robot


def _name_unnamed(spec: mujoco.MjSpec) -> None:
    """Give every geom a name (``<body>_geom<k>``) so each model element is addressable."""
    counts: dict[str, int] = {}
    for geom in spec.geoms:
        if geom.name:
            continue
        body = geom.parent.name or "world"
        k = counts.get(body, 0)
        counts[body] = k + 1
        geom.name = f"{body}_visual{k}"


def add_panda(
    scene: mujoco.MjSpec, base_pos: tuple[float, float, float], *, with_fingers: bool = True
) -> None:
    """Attach the Panda (see :func:`panda_spec`) to ``scene``'s world body, facing +x.

    Args:
        scene: the spec to modify in place.
        base_pos: position of the robot base (bottom of link0) in the world [m], shape (3,).
        with_fingers: keep the finger joints (False for the IK-only model).
    """
    robot = panda_spec(with_fingers=with_fingers)
    frame = scene.worldbody.add_frame(pos=list(base_pos))
    scene.attach(robot, frame=frame, prefix=PREFIX)


def robot_only_model(base_pos: tuple[float, float, float]) -> mujoco.MjModel:
    """A compiled 7-DoF model holding only the arm (no fingers, no scene): for inverse kinematics.

    Its world frame matches the scene's, so end-effector targets are given in world coordinates.
    """
    spec = mujoco.MjSpec()
    add_panda(spec, base_pos, with_fingers=False)
    return spec.compile()
