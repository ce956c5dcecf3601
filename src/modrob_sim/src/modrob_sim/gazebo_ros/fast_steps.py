"""The /gazebo node's steps in batches of the C loop (modrob_sim.physics.native_batch) while none
of its step hooks has anything to do.

Per step the node's hooks set rospy's time, run force jobs, the plugins (ros_control's read ->
controllers -> write) and the publishers' schedules; each costs little, together they cost more
than the physics. Most steps need none of it in Python: the World's actuators carry the
controllers' set-points (PIDs, trajectory segments, held efforts) at every step in C, /clock on
every step goes out from C through roscpp, and everything else is due only at known times (the
plugins' due times: docs/plugins.md; states and markers at simulated times; the guard's
snapshots). A step at which a before-hook is due runs in Python (World.step); one at which only
after-hooks are due is made in C and its after-hooks run in Python, so what is published, when
and with which contents does not change. Between two batches the loop runs its jobs (services)
as between any two steps. Wall-clock schedules (a throttled /clock, the scene) are looked at after
each batch (a batch is at most the loop's batch of steps, 10 by default).
"""
import os

from modrob_sim.physics import native_batch

INF = float("inf")
#: the plugins' due times compare t + 1e-9 >= due; the batch ends 2e-9 earlier so that float
#: rounding never lets it run past a due step
DUE_MARGIN = 2e-9


def enabled():
    """MODROB_SIM_NATIVE_STEPS=0 keeps every step in Python (comparisons, debugging)."""
    return os.environ.get("MODROB_SIM_NATIVE_STEPS", "") not in ("0", "false", "no")


class FastSteps(object):
    def __init__(self, world, plugins, forces, outputs, set_time=None):
        self.world = world
        self.plugins = plugins
        self.forces = forces
        self.outputs = outputs
        self.set_time = set_time
        self.batcher = native_batch.Batcher(world) if enabled() and native_batch.available(world) else None
        self.steps = 0          # steps run in batches (statistics, tests)
        self.batches = 0        # and the batches that ran them

    def step(self, n, whole=True):
        """``n`` steps of the World: batches where possible, World.step where not. Returns the
        steps done: ``n``, or with ``whole`` False fewer when a batch ended at a step whose
        after-hooks were due (a state message), so that the caller's next pass of ``n`` steps
        starts there. The simulation loop's passes then fall in step with the 100 Hz states
        instead of each being cut in two batches (9 + 1 steps in C, twice the Python around
        each batch)."""
        world = self.world
        done = 0
        while done < n:
            k = self._batch(n - done)
            if k <= 0:
                world.step(1)
                done += 1
                continue
            done += k
            if not whole and self.batcher.after_due:
                break
        return done

    def _batch(self, n):
        b = self.batcher
        if b is None or self.world.step_hook_count != 1 or not b.eligible() or not self.forces.idle:
            return 0
        # the plugins' due times (docs/plugins.md), a little early: a hook called at a step at which
        # it finds nothing to do costs nothing, one called a step late would be wrong
        before_due = self.plugins.before_due() - DUE_MARGIN
        if before_due <= self.world.time:
            return 0
        after_due = min(self.outputs.batch_after_due(), self.plugins.after_due() - DUE_MARGIN)
        clock = self.outputs.batch_clock()
        if clock is False:
            return 0
        k = b.run(n, before_due, after_due, clock)
        if k > 0:
            if self.set_time is not None:
                self.set_time(self.world.time)
            self.steps += k
            self.batches += 1
            self.outputs.after_batch(wall_schedules=not b.after_due)
            if b.after_due:         # the last step's after-hooks are due: as World.step runs them
                b.run_after_hooks()
        return k

    def shutdown(self):
        pass
