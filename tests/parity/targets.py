"""The two vehicles a probe can drive: Firefly (in CI) and the reference ArduCopter SITL (when
recording, on a machine that built it with the reference scripts). Each boot is a fresh vehicle
with wiped parameters, at the same home (ArduPilot SITL's default field, also Firefly's), and
ready to arm: Firefly at once, ArduCopter once its EKF and GPS are ready (its pre-arm bit).
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

from firefly.groundstation.flight.autopilot_process import free_udp_port, start_autopilot, stop_process

from .client import Client, ProbeTimeout, mav
from .facts import Trace

HOME = "-35.363261,149.165230,584,0"
PREARM = mav.MAV_SYS_STATUS_PREARM_CHECK
GUIDED = 4


def wait_armable(client: Client, sim_s: float = 120.0) -> float:
    """Vehicle seconds until SYS_STATUS reports the pre-arm checks passing."""
    def ready():
        s = client.last.get("SYS_STATUS")
        return s is not None and bool(s.onboard_control_sensors_health & PREARM) \
            and client.last.get("GPS_RAW_INT") is not None and client.last["GPS_RAW_INT"].fix_type >= 3
    took = client.wait(ready, sim_s, what="pre-arm checks passing")
    # The bit can pass a moment before ArduCopter's EKF accepts an arm: arm once (and disarm) to
    # know. Both vehicles go through the same steps, so both start having armed once.
    start, boot_mode = client.now_ms, client.mode
    client.set_mode(GUIDED)  # a mode that needs a position estimate, the last thing to be ready
    while client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) != mav.MAV_RESULT_ACCEPTED:
        if client.now_ms - start > sim_s * 1000:
            raise ProbeTimeout(f"not armable within {sim_s:g} s of vehicle time")
        client.idle(1.0)
    client.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0)
    client.wait(lambda: not client.armed, 10, what="disarm after the first arm")
    client.set_mode(boot_mode)
    client.wait(lambda: client.mode == boot_mode, 5, what="the mode it booted in")
    client.texts.clear()
    return took + (client.now_ms - start) / 1000.0


def ready(client: Client, streams_hz: int | None) -> Client:
    if streams_hz:
        client.boot_s = wait_armable(client)
    return client


WIND_KEYS = {"SIM_WIND_SPD": "speed_m_s", "SIM_WIND_DIR": "from_direction_deg"}  # a scenario's [wind]


class FireflyTarget:
    name = "firefly"

    def __init__(self, speedup: str = "20"):
        self.speedup = speedup
        self.process = None
        self.scenario_dir = None

    def boot(self, streams_hz: int | None = 10, realistic_startup: bool = False,
             params: dict | None = None, world: dict | None = None) -> Client:
        """A fresh vehicle; with streams_hz, streams requested and ready to arm; with
        realistic_startup, booting as ArduCopter does instead of armable at once; with params,
        those parameters in force from power-on: SIM_* faults as a scenario's [faults], the
        rest as saved parameters it boots with (CAM1_TYPE, read at boot on both vehicles). Mind
        that ArduCopter takes its boot parameters unsaved, and replaces an unsaved CAM1_TYPE by
        1 if an output has SERVOn_FUNCTION 10, else 0 (AP_Camera::convert_params): boot a servo
        camera with CAM1_TYPE 1 and its trigger output; any other camera, set it and reboot.
        With world, a scenario's arrays of tables ({"terrain": [hill, ...]}): the world it flies
        in (ArduCopter's comes from what the probe serves it: ArduCopterTarget ignores it)."""
        self.close()
        extra = (f"--home={HOME}",) + (("--startup", "realistic") if realistic_startup else ())
        saved = {name: value for name, value in (params or {}).items() if not name.startswith("SIM_")}
        faults = {name: value for name, value in (params or {}).items() if name.startswith("SIM_")}
        if params or world:
            self.scenario_dir = tempfile.TemporaryDirectory(prefix="firefly-parity-")
        if faults or world:
            extra += ("--scenario", str(self._faults_scenario(faults, world or {})))
        state_dir = self._saved_params(saved) if saved else None
        self.process = start_autopilot(state_dir=state_dir, speedup=self.speedup, extra=extra, capture_stderr=True,
                                       wipe=not saved)
        return ready(Client(self.process.pymavlink_url, streams_hz), streams_hz)

    def _faults_scenario(self, params: dict, world: dict) -> Path:
        """A scenario with these SIM_* values: the wind's in its [wind] table (where a scenario
        sets them), the rest in [faults]; and the world's arrays of tables. The wind keeps
        ArduPilot SITL's profile (SIM_WIND_T 0) unless the values say otherwise: set as parameters
        on the reference, it weakens near the ground, where a scenario's [wind] does not."""
        path = Path(self.scenario_dir.name) / "faults.toml"
        wind = {WIND_KEYS[name]: value for name, value in params.items() if name in WIND_KEYS}
        faults = {name: value for name, value in params.items() if name not in WIND_KEYS}
        if wind:
            faults.setdefault("SIM_WIND_T", 0)
        path.write_text("".join(f"[{table}]\n" + "".join(f"{name} = {float(value)!r}\n" for name, value in values.items())
                                for table, values in (("faults", faults), ("wind", wind)) if values)
                        + "".join(f"[[{table}]]\n" + "".join(f"{key} = {float(value)!r}\n" for key, value in entry.items())
                                  for table, entries in world.items() for entry in entries))
        return path

    def _saved_params(self, params: dict) -> Path:
        """A state directory whose vehicle (instance 0) has these parameters saved."""
        state_dir = Path(self.scenario_dir.name) / "state"
        (state_dir / "instance-0").mkdir(parents=True)
        (state_dir / "instance-0" / "params.json").write_text(json.dumps({k: float(v) for k, v in params.items()}))
        return state_dir

    def close(self) -> None:
        if self.process is not None:
            self.process.stop()
            self.process = None
        if self.scenario_dir is not None:
            self.scenario_dir.cleanup()
            self.scenario_dir = None


class ArduCopterTarget:
    """The reference: run-arducopter-sitl from the reference scripts, in OUT_DIR (the build's)."""
    name = "arducopter"

    def __init__(self, out_dir: Path, instance: int = 0, speedup: int = 10,
                 runner: Path = Path(os.environ.get("ARDUCOPTER_RUNNER", "../shared/reference/run-arducopter-sitl"))):
        self.out_dir, self.instance, self.speedup, self.runner = Path(out_dir), instance, speedup, runner
        self.process = None

    def boot(self, streams_hz: int | None = 10, realistic_startup: bool = True,
             params: dict | None = None, world: dict | None = None) -> Client:
        """A fresh vehicle (its start-up is always ArduCopter's own); with params, those
        parameters in force from power-on: a defaults file after the runner's own (SITL takes the
        last --defaults, so the runner's files are named again before it)."""
        self.close()
        run_dir = self.out_dir / f"run-{self.instance}"
        shutil.rmtree(run_dir, ignore_errors=True)
        port = free_udp_port()
        extra = []
        if params:
            run_dir.mkdir(parents=True)
            (run_dir / "boot.parm").write_text("".join(f"{name} {value:.12g}\n" for name, value in params.items()))
            copter = (self.out_dir / "ardupilot/Tools/autotest/default_params/copter.parm").resolve()
            extra = ["--defaults", f"{copter},nofpe.parm,boot.parm"]  # relative: the runner works in run_dir
        self.process = subprocess.Popen(
            [str(self.runner), str(self.out_dir), str(self.instance), str(port), str(self.speedup),
             "--home", HOME, *extra], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
        return ready(Client(f"udpin:127.0.0.1:{port}", streams_hz), streams_hz)

    def close(self) -> None:
        if self.process is not None:
            stop_process(self.process)
            self.process = None


def run_each(target, probes: dict, only: tuple[str, ...] = ()) -> dict[str, Trace]:
    """Each probe (name -> (probe(client, trace), boot parameters or None)) on a fresh vehicle booted
    with its parameters; with `only`, those named alone. The target is closed at the end."""
    traces = {}
    try:
        for name, (probe, params) in probes.items():
            if only and name not in only:
                continue
            client = target.boot(params=params)
            trace = traces[name] = Trace()
            probe(client, trace)
    finally:
        target.close()
    return traces
