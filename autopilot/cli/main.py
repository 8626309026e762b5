"""`autopilot`: start a simulated ArduCopter-compatible vehicle and serve MAVLink over TCP and UDP.

Ports follow ArduPilot SITL's instance convention: instance N is system id N+1 (N % 255 + 1 past
254: fleet.py), serves TCP 5760+10N (SERIAL0, as ArduPilot SITL does), listens on UDP 5760+10N and
sends to 14550+10N and 14540+10N (what MAVProxy's default outputs give SITL users). --serialN adds ports as ArduPilot
SITL's option of that name does. A default port another process holds is not an error: the
vehicle takes the next free one in steps of 10 and says so.
"""
from __future__ import annotations

import argparse
import functools
import math
import os
import signal
import sys
import time
from pathlib import Path

from .fleet import MAX_INSTANCE, PART_SIZE, parse_fleet, start_parts, stop_parts, system_id_of


class CliError(Exception):
    pass


def parse_udp(text: str, option: str) -> tuple:
    body = text[4:] if text.startswith("udp:") else text
    host, sep, port = body.rpartition(":")
    if not sep or not host:
        raise CliError(f"{option}: expected udp:HOST:PORT, got {text!r}")
    try:
        port_n = int(port)
    except ValueError:
        raise CliError(f"{option}: port must be a number in {text!r}") from None
    if not 0 <= port_n <= 65535:
        raise CliError(f"{option}: port {port_n} outside 0..65535")
    return host, port_n


SERIAL_PORTS = 8  # --serial0 .. --serial7
SERIAL_KINDS = ("tcp", "tcpclient", "udp", "udpclient")


def parse_serial(text: str, option: str) -> tuple | None:
    """ArduPilot SITL's port spec: tcp:[HOST:]PORT (a server), tcpclient:HOST:PORT,
    udpclient:HOST:PORT (an output), udp:HOST:PORT (the UDP socket's own address), or none.
    (kind, host, port), or None for none."""
    if text == "none":
        return None
    kind, sep, rest = text.partition(":")
    if not sep or kind not in SERIAL_KINDS:
        raise CliError(f"{option}: expected none or {', '.join(k + ':...' for k in SERIAL_KINDS)}, got {text!r}")
    if kind == "tcp" and ":" not in rest:
        rest = f"0.0.0.0:{rest}"
    host, port = parse_udp(rest, option)
    if kind in ("tcpclient", "udpclient") and port == 0:
        raise CliError(f"{option}: {kind} needs a port to connect to, got {text!r}")
    return kind, host, port


def parse_speedup(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise CliError(f"--speedup: expected a number or 'inf', got {text!r}") from None
    if math.isnan(value) or value <= 0:
        raise CliError(f"--speedup: must be positive, got {text!r}")
    return value


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, no usage dump
        raise CliError(message)


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="autopilot", description=__doc__.splitlines()[0])
    p.add_argument("--out", action="append", default=None, metavar="udp:HOST:PORT",
                   help="send MAVLink here (repeatable; default 127.0.0.1:14550 and :14540, +10 per instance)")
    p.add_argument("--listen", default=None, metavar="udp:HOST:PORT",
                   help="local UDP address to bind (default 0.0.0.0:5760+10*instance; port 0 = any)")
    for n in range(SERIAL_PORTS):
        p.add_argument(f"--serial{n}", default=None, metavar="SPEC",
                       help="SERIAL0: tcp server on 5760+10*instance by default; SPEC is none, tcp:[HOST:]PORT, "
                            "tcpclient:HOST:PORT, udpclient:HOST:PORT or udp:HOST:PORT (ports +10 per vehicle)"
                       if n == 0 else argparse.SUPPRESS)
    p.add_argument("--speedup", default="1", help="sim seconds per wall second; 'inf' runs flat out")
    p.add_argument("--instance", type=int, default=0, help="instance number N: system id N+1, ports +10N")
    p.add_argument("--count", type=int, default=1,
                   help="vehicles: instances N..N+count-1, one UDP port each, on a 5 m grid; past 255 a "
                        "process per 255 (system ids repeat from 1 in each)")
    p.add_argument("--fleet", default=None, type=fleet_part, help=argparse.SUPPRESS)  # a fleet's part: FIRST,TOTAL
    p.add_argument("--home", default=None, metavar="LAT,LON,ALT[,YAW]", help="home location (AMSL metres, degrees)")
    p.add_argument("--seed", type=int, default=None, help="seed for sensor noise (overrides the scenario)")
    p.add_argument("--scenario", default=None, metavar="FILE", help="scenario TOML file")
    p.add_argument("--state-dir", default=None, metavar="DIR",
                   help="where parameters are kept per instance (default ~/.local/state/firefly)")
    p.add_argument("--startup", choices=("instant", "realistic"), default=None,
                   help="instant: armable at once (default); realistic: boot as ArduCopter does, "
                        "about 42 s of vehicle time before a mode that needs a position can arm")
    p.add_argument("--thermal-camera", action="store_true",
                   help="fit the thermal camera (MAVLink component 100) with its default spec, unless the "
                        "scenario's [thermal_camera] gives one")
    p.add_argument("--video-port", type=video_port_option, default=None, metavar="PORT",
                   help="UDP port on 127.0.0.1 the thermal camera's live video (H.264 in MPEG-TS) goes to, "
                        "+10 per instance (default 5600, or the scenario's [thermal_camera].video_port; "
                        "0: no video)")
    p.add_argument("--wipe", action="store_true", help="reset saved parameters to defaults (like SITL -w)")
    p.add_argument("--param", action="append", default=[], type=param_setting, metavar="NAME=VALUE",
                   help="set and save a parameter before the vehicle boots, as a ground station's set and a "
                        "reboot would (repeatable; e.g. CAM1_TYPE=1 for a camera, which is made at boot)")
    p.add_argument("--duration", type=float, default=math.inf, help="stop after this many sim seconds")
    p.add_argument("--tlog", default=None, metavar="FILE",
                   help="record every MAVLink frame sent and received to this .tlog (appends)")
    p.add_argument("--signing-key", default=None, metavar="FILE",
                   help="MAVLink 2 signing: FILE holds 64 hex digits (the key) or a passphrase "
                        "(SHA-256, as MAVProxy's 'signing setup'); unsigned commands are then dropped")
    p.add_argument("--state-log", default=None, metavar="FILE",
                   help="write the true state (body, on ground, armed, mode, home) every 0.1 s of sim time "
                        "(CSV with a header line; for determinism checks and waits in vehicle time)")
    p.add_argument("--stats", default=None, metavar="FILE",
                   help="at exit, write a JSON report: ticks run, sim time, frames refused and dropped per vehicle")
    p.add_argument("--exit-with-parent", nargs="?", const=0, default=None, type=positive_pid, metavar="PID",
                   help="stop when the process that started this one dies, or process PID if given "
                        "(for harnesses that start autopilots: giving their own PID also covers a "
                        "harness that dies before this process has started)")
    p.add_argument("--quiet", action="store_true", help="print nothing but errors")
    return p


DEFAULT_VIDEO_PORT = 5600  # the thermal camera's video, +10 per instance (QGroundControl's usual port)
GRID_SPACING_M = 5.0  # vehicles of one process start this far apart, on a square grid


def build(args) -> list:
    """Assemble every vehicle with its MAVLink session and UDP endpoint: a list of (Node, outs)."""
    from ..startup import StartupTimeline
    from .scenario import Scenario, load_scenario, parse_home

    if not hasattr(args, "fleet_total"):  # which vehicles of the fleet this process runs
        args.fleet_first, args.fleet_total = args.fleet or (0, args.count)
        if args.fleet is None:  # the fleet's first part (fleet.py), or all of a fleet of up to 255
            args.count = min(args.count, PART_SIZE)
    if not 0 <= args.instance <= MAX_INSTANCE:
        raise CliError(f"--instance: must be 0..{MAX_INSTANCE}, got {args.instance}")
    if not 1 <= args.fleet_total <= MAX_INSTANCE + 1 - args.instance:  # every port below 65536
        raise CliError(f"--count: must be 1..{MAX_INSTANCE + 1 - args.instance} with --instance {args.instance}, "
                       f"got {args.fleet_total}")
    scenario = load_scenario(Path(args.scenario)) if args.scenario else Scenario()
    if args.home:
        scenario.home, scenario.home_yaw_deg = parse_home(args.home)
    if args.seed is not None:
        scenario.seed = args.seed
    if getattr(args, "thermal_camera", False) and scenario.thermal_camera is None:
        from firefly.sim.thermal_camera import ThermalCameraSpec
        scenario.thermal_camera = ThermalCameraSpec()
    if getattr(args, "video_port", None) is not None:
        scenario.video_port = args.video_port
    if scenario.thermal_camera is not None and scenario.video_port is None:
        scenario.video_port = DEFAULT_VIDEO_PORT
    if scenario.thermal_camera is not None and scenario.video_port:
        last = scenario.video_port + 10 * (args.instance + args.fleet_total - 1)
        if last > 65535:
            raise CliError(f"--video-port: {scenario.video_port} + 10 per instance reaches {last}, past 65535")
    if args.signing_key:
        scenario.signing_key = signing_key_option(args.signing_key)
    if args.startup == "instant":
        scenario.startup = None
    elif args.startup == "realistic" and scenario.startup is None:
        scenario.startup = StartupTimeline()
    outs = [parse_udp(o, "--out") for o in args.out] if args.out else None
    listen = parse_udp(args.listen, "--listen") if args.listen else None
    serials = {n: parse_serial(spec, f"--serial{n}") for n in range(SERIAL_PORTS)
               if (spec := getattr(args, f"serial{n}")) is not None}
    for n, spec in serials.items():
        if spec is not None and spec[0] == "udp":
            if listen is not None:
                raise CliError(f"--serial{n}: one UDP socket per vehicle, and --listen (or another --serialN udp:) "
                               "already names it")
            listen = spec[1:]
        elif spec is not None and spec[0] == "udpclient":
            outs = (outs or []) + [spec[1:]]
    args.serials = serials
    epoch_us = int(time.time() * 1e6)
    built = []
    try:
        for k in range(args.fleet_first, args.fleet_first + args.count):  # k: the vehicle's place in the fleet
            built.append(build_vehicle(args, scenario, k, outs, listen, epoch_us))
    except CliError:
        for node, _ in built:
            node.endpoint.close()
        raise
    return built


def signing_key_option(path: str) -> bytes:
    from ..io.signing_keys import SigningKeyError, read_key_file
    try:
        return read_key_file(Path(path))
    except SigningKeyError as exc:
        raise CliError(f"--signing-key {path}: {exc}") from None


def _offset_port(address: tuple, offset: int) -> tuple:
    return (address[0], address[1] + offset if address[1] else 0)


def build_vehicle(args, scenario, k: int, outs, listen, epoch_us: int):
    """Vehicle k of this process: instance args.instance + k, its own ports, state and seed."""
    from ..faults.link import LinkFaults
    from ..io.board_id import read_machine_id
    from ..io.reboot import bind_link
    from ..io.runner import Node
    from ..mavlink.link import Link
    from ..mavlink.routing import Router
    from ..startup import StartupTimeline
    from ..version import board_id_for

    n = args.instance + k
    offset = 10 * n
    vehicle_outs = [_offset_port(o, 10 * k) for o in outs] if outs else \
        [("127.0.0.1", 14550 + offset), ("127.0.0.1", 14540 + offset)]
    state_root = Path(args.state_dir) if args.state_dir else \
        Path(os.environ.get("XDG_STATE_HOME", Path.home() / ".local" / "state")) / "firefly"
    # What a reboot builds again from the saved state (io/reboot.py): the same vehicle, not wiped,
    # booting as ArduCopter boots (startup.py), its clock and the world starting again.
    power_on = functools.partial(assemble, args, scenario, k, state_root / f"instance-{n}",
                                 board_id_for(read_machine_id(), n), kept={})
    vehicle, session, recorder, log_files = power_on(epoch_us=epoch_us, wipe=args.wipe, startup=scenario.startup)
    endpoint = open_ports(args, k, offset, listen, vehicle_outs)
    tlog = state_log = None
    if args.tlog:
        from ..io.tlog import TlogWriter
        tlog = open_output(TlogWriter, args.tlog, "--tlog", f".{n}.tlog", args.fleet_total, endpoint)
    if args.state_log:
        from ..io.state_log import open_state_log
        state_log = open_output(open_state_log, args.state_log, "--state-log", f".{n}.csv", args.fleet_total, endpoint)
    link = Link(session.codec, session.signing, LinkFaults(vehicle.params, vehicle.config.sim.seed))
    bind_link(link, vehicle, session)
    reboot_startup = scenario.startup or StartupTimeline()
    router = Router(system_id_of(n), vehicle.lists_traffic)
    node = Node(vehicle, session, endpoint, link, router, tlog, state_log, recorder, log_files,
                power_on=functools.partial(power_on, wipe=False, startup=reboot_startup))
    return node, vehicle_outs


def assemble(args, scenario, k: int, state_dir: Path, board_id: str, *, epoch_us: int, wipe: bool,
             startup, powered_on_at_s: float = 0.0, kept: dict | None = None):
    """Vehicle k's vehicle, MAVLink session and dataflash log (recorder, files), from its saved
    state in `state_dir` (or wiped): at start, and again at each reboot (io/reboot.py). `kept`
    holds what outlives a reboot of the autopilot (the thermal camera, a device of its own)."""
    import dataclasses

    from ..io.signing_keys import attach_state
    from ..mavlink.dialect import new_codec
    from ..mavlink.session import Session
    from ..mission import MissionStore
    from ..params import ParamStore
    from ..rates import LoopRates
    from ..vehicle import Vehicle, VehicleConfig

    n = args.instance + k
    params = ParamStore(state_dir / "params.json", wipe=wipe)
    missions_path = state_dir / "missions.json"
    if wipe:
        params.save_all()
        missions_path.unlink(missing_ok=True)
    if not powered_on_at_s:  # [params] and --param: saved before the first boot, kept by later reboots
        for name, value in [*scenario.params.items(), *args.param]:  # the command line has the last word
            params.set(name, value)
    mission = MissionStore(missions_path)
    for store_file in (params.file, mission.file):
        store_file.min_interval_s, store_file.clock = SAVE_EVERY_S, time.monotonic  # the link clock
    rate = scenario.sim.physics_rate_hz
    cols = math.ceil(math.sqrt(args.fleet_total))
    sim = dataclasses.replace(scenario.sim, seed=scenario.seed + k)
    config = VehicleConfig(home=scenario.home, home_yaw_deg=scenario.home_yaw_deg, sim=sim,
                           offset_ne_m=(GRID_SPACING_M * (k // cols), GRID_SPACING_M * (k % cols)),
                           rates=LoopRates(rate, min(400, rate), 100), system_id=system_id_of(n),
                           epoch_unix_us=epoch_us, faults=scenario.faults, startup=startup,
                           board_id=board_id, powered_on_at_s=powered_on_at_s)
    vehicle = Vehicle(config, params, mission)
    params.report("SIM_SPEEDUP", reported_speedup(parse_speedup(args.speedup)))
    vehicle.internal_errors.report = lambda text, n=n: print(
        f"autopilot: system {system_id_of(n)}: internal error: {text}", file=sys.stderr, flush=True)
    if scenario.script and not powered_on_at_s:  # a scenario's script runs once, from the first boot
        from .script import Script
        vehicle.script = Script(scenario.script)
    session = Session(vehicle, new_codec(system_id_of(n)))
    attach_state(session.signing, state_dir / "signing.json", scenario.signing_key, wipe)
    recorder, log_files = attach_dataflash(vehicle, session, state_dir / "logs")
    if scenario.thermal_camera is not None:
        video_port = scenario.video_port + 10 * n if scenario.video_port else 0
        attach_thermal_camera(vehicle, session, scenario.thermal_camera, state_dir / "thermal",
                              {} if kept is None else kept, video_port)
    return vehicle, session, recorder, log_files


def attach_thermal_camera(vehicle, session, spec, directory: Path, kept: dict, video_port: int = 0) -> None:
    """The thermal camera (payload/thermal_camera.py) and its MAVLink component; its card and its
    copy on disk outlive a reboot of the autopilot, as a separate camera's do, and so does its live
    video to 127.0.0.1:video_port (payload/thermal_video.py, io/thermal_video.py; 0: none)."""
    from ..io.thermal_stills import ThermalStills
    from ..mavlink.camera_component import CameraComponent
    from ..payload.camera import MAVLINK_CAMV2
    from ..payload.thermal_camera import ThermalCamera, look_of
    from ..results import Severity
    camera = kept.get("thermal_camera")
    if camera is None:
        camera = kept["thermal_camera"] = ThermalCamera(spec, vehicle.config.sim.world, look=lambda: look_of(vehicle),
                                                        now=lambda: vehicle.time_s, seed=vehicle.config.sim.seed)
        disk = ThermalStills(directory)
        camera.on_still, camera.on_format = disk.write, disk.clear
    camera.look, camera.now = (lambda: look_of(vehicle)), (lambda: vehicle.time_s)
    camera.stop()  # the sim's clock starts again at a reboot
    video = kept.get("thermal_video")
    if video is None and video_port:
        from ..io.thermal_video import VideoSender
        from ..payload.thermal_video import ThermalVideo
        video = kept["thermal_video"] = ThermalVideo(camera, f"udp://127.0.0.1:{video_port}",
                                                     seed=vehicle.config.sim.seed)
        sender = VideoSender(("127.0.0.1", video_port), spec.width_px, spec.height_px, spec.frame_rate_hz,
                             video.bit_rate)
        video.on_frame, video.edge_counters = sender.frame, sender.counters
    if video is not None:
        video.restart()
    component = session.camera_component = CameraComponent(camera, session.codec,
                                                           gimbal_device_id=1 if vehicle.mount.fitted else 0,
                                                           video=video)
    component.on_failure = session.handler_failed
    if vehicle.camera.kind == MAVLINK_CAMV2:  # the autopilot's CAM1 drives it (payload/camera.py)
        vehicle.camera.mavlink_camera = component
        vehicle.notify(component.announcement, Severity.INFO)


# What SIM_SPEEDUP reads when the vehicle runs flat out (--speedup inf): ArduPilot's SITL keeps
# its --speedup there, and a ground station or script divides its timeouts by it; a float that
# is inf would reach it as inf. A finite stand-in of the order one vehicle reaches flat out
# (roughly 1000x on one core, runner.py).
FLAT_OUT_SPEEDUP = 1000.0


def reported_speedup(speedup: float) -> float:
    return FLAT_OUT_SPEEDUP if speedup == math.inf else speedup


def attach_dataflash(vehicle, session, directory: Path):
    """The vehicle's dataflash logs in `directory`: the recorder that writes them, and the files,
    which LOG_REQUEST_* and FTP's logs/ read."""
    from ..dataflash.recorder import Recorder
    from ..io.dataflash_files import LogFiles
    log_files = LogFiles(directory, vehicle.params)
    recorder = Recorder(vehicle, log_files)
    vehicle.text_listener = recorder.text
    vehicle.camera.picture_listener = recorder.picture
    session.logs.store = log_files
    session.ftp.tree.logs = log_files
    return recorder, log_files


def open_output(opener, option_value: str, option: str, per_vehicle_suffix: str, count: int, endpoint):
    """A file a command-line option names (one per vehicle of a --count process, by suffix);
    a file that cannot be opened is the option's one-line error, the ports closed again."""
    path = Path(option_value) if count == 1 else Path(option_value).with_suffix(per_vehicle_suffix)
    try:
        return opener(path)
    except OSError as exc:
        endpoint.close()
        raise CliError(f"{option}: cannot open {path}: {exc.strerror}") from None


DEFAULT_PORT_TRIES = 20  # a default port held by another process: the next in steps of 10, this many times


def open_ports(args, k: int, offset: int, listen, outs):
    """Vehicle k's serial ports (io/ports.py): the UDP socket (--listen, its outputs) and the TCP ones."""
    from ..io.ports import Ports
    from ..io.tcp import TcpClient, TcpServer
    from ..io.udp import UdpEndpoint
    notes = []

    def bind_default(make, kind: str, host: str, port: int):
        """A default port: if another process has it, the next free one 10 up (as the next instance's)."""
        for step in range(DEFAULT_PORT_TRIES):
            try:
                made = make((host, port + 10 * step))
            except OSError:
                continue
            if step:
                notes.append(f"{kind}:{port} in use: {kind}:{port + 10 * step} instead")
            return made
        notes.append(f"{kind}:{port} and the {DEFAULT_PORT_TRIES - 1} ports above it in steps of 10 are in use: "
                     f"no {kind} port")
        return None

    opened: list = []
    try:
        if listen is not None:
            bind = _offset_port(listen, 10 * k)
            try:
                udp = UdpEndpoint(bind, outs)
            except OSError as exc:
                raise CliError(f"--listen: cannot bind udp:{bind[0]}:{bind[1]}: {exc.strerror}") from None
        else:
            udp = bind_default(lambda a: UdpEndpoint(a, outs), "udp", "0.0.0.0", 5760 + offset) \
                or UdpEndpoint(("0.0.0.0", 0), outs)
        opened.append(udp)
        servers, clients = [], []
        serials = getattr(args, "serials", {})
        if 0 not in serials:  # SERIAL0: ArduPilot SITL's TCP server
            server = bind_default(TcpServer, "tcp", "0.0.0.0", 5760 + offset)
            if server is not None:
                servers.append(server)
                opened.append(server)
        for n, spec in sorted(serials.items()):
            if spec is None or spec[0] not in ("tcp", "tcpclient"):
                continue
            kind, host, port = spec
            address = _offset_port((host, port), 10 * k)
            if kind == "tcpclient":
                clients.append(TcpClient(address))
                continue
            try:
                servers.append(TcpServer(address))
            except OSError as exc:
                raise CliError(f"--serial{n}: cannot listen on tcp:{address[0]}:{address[1]}: {exc.strerror}") from None
            opened.append(servers[-1])
    except BaseException:
        for port in opened:
            port.close()
        raise
    ports = Ports(udp, servers, clients)
    ports.notes = [f"autopilot: system {system_id_of(k + args.instance)}: {note}" for note in notes]  # said once all is built
    return ports


def main(argv=None) -> int:
    parent = os.getppid()  # first, before the imports: --exit-with-parent watches this one
    from .scenario import ScenarioError
    try:
        args = build_parser().parse_args(argv)
        speedup = parse_speedup(args.speedup)
        if args.stats:
            check_writable(Path(args.stats), "--stats")
        built = build(args)
    except (CliError, ScenarioError) as exc:
        print(f"autopilot: error: {exc}", file=sys.stderr)
        return 2
    # The rest of a fleet, once this part has built (a bad option or scenario is said once, here)
    parts = start_parts(sys.argv[1:] if argv is None else list(argv), args.fleet_total, args.stats) \
        if args.fleet is None and args.fleet_total > PART_SIZE else []
    from ..io.runner import Runner
    nodes = [node for node, _ in built]
    runner = Runner(nodes, speedup)
    signal.signal(signal.SIGTERM, lambda *_: runner.stop())
    if args.exit_with_parent is not None:
        watch_parent(parent, args.exit_with_parent, runner.stop)
    if not args.quiet:
        for node, _ in built:
            for note in node.endpoint.notes:
                print(note, file=sys.stderr, flush=True)
        for node, outs in built[:10]:
            host, port = node.endpoint.address
            signed = ", MAVLink 2 signing on" if node.session.signing.enabled else ""
            tcp = "".join(f"tcp:{h}:{p}, " for h, p in node.endpoint.tcp_addresses)
            print(f"Firefly autopilot: system {node.vehicle.system_id}, {tcp}udp:{host}:{port}, "
                  f"out {' '.join(f'{h}:{p}' for h, p in outs)}, speedup {args.speedup}{signed}", flush=True)
        if args.fleet_total > 10:
            more = f" in {len(parts)} more processes" if parts else ""
            print(f"... and {args.fleet_total - 10} more vehicles{more}", flush=True)
    escaped, wall0, code = None, time.monotonic(), 0
    try:
        runner.run(args.duration)
    except KeyboardInterrupt:
        pass
    except Exception as exc:
        escaped = exc
        raise
    finally:
        if args.stats:
            from ..io import exit_report
            try:
                exit_report.write(Path(args.stats), runner, nodes, escaped, time.monotonic() - wall0)
            except OSError as exc:  # the rest of the shutdown (signing state, tlog) must still run
                print(f"autopilot: error: --stats {args.stats}: {exc.strerror or exc}", file=sys.stderr)
        for node in nodes:
            node.vehicle.params.file.flush()  # what a flood of changes left for its next write
            node.vehicle.mission.file.flush()
            report_signing(node, args.quiet)
            node.endpoint.close()
            if node.tlog is not None:
                node.tlog.close()
            if node.state_log is not None:
                node.state_log.close()
            if node.log_files is not None:
                node.log_files.stop()
        code = stop_parts(parts)
    return 2 if code else 0


PARENT_POLL_S = 0.5
SAVE_EVERY_S = 0.5  # a store writes its file at most this often (link time); the rest at exit


def fleet_part(text: str) -> tuple[int, int]:
    try:
        return parse_fleet(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def param_setting(text: str) -> tuple[str, float]:
    from ..params import ParamError, checked_value

    name, _, value = text.partition("=")
    try:
        return name, checked_value(name, value)
    except ParamError as exc:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE of a known parameter: {exc}") from None


def video_port_option(text: str) -> int:
    """argparse names the option: the message says only what is wrong."""
    try:
        port = int(text)
    except ValueError:
        port = -1
    if not 0 <= port <= 65535:
        raise argparse.ArgumentTypeError(f"expected a UDP port 1..65535 (0: no video), got {text!r}")
    return port


def positive_pid(text: str) -> int:
    try:
        pid = int(text)
    except ValueError:
        pid = 0
    if pid <= 0:
        raise argparse.ArgumentTypeError(f"expected a process id (a positive integer), got {text!r}")
    return pid


def process_exists(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # somebody else's process: it exists
        return True
    return True


def watch_parent(parent: int, pid: int, stop) -> None:
    """Call stop() once the harness has gone, so that a harness killed without its clean-up (a
    test worker, a campaign worker) leaves no vehicle flying on: process `pid` if given (0: not),
    else the parent this process had at start (gone once this process is re-parented; a parent
    that is PID 1, as in a container, counts as alive while it stays the parent). A daemon
    thread: the loop itself never waits on it."""
    import threading

    def watch():
        if pid:
            while process_exists(pid):
                time.sleep(PARENT_POLL_S)
        else:
            while os.getppid() == parent:
                time.sleep(PARENT_POLL_S)
        stop()
    threading.Thread(target=watch, name="exit-with-parent", daemon=True).start()


def check_writable(path: Path, option: str) -> None:
    """Fail at start, in one line, rather than at exit with a traceback."""
    directory = path.parent if str(path.parent) else Path(".")
    if not directory.is_dir():
        raise CliError(f"{option} {path}: no such directory {directory}")
    if not os.access(directory, os.W_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise CliError(f"{option} {path}: not writable")


def report_signing(node, quiet: bool) -> None:
    """Save the signing timestamp for the next run and say what signing dropped."""
    signing = node.session.signing
    if signing.enabled:
        signing.save()
    if not quiet and (signing.enabled or any(signing.counters.values())):
        print(f"system {node.vehicle.system_id}: {signing.summary()}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
