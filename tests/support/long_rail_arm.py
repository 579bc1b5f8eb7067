"""A redundant arm on a mobile base: Panda on a turning base and a +-999,999 m rail (URDF text).

The Robotics Toolbox's Frankie as its URDF declares it: a revolute and a prismatic base joint with
+-999,999 limits, then Panda's seven joints (franka_description's joint origins and limits, no
meshes). With ``spheres``, each Panda link and the flange carry a collision sphere of that radius
[m] at their origin (for the collision checks; no pair of neighbouring links' spheres is checked
when the caller passes :func:`srdf_text`).
"""

from __future__ import annotations

import math

HALF_PI = math.pi / 2
#: Panda's joints: (origin xyz [m], origin roll [rad], lower, upper [rad]), franka_description's.
PANDA = (
    ((0.0, 0.0, 0.333), 0.0, -2.8973, 2.8973),
    ((0.0, 0.0, 0.0), -HALF_PI, -1.7628, 1.7628),
    ((0.0, -0.316, 0.0), HALF_PI, -2.8973, 2.8973),
    ((0.0825, 0.0, 0.0), HALF_PI, -3.0718, -0.0698),
    ((-0.0825, 0.384, 0.0), -HALF_PI, -2.8973, 2.8973),
    ((0.0, 0.0, 0.0), HALF_PI, -0.0175, 3.7525),
    ((0.088, 0.0, 0.0), HALF_PI, -2.8973, 2.8973),
)
#: The links that carry a sphere when asked.
SPHERE_LINKS = ("link4", "link6", "flange")


def _joint(name: str, kind: str, parent: str, child: str, xyz: str, roll: float, limits: str):
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}" rpy="{roll!r} 0 0"/><axis xyz="{"1 0 0" if kind == "prismatic" else "0 0 1"}"/>'
        f'<limit lower="{limits.split()[0]}" upper="{limits.split()[1]}" effort="1" velocity="1"/>'
        "</joint>"
    )


def _link(name: str, spheres: float | None) -> str:
    if spheres is None or name not in SPHERE_LINKS:
        return f'<link name="{name}"/>'
    return (
        f'<link name="{name}"><collision><geometry><sphere radius="{spheres!r}"/></geometry>'
        "</collision></link>"
    )


def frankie_urdf(spheres: float | None = None) -> str:
    """Panda on a revolute and a prismatic base joint of +-999,999 (rad, m), tool at flange."""
    links = ["base0", "base1", "rail", *(f"link{i}" for i in range(1, 8)), "flange"]
    joints = [
        _joint("base_turn", "revolute", "base0", "base1", "0 0 0", 0.0, "-999999 999999"),
        _joint("base_rail", "prismatic", "base1", "rail", "0 0 0", 0.0, "-999999 999999"),
        '<joint name="mount" type="fixed"><parent link="rail"/><child link="link0"/>'
        '<origin xyz="0.15 0 0.38"/></joint>',
    ]
    for i, (xyz, roll, lower, upper) in enumerate(PANDA, start=1):
        parent = f"link{i - 1}"
        joints.append(
            _joint(
                f"joint{i}",
                "revolute",
                parent,
                f"link{i}",
                " ".join(map(str, xyz)),
                roll,
                f"{lower} {upper}",
            )
        )
    joints.append(
        '<joint name="flange_joint" type="fixed"><parent link="link7"/><child link="flange"/>'
        '<origin xyz="0 0 0.107"/></joint>'
    )
    body = "".join(_link(name, spheres) for name in [*links, "link0"]) + "".join(joints)
    return f'<?xml version="1.0"?><robot name="frankie_kinematics">{body}</robot>'


def srdf_text() -> str:
    """An SRDF leaving out the sphere pairs of :data:`SPHERE_LINKS` (neighbours on the chain)."""
    pairs = [(a, b) for i, a in enumerate(SPHERE_LINKS) for b in SPHERE_LINKS[i + 1 :]]
    body = "".join(
        f'<disable_collisions link1="{a}" link2="{b}" reason="Adjacent"/>' for a, b in pairs
    )
    return f'<?xml version="1.0"?><robot name="frankie_kinematics">{body}</robot>'
