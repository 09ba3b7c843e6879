#!/usr/bin/env python3
"""Pinocchio's inverse dynamics of the URDF robots, the anchor of tests/src/urdf_rnea.rs.

For each URDF: pinocchio.buildModelFromUrdf (fixed base at the root link, gravity
[0, 0, -9.81]), 20 seeded random states over every movable joint of the model and
pinocchio.rnea; one CSV per robot, written next to this script. See README.md.

Columns: q:<joint>, qd:<joint>, qdd:<joint>, tau:<joint> for every movable joint in
pinocchio's joint order. A continuous joint's q is its angle (pinocchio's configuration
holds cos q, sin q); prismatic positions are within the joint's limits, revolute angles in
[-pi, pi], velocities in [-2, 2] and accelerations in [-5, 5] (units of the joint).
Every number is written with repr (shortest text that reads back to the same double).
"""

import math
import os
import re
import sys

import numpy as np
import pinocchio

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))

ROBOTS = [
    ("panda", "data/example_robot_data/panda/panda.urdf"),
    ("ur5", "data/example_robot_data/ur5/ur5_robot.urdf"),
    ("kuka_lwr4", "data/kuka_lwr4/description/kuka_lwr4.urdf"),
    ("tx40", "data/staubli_tx40/description/tx40_mdh_modified.urdf"),
    ("skewed_arm", "tests/reference/urdf/skewed_arm.urdf"),
    ("kinova", "data/example_robot_data/kinova/kinova.urdf"),
    ("xarm7", "data/example_robot_data/xarm7/xarm7.urdf"),
    ("so101", "data/example_robot_data/so101/so101.urdf"),
]
STATES = 20
SEED = 20261126


def printed_right_angle(word):
    """The nonzero multiple of pi/2 that `word` prints to its own number of decimals (at
    least four, no exponent), as robid's URDF reader takes it (docs/urdf.md#the-angle-rule);
    None otherwise."""
    if "e" in word.lower() or "." not in word:
        return None
    decimals = len(word.split(".", 1)[1])
    value = float(word)
    if decimals < 4 or not math.isfinite(value):
        return None
    k = round(value / (math.pi / 2))
    if k == 0 or abs(k) > 4:
        return None
    exact = k * (math.pi / 2)
    return exact if float(f"{exact:.{decimals}f}") == value else None


def with_right_angles(text):
    """The URDF text with every rpy value that prints a right angle written exactly."""

    def words(match):
        out = []
        for word in match.group(2).split():
            exact = printed_right_angle(word)
            out.append(word if exact is None else repr(exact))
        return f'{match.group(1)}"{" ".join(out)}"'

    return re.sub(r'(\brpy\s*=\s*)"([^"]*)"', words, text)


def continuous(joint):
    """A revolute joint without limits: nq = 2 (cos, sin), nv = 1."""
    return joint.nq == 2 and joint.nv == 1


def main():
    print("pinocchio", pinocchio.__version__, file=sys.stderr)
    for index, (robot, relative) in enumerate(ROBOTS):
        path = os.path.join(ROOT, relative)
        write(robot, pinocchio.buildModelFromUrdf(path), index)
        # the file as robid reads it, when it writes right angles to a few decimals: the
        # same states, so the two CSVs differ only by the angles
        with open(path) as f:
            text = f.read()
        exact = with_right_angles(text)
        if exact != text:
            write(f"{robot}_right_angles", pinocchio.buildModelFromXML(exact), index)


def write(robot, model, index):
    """Pinocchio's torques at the seeded states, as `<robot>.csv` next to this script."""
    data = model.createData()
    assert np.allclose(model.gravity.linear, [0.0, 0.0, -9.81], atol=0.0)
    # rnea adds armature * qdd; the URDF parser leaves it at zero (checked, so the
    # torques are the rigid-body ones only)
    assert not np.any(model.armature), model.armature
    joints = []  # (name, joint model) of every movable joint, pinocchio's order
    for j in range(1, model.njoints):
        joint = model.joints[j]
        assert joint.nv == 1, (robot, model.names[j], joint.shortname())
        joints.append((model.names[j], joint))
    rng = np.random.default_rng(SEED + index)
    header = [
        f"{kind}:{name}" for kind in ("q", "qd", "qdd", "tau") for name, _ in joints
    ]
    rows = []
    for _ in range(STATES):
        angles = []
        config = np.zeros(model.nq)
        for name, joint in joints:
            if continuous(joint):
                angle = rng.uniform(-np.pi, np.pi)
                config[joint.idx_q] = np.cos(angle)
                config[joint.idx_q + 1] = np.sin(angle)
            elif joint.shortname().startswith("JointModelP"):  # PX, PY, PZ, PrismaticUnaligned
                lower = model.lowerPositionLimit[joint.idx_q]
                upper = model.upperPositionLimit[joint.idx_q]
                angle = rng.uniform(lower, upper)
                config[joint.idx_q] = angle
            else:
                angle = rng.uniform(-np.pi, np.pi)
                config[joint.idx_q] = angle
            angles.append(angle)
        qd = rng.uniform(-2.0, 2.0, model.nv)
        qdd = rng.uniform(-5.0, 5.0, model.nv)
        tau = pinocchio.rnea(model, data, config, qd, qdd)
        rows.append(list(angles) + list(qd) + list(qdd) + list(tau))
    path = os.path.join(HERE, f"{robot}.csv")
    with open(path, "w") as out:
        out.write(",".join(header) + "\n")
        for row in rows:
            out.write(",".join(repr(float(x)) for x in row) + "\n")
    kinds = ", ".join(f"{n} ({j.shortname()})" for n, j in joints)
    print(f"{robot}: {kinds}", file=sys.stderr)


if __name__ == "__main__":
    main()
