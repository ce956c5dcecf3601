#!/usr/bin/env python3
"""Physics core against theory, as a picture: a compound pendulum's swing, a dropped box and a box
on 30 and 40 degree ramps (mu 0.7), each beside its analytic curve.

    source scripts/env.sh && python3 scripts/bench/physics_core_validation.py [out.png]

Writes out/physics_core_validation.png by default (matplotlib, Agg).
"""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from modrob_sim.physics import World  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FIX = os.path.join(ROOT, "src", "modrob_sim", "test", "fixtures", "physics")


def fixture(name):
    with open(os.path.join(FIX, name)) as f:
        return f.read()


def pendulum():
    w = World()
    m = w.add_urdf("p", fixture("pendulum.urdf"), joint_positions={"swing": 0.05})
    j = m.joints["swing"]
    t, q = [], []
    for _ in range(3000):
        w.step()
        t.append(w.time)
        q.append(j.position)
    mass, length, ic = 1.0, 0.25, 0.0208667
    omega = math.sqrt(mass * 9.81 * length / (ic + mass * length ** 2))
    return t, q, [0.05 * math.cos(omega * x) for x in t]


def drop():
    w = World()
    w.add_urdf("ground", fixture("ground_box.urdf"))
    b = w.add_urdf("box", fixture("box.urdf"), pose=((0, 0, 0.5), (0, 0, 0, 1)))
    t, z = [], []
    for _ in range(600):
        w.step()
        t.append(w.time)
        z.append(b.pose[0][2])
    theory = [max(0.05, 0.5 - 0.5 * 9.81 * x * x) for x in t]
    return t, z, theory


def ramp(deg, mu=0.7):
    a = math.radians(deg)
    box = ('<link name="box"><inertial><mass value="1"/><inertia ixx="0.0042" ixy="0" ixz="0" '
           'iyy="0.0042" iyz="0" izz="0.0067"/></inertial><collision><geometry><box size="0.2 0.2 0.1"/>'
           '</geometry></collision></link><gazebo reference="box"><mu1>%r</mu1><mu2>%r</mu2></gazebo>'
           % (mu, mu))
    slab = ('<link name="world"/><link name="slab"><collision><origin xyz="0 0 -0.05"/><geometry>'
            '<box size="4 1 0.1"/></geometry></collision></link><gazebo reference="slab"><mu1>%r</mu1>'
            '<mu2>%r</mu2></gazebo><joint name="f" type="fixed"><parent link="world"/>'
            '<child link="slab"/><origin rpy="0 %r 0"/></joint>' % (mu, mu, a))
    w = World()
    w.add_urdf("ramp", "<robot name='r'>%s</robot>" % slab)
    n = (math.sin(a), 0.0, math.cos(a))
    b = w.add_urdf("box", "<robot name='b'>%s</robot>" % box,
                   pose=((0.0501 * n[0], 0, 0.0501 * n[2]), (0, math.sin(a / 2), 0, math.cos(a / 2))))
    p0 = b.pose[0]
    t, s = [], []
    for _ in range(1000):
        w.step()
        t.append(w.time)
        s.append(math.dist(p0, b.pose[0]))
    acc = max(0.0, 9.81 * (math.sin(a) - mu * math.cos(a)))
    return t, s, [0.5 * acc * x * x for x in t]


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "out", "physics_core_validation.png")
    os.makedirs(os.path.dirname(out), exist_ok=True)
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    t, q, th = pendulum()
    ax[0].plot(t, q, label="simulated")
    ax[0].plot(t, th, "--", label="theory (compound pendulum)")
    ax[0].set(title="Pendulum, 0.05 rad swing", xlabel="t (s)", ylabel="angle (rad)")
    t, z, th = drop()
    ax[1].plot(t, z, label="simulated")
    ax[1].plot(t, th, "--", label="free fall, rest at h/2 = 0.05 m")
    ax[1].set(title="Box dropped from 0.5 m", xlabel="t (s)", ylabel="centre height (m)")
    for deg, c in ((30, "C0"), (40, "C1")):
        t, s, th = ramp(deg)
        ax[2].plot(t, s, color=c, label="%d deg simulated" % deg)
        ax[2].plot(t, th, "--", color=c, label="%d deg theory" % deg)
    ax[2].set(title="Box on a ramp, mu 0.7 (atan 0.7 = 35 deg)", xlabel="t (s)", ylabel="distance slid (m)")
    for a in ax:
        a.grid(True, alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print(out)


if __name__ == "__main__":
    main()
