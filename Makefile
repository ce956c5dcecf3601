# modrob workspace. Every target runs inside scripts/env.sh's environment.
# Quick start: `make demo`, `make test` (each sets the machine up first when needed).
SHELL := /bin/bash
ROOT := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
ENV := source $(ROOT)/scripts/env.sh
SCENARIO ?= one_robot
# Set-up is done when the venv, its requirements stamp and the devel space exist.
SETUP_STAMP := $(ROOT)/devel/setup.bash

.PHONY: setup build build-colcon test test-unit test-ros demo sweep lint bench rviz tune graph plot clean help

help:
	@echo "make demo      set up if needed, then run the Bulbs and Slides pick-and-place headless (SCENARIO=$(SCENARIO))"
	@echo "make test      set up if needed, then every unit test and rostest; ends with 'N passed, N failed'"
	@echo "make setup     Debian packages + .venv (pinned PyPI extras) + catkin_make (idempotent)"
	@echo "make build     catkin_make;  make build-colcon: colcon build into build_colcon/ install_colcon/"
	@echo "make fuzz      the simulator's fuzz suite in full (MODROB_FUZZ_SCALE=20: models, requests, YAML, trajectory and gripper goals; minutes)"
	@echo "make sweep FILE=<sweep.yaml> [RUNS=N] [ADDRESS=<ray head:port>]  trials on Ray (local or a cluster): out/sweeps/<name>/"
	@echo "make lint      catkin_lint on all packages + flake8 on all Python"
	@echo "make bench     quick benchmarks vs PyBullet/MuJoCo (< 10 min; FULL=1 everything, J=N side by side): docs/benchmarks.md, out/bench/"
	@echo "make bench AGAINST=<commit> [PAIRS=3] [ONLY=polaris_pace,...]  the scenario launches' pace against another commit's"
	@echo "make tune      rqt_reconfigure on the running system (FILTER=/ptrz narrows; LAUNCH='pkg file args' starts a scenario beside it)"
	@echo "make graph     rqt_graph of the running system to out/rqt_graph.png/.svg, then its window (LAUNCH= as for tune)"
	@echo "make plot SERIES='/topic/field[i] ...'  live plot; out/rqt_plot.png/.csv when closed (LAUNCH= as for tune)"
	@echo "make clean     remove build/, devel/, install/, colcon dirs and out/ (keeps .venv)"

setup:
	@$(ROOT)/scripts/setup.sh

# Set-up is cheap when done (seconds), so test and demo always run it: that also rebuilds
# after a pull that added messages or packages.
build:
	@$(ROOT)/scripts/setup.sh --no-build >/dev/null
	@$(ROOT)/scripts/build.sh

build-colcon:
	@$(ROOT)/scripts/setup.sh --no-build >/dev/null
	@cd $(ROOT) && export PATH=$(ROOT)/.venv/bin:/usr/bin:$$PATH && \
	  colcon --log-base log_colcon build --base-paths src --build-base build_colcon \
	    --install-base install_colcon --cmake-args -DPYTHON_EXECUTABLE=$(ROOT)/.venv/bin/python3

test:
	@$(ROOT)/scripts/setup.sh
	@$(ENV) && python3 $(ROOT)/scripts/run_tests.py $(TESTARGS)

test-unit:
	@$(ROOT)/scripts/setup.sh
	@$(ENV) && python3 $(ROOT)/scripts/run_tests.py --tier 1 $(TESTARGS)

test-ros:
	@$(ROOT)/scripts/setup.sh
	@$(ENV) && python3 $(ROOT)/scripts/run_tests.py --tier 2 $(TESTARGS)

# The short form of the fuzz suite runs in `make test`; this is the full one (seeded, so a failure
# reproduces): the physics core in pytest, then the /gazebo node and the Franka gripper under rostest
# (sim_fuzz.test, gripper_fuzz.test; run_tests.py cleans up after that part). The pytest part's TMPDIR and --basetemp are a directory removed when the
# target ends, also on Ctrl-C and SIGTERM: pytest would keep its last three in /tmp/pytest-of-<user>.
fuzz:
	@$(ROOT)/scripts/setup.sh
	@$(ENV) && export MODROB_FUZZ_SCALE=$${MODROB_FUZZ_SCALE:-20} && \
	  tmp=$$(mktemp -d -t modrob-fuzz-XXXXXXXX) && trap 'rm -rf "$$tmp"' EXIT && \
	  trap 'exit 130' INT && trap 'exit 143' TERM && \
	  (cd $(ROOT) && TMPDIR=$$tmp python3 -m pytest -q --import-mode=importlib -p no:cacheprovider \
	    --basetemp $$tmp/pytest src/modrob_sim/test/unit/test_fuzz_physics.py) && \
	  python3 $(ROOT)/scripts/run_tests.py --tier 2 -k fuzz

demo:
	@$(ROOT)/scripts/setup.sh
	@$(ENV) && $(ROOT)/scripts/demo.sh $(SCENARIO)

# A sweep or Monte-Carlo study (docs/sweeps.md): FILE is a path or a file of src/modrob_sweep/sweeps/.
FILE ?=
RUNS ?=
ADDRESS ?=
sweep:
	@[ -n "$(FILE)" ] || { echo "make sweep: give FILE=<sweep.yaml>, e.g. FILE=src/modrob_sweep/sweeps/slide_friction.yaml \
(shipped: $$(ls $(ROOT)/src/modrob_sweep/sweeps | tr '\n' ' '))" >&2; exit 2; }
	@$(ROOT)/scripts/setup.sh
	@$(ENV) && rosrun modrob_sweep sweep $(FILE) $(if $(RUNS),--runs $(RUNS)) $(if $(ADDRESS),--address $(ADDRESS)) $(SWEEPARGS)

lint:
	@$(ROOT)/scripts/setup.sh --no-build >/dev/null
	@$(ROOT)/scripts/lint.sh

bench:
	@$(ROOT)/scripts/setup.sh
	@$(ENV) && bash $(ROOT)/scripts/bench/run.sh $(if $(filter 1 true yes,$(FULL)),--full) $(if $(J),-j $(J)) \
	  $(if $(AGAINST),--against $(AGAINST) $(if $(PAIRS),--pairs $(PAIRS)) $(if $(ONLY),--only $(ONLY)))

rviz:
	@$(ENV) && roslaunch modrob_sim empty_world.launch gui:=true

# The rqt tools beside a scenario (docs/tools.md). Without LAUNCH they attach to the ROS master
# already running (a scenario started in another shell); with LAUNCH="modrob_motion
# bulbs_and_slides.launch gui:=true" they start it, wait for its master, and stop it when the
# tool's window closes.
FILTER ?=
SERIES ?=
LAUNCH ?=
define BESIDE_SCENARIO
if [ -n "$(LAUNCH)" ]; then roslaunch $(LAUNCH) & lpid=$$!; trap 'kill -INT $$lpid 2>/dev/null; wait $$lpid' EXIT; fi; \
for i in $$(seq 1 120); do python3 -c 'import rosgraph,sys; sys.exit(not rosgraph.is_master_online())' && break; \
  [ -z "$(LAUNCH)" ] && break; sleep 0.5; done; \
python3 -c 'import rosgraph,sys; sys.exit(not rosgraph.is_master_online())' || { echo "make $@: no ROS master at \
$$ROS_MASTER_URI: start a scenario first (e.g. roslaunch modrob_motion bulbs_and_slides.launch gui:=true) or give \
LAUNCH=\"pkg file.launch args\"" >&2; exit 2; }
endef

tune:
	@$(ENV) && $(BESIDE_SCENARIO); rosrun rqt_reconfigure rqt_reconfigure --filter '$(FILTER)'

graph:
	@$(ENV) && $(BESIDE_SCENARIO); \
	  rosrun rqt_graph rqt_graph -o $(ROOT)/out/rqt_graph.png -o $(ROOT)/out/rqt_graph.svg --group-namespaces \
	    --hide-params $(if $(LAUNCH),--settle 3) --gui $(GRAPHARGS)

plot:
	@[ -n "$(SERIES)" ] || { echo "make plot: give SERIES='/topic/field[index] ...', e.g. \
SERIES=/modrob0/joint2_position_controller/state/process_value:set_point" >&2; exit 2; }
	@$(ENV) && $(BESIDE_SCENARIO); rosrun rqt_plot rqt_plot $(SERIES) --png $(ROOT)/out/rqt_plot.png \
	  --csv $(ROOT)/out/rqt_plot.csv $(PLOTARGS)

clean:
	rm -rf $(ROOT)/build $(ROOT)/devel $(ROOT)/install $(ROOT)/build_colcon $(ROOT)/install_colcon \
	  $(ROOT)/log_colcon $(ROOT)/log $(ROOT)/out
