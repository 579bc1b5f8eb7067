"""The one declaration of the compiled twins: read by the build (``setup.py``) and the loader.

Pure data and string rules, no import: ``setup.py`` runs this file by itself (``runpy``), so the
build needs neither NumPy nor Pinocchio nor ``kin`` importable.

A twin's C source sits at the path of the module it builds, below ``kin/_native/``: the module
``kin.ik.analytic.six_r._general6r`` (imported beside ``general_6r.py``) is built from
``kin/_native/ik/analytic/six_r/_general6r.c`` (:func:`source_of`). A header sits beside the
twins that include it, or in ``kin/_native/include/`` (:data:`INCLUDE_DIR`) when twins of
different folders share it. Each extension's ``depends`` are the headers its source reaches by
``#include "..."`` lines, found by ``setup.py``, not listed by hand.
"""

from __future__ import annotations

#: Each twin's name (its C source's stem, the built module's last part) -> the module it builds.
TWINS: dict[str, str] = {
    "_closed7": "kin.ik.analytic.seven_r._closed7",
    "_damped_step": "kin.ik.numeric._damped_step",
    "_general6r": "kin.ik.analytic.six_r._general6r",
    "_plain_lines": "kin.commands._plain_lines",
    "_pitch_sweep": "kin.ik.analytic.planar._pitch_sweep",
    "_pieper_arms": "kin.ik.analytic.six_r._pieper_arms",
    "_pose_check": "kin.ik.targets._pose_check",
    "_shoulder7": "kin.ik.analytic.seven_r._shoulder7",
    "_sphere_motion": "kin.plan._sphere_motion",
    "_three_parallel": "kin.ik.analytic.six_r._three_parallel",
}

#: Each twin's name -> the test file (under ``tests/``) that compares it with its NumPy form.
PARITY_TESTS: dict[str, str] = {
    "_closed7": "native/test_closed7_parity.py",
    "_damped_step": "native/test_damped_step.py",
    "_general6r": "native/test_general6r_twin.py",
    "_plain_lines": "native/test_plain_lines.py",
    "_pitch_sweep": "native/test_pitch_sweep.py",
    "_pieper_arms": "native/test_six_r_family_twins.py",
    "_pose_check": "native/test_pose_check.py",
    "_shoulder7": "native/test_shoulder7_parity.py",
    "_sphere_motion": "native/test_sphere_motion.py",
    "_three_parallel": "native/test_six_r_family_twins.py",
}

#: The C sources' root, relative to the project (the folder holding ``pyproject.toml``).
NATIVE_DIR = "kin/_native"

#: The headers twins of different folders share (``-I`` at build time), relative to the project.
INCLUDE_DIR = f"{NATIVE_DIR}/include"

#: The environment variable that, set to 1 (or true, yes), keeps every twin unloaded.
PURE_PYTHON_VARIABLE = "DH_KINEMATICS_PURE_PYTHON"


def source_of(module: str) -> str:
    """The C source of a twin's module, relative to the project, in ``/`` form.

    Args:
        module: The built module's dotted name (a value of :data:`TWINS`, below ``kin.``).

    Returns:
        ``kin/_native/`` + the module's path below ``kin`` + ``.c``
        (``kin.ik.targets._pose_check`` -> ``kin/_native/ik/targets/_pose_check.c``).
    """
    package, _, below = module.partition(".")
    if package != "kin" or not below:
        raise ValueError(f"a twin's module is below kin: {module!r}")
    return f"{NATIVE_DIR}/{below.replace('.', '/')}.c"
