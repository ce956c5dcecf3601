"""Runs the seed's experiment for every configuration of table 2 on the in-process simulator and
writes the figure 7 / figure 8 analogues plus a summary table (markdown) -- the script behind
docs/polaris.md's PID section: ``rosrun polaris_description pid_table_figures --out out/polaris`` (the
doc's figures in docs/images/polaris were made this way)."""
import argparse
import os
import sys

from polaris_description import seed_experiment as E
from polaris_description.vehicle_sim import PID_CONFIGS, VehicleSim, load_pid_gains


def run_config(n, log=print):
    sim = VehicleSim(world_file=None, pid_config=n)
    return _drive(sim, n, log)


def _drive(sim, n, log):
    exp = E.SeedExperiment()
    samples = []

    def controller(state):
        sim.command(**exp.step(state))
        samples.append(state)
        return not exp.done

    sim.run(60.0, controller=controller, every=0.02)
    summary = E.summarize(samples, exp)
    log("config %d: mean speed %.3f m/s (%+.1f %%), heading change %.0f deg, turn %s..%s s"
        % (n, summary["mean_speed"], 100 * summary["speed_error"], summary["heading_change_deg"],
           _fmt(summary["turn_started"]), _fmt(summary["turn_ended"])))
    return samples, exp, summary


def _fmt(v):
    return "-" if v is None else "%.1f" % v


def label(n):
    g = load_pid_gains(n)
    s = g["polaris_ranger_ev__front_left_steering_joint"]
    v = g["polaris_ranger_ev__rear_left_wheel_joint"]
    return ("config %d: steer P%g I%g D%g, vel P%g I%g D%g"
            % (n, s["p"], s["i"], s["d"], v["p"], v["i"], v["d"]))


def main(argv=None):
    from polaris_description.figures import grid_plots
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--out", required=True, help="directory for pid_speed.png, pid_path.png, pid_table.md")
    p.add_argument("--configs", default=",".join(map(str, PID_CONFIGS)))
    a = p.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    runs, rows = [], []
    for n in [int(c) for c in a.configs.split(",")]:
        samples, exp, summary = run_config(n, log=lambda m: print(m, flush=True))
        runs.append((label(n), samples, exp.events))
        rows.append((n, summary))
    grid_plots(runs, os.path.join(a.out, "pid_speed.png"), os.path.join(a.out, "pid_path.png"),
               E.EXPECTED_SPEED)
    with open(os.path.join(a.out, "pid_table.md"), "w") as f:
        f.write("| config | mean speed, straight [m/s] | vs 0.64 m/s | heading change [deg] "
                "| steer on..off [s] |\n")
        f.write("|---|---|---|---|---|\n")
        for n, s in rows:
            f.write("| %d | %.3f | %+.1f %% | %.0f | %s..%s |\n"
                    % (n, s["mean_speed"], 100 * s["speed_error"], s["heading_change_deg"],
                       _fmt(s["turn_started"]), _fmt(s["turn_ended"])))
    print("wrote %s/pid_speed.png, pid_path.png, pid_table.md" % a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
