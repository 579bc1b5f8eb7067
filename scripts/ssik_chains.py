"""ssik's prebuilt arms as URDFs: the chain ssik baked for an arm, read by ``kin`` as a user's URDF.

Shared by ``bench_ik_6r.py``, ``bench_ik_7r_branches.py`` and ``tests/scripts/test_ssik_chains_6r.py``.
Not a script: helpers only (ssik is a peer, installed with the ``[bench]`` extra).
"""

from __future__ import annotations

import importlib
from pathlib import Path
from types import ModuleType

import numpy as np

#: ssik's prebuilt 6R arms that none of our special 6R families fits (the general 6R closed
#: form answers): ``<maker>.<arm>_ik`` module names under ``ssik.prebuilt``.
GENERAL_6R = (
    "agilex.piper_ik", "doosan.m0609_ik", "doosan.m1013_ik", "fanuc.crx10ia_ik",
    "fanuc.crx10ial_ik", "fanuc.crx10ialp_ik", "fanuc.crx20ial_ik", "fanuc.crx30ia_ik",
    "fanuc.crx3ia_ik", "fanuc.crx5ia_ik", "i2rt.big_yam_ik", "i2rt.yam_ik",
    "kinova.gen3_lite_ik", "kinova.jaco2_ik", "rokae.xmatecr7_ik", "rokae.xmatesr3_ik",
    "ufactory.xarm6_ik", "yaskawa.hc10_ik",
)  # fmt: skip


def ssik_urdf(module: ModuleType, name: str) -> str:
    """The chain ssik baked for an arm (joint origins, axes, limits, tool) as URDF text.

    Joint ``i``'s origin is ``T_right(i-1) T_left(i)`` of ssik's product-of-exponentials form;
    a joint without limits is ``continuous``; the tool is a fixed joint to ssik's ``EE_LINK``.
    """
    from scipy.spatial.transform import Rotation

    def origin(T: np.ndarray) -> str:
        xyz = " ".join(repr(float(v)) for v in T[:3, 3])
        rpy = " ".join(repr(float(v)) for v in Rotation.from_matrix(T[:3, :3]).as_euler("xyz"))
        return f'<origin xyz="{xyz}" rpy="{rpy}"/>'

    lines = [f'<robot name="{name}">', f'<link name="{module.BASE_LINK}"/>']
    parent, before = module.BASE_LINK, np.eye(4)
    for i, joint in enumerate(module._JOINT_NAMES):
        child = f"{name}_link{i + 1}"
        limits = module._JOINT_LIMITS[i]
        kind = "continuous" if limits is None else "revolute"
        limit = (
            ""
            if limits is None
            else f'<limit lower="{limits[0]!r}" upper="{limits[1]!r}" effort="1" velocity="1"/>'
        )
        axis = " ".join(repr(float(v)) for v in module._JOINT_AXES[i])
        lines += [
            f'<link name="{child}"/>',
            f'<joint name="{joint}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f'{origin(before @ module._JOINT_T_LEFTS[i])}<axis xyz="{axis}"/>{limit}</joint>',
        ]
        parent, before = child, module._JOINT_T_RIGHTS[i]
    lines += [
        f'<link name="{module.EE_LINK}"/>',
        f'<joint name="tool" type="fixed"><parent link="{parent}"/><child link="{module.EE_LINK}"/>'
        f"{origin(before)}</joint>",
        "</robot>",
    ]
    return "\n".join(lines) + "\n"


def write_ssik_arm(module_name: str, folder: Path) -> tuple[Path, ModuleType]:
    """Ssik's prebuilt module ``module_name`` and its chain written as ``folder/<arm>.urdf``."""
    module = importlib.import_module(f"ssik.prebuilt.{module_name}")
    name = module_name.split(".")[-1].removesuffix("_ik")
    path = folder / f"{name}.urdf"
    path.write_text(ssik_urdf(module, name))
    return path, module


def distinct_mod_2pi(solutions: np.ndarray, tol: float = 1e-6) -> int:
    """How many of the joint vectors (k, n) [rad] differ by more than ``tol`` modulo 2 pi.

    ssik returns every ``2 pi`` copy inside the limits (32 on an xArm6 pose of 4 branches);
    ours one per branch: counts are compared modulo 2 pi.
    """
    kept: list[np.ndarray] = []
    for q in np.atleast_2d(np.asarray(solutions, dtype=float)):
        if not q.size:
            continue
        if all(np.abs(np.angle(np.exp(1j * (q - other)))).max() > tol for other in kept):
            kept.append(q)
    return len(kept)
