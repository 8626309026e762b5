# Two promises: `make run` flies the default scenario, `make test` passes the tests,
# both on a fresh machine with only Python 3.11, pip and gcc.
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: install run test unit sitl install-check bench fuzz soak clean parity record-parity plans

install: $(STAMP)

# setup.py builds the compiled cascade; its C sources rebuild it when they change.
$(STAMP): pyproject.toml setup.py $(wildcard sim/*.h sim/*.c autopilot/control/*.h autopilot/control/*.c autopilot/mavlink/*.c)
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test,ray,explore]'
	touch $(STAMP)

run: install
	$(PY) -m firefly.groundstation explore --scenario scenarios/default.toml --sensor camera

# The unit tests share no sockets, ports or wall-clock timing: two workers halve their time. The
# parity areas wait mostly on their vehicles' sim time at speedup 20 (a mismatch is run again
# before it fails), so two run at once too. The rest flies real processes on free ports, waiting
# on conditions with generous deadlines: two at once as well, except the tests marked `serial`,
# which judge wall-clock time or keep both cores busy themselves and run one at a time, last.
test: install
	$(PY) -m pytest -q -ra -n 2 tests/unit
	$(PY) -m pytest -q -ra -n 2 --durations=15 tests/parity
	$(PY) -m pytest -q -ra -n 2 --durations=20 -m "not serial" --ignore=tests/unit --ignore=tests/parity
	$(PY) -m pytest -q -ra --durations=15 -m serial --ignore=tests/unit --ignore=tests/parity

unit: install
	$(PY) -m pytest -q tests/unit

sitl: install
	$(PY) -m pytest -q tests/sitl

# Part of `make test`: `pip install .` (not editable) of the checkout, flown from outside it.
install-check: install
	$(PY) -m pytest -q tests/install

# Firefly against the recorded ArduCopter, per area; writes PARITY.md (also checked in `make test`).
parity: install
	$(PY) -m tests.parity.report --out PARITY.md

# Re-record the reference: needs ArduCopter SITL built by build-arducopter-sitl into REF_DIR.
REF_DIR ?= ../ref
record-parity: install
	$(PY) -m tests.parity.record $(REF_DIR)

# The example plans (QGC survey, corridor and structure scans; a Mission Planner spline mission)
# made by the ground stations' rules: groundstation/plans/.
plans: install
	$(PY) -m groundstation.plans examples/plans

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache autopilot/control/_cascade*.so

bench: install
	REF_DIR=$(REF_DIR) $(PY) bench/run.py

# A million hostile datagrams through the sans-IO link layer and session (CI runs 20,000); then a
# million steps of the state-space walk: every start-up stage, mode, flight phase, failsafe and
# half-done transfer, attacked with hostile messages (CI runs 10,000 and hypothesis rules).
fuzz: install
	$(PY) -m tests.fuzz.receive_fuzz --frames 1000000 --json out/fuzz.json
	$(PY) -m tests.fuzz.state_walk --steps 1000000 --seed 1 --json out/state_walk.json

# A simulated hour at 60x with a pilot and three noisy clients; checks every tick ran, memory flat.
soak: install
	$(PY) -m tests.fuzz.soak --sim-hours 1 --speedup 60 --json out/soak.json
