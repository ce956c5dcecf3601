# modrob workspace. Every target runs inside scripts/env.sh's environment.
# Quick start: `make demo`, `make test` (each sets the machine up first when needed).
SHELL := /bin/bash
ROOT := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
ENV := source $(ROOT)/scripts/env.sh
SCENARIO ?= one_robot
# Set-up is done when the venv, its requirements stamp and the devel space exist.
SETUP_STAMP := $(ROOT)/devel/setup.bash

.PHONY: setup build build-colcon test test-unit test-ros demo lint bench rviz clean help

help:
	@echo "make demo      set up if needed, then run the Bulbs and Slides pick-and-place headless (SCENARIO=$(SCENARIO))"
	@echo "make test      set up if needed, then every unit test and rostest; ends with 'N passed, N failed'"
	@echo "make setup     Debian packages + .venv (pinned PyPI extras) + catkin_make (idempotent)"
	@echo "make build     catkin_make;  make build-colcon: colcon build into build_colcon/ install_colcon/"
	@echo "make lint      catkin_lint on all packages + flake8 on all Python"
	@echo "make bench     benchmarks under scripts/bench/ (results in docs/benchmarks.md)"
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

demo:
	@$(ROOT)/scripts/setup.sh
	@$(ENV) && $(ROOT)/scripts/demo.sh $(SCENARIO)

lint:
	@$(ROOT)/scripts/setup.sh --no-build >/dev/null
	@$(ROOT)/scripts/lint.sh

bench:
	@$(ROOT)/scripts/setup.sh
	@$(ENV) && for b in $(ROOT)/scripts/bench/*.sh; do echo "== $$b"; bash $$b || exit 1; done

rviz:
	@$(ENV) && roslaunch modrob_sim empty_world.launch gui:=true

clean:
	rm -rf $(ROOT)/build $(ROOT)/devel $(ROOT)/install $(ROOT)/build_colcon $(ROOT)/install_colcon \
	  $(ROOT)/log_colcon $(ROOT)/log $(ROOT)/out
