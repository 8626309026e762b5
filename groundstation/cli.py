"""`groundstation`: the decision-layer companion. Subcommands: demo."""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path


class CliError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        raise CliError(message)


def positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not value > 0 or math.isnan(value):
        raise argparse.ArgumentTypeError(f"must be positive, got {text!r}")
    return value


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="groundstation", description="Firefly decision layer (MAVSDK companion)")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    demo = sub.add_parser("demo", help="take off, fly a square, land (starts its own autopilot unless --url)")
    demo.add_argument("--url", help="MAVSDK connection URL of a running vehicle, e.g. udpin://0.0.0.0:14540")
    demo.add_argument("--speedup", type=positive, default=10.0, help="speedup of the autopilot it starts")
    demo.add_argument("--side", type=positive, default=20.0, help="square side [m]")
    demo.add_argument("--alt", type=positive, default=10.0, help="flight altitude above home [m]")
    demo.add_argument("--plot", type=Path, default=Path("out/demo_track.png"), help="PNG of the flown track")
    mission = sub.add_parser("mission", help="fly a QGroundControl .plan or 'QGC WPL 110' .waypoints file")
    mission.add_argument("file", type=Path, help="mission file (.plan or .waypoints)")
    mission.add_argument("--url", help="MAVSDK connection URL of a running vehicle (default: start one)")
    mission.add_argument("--speedup", type=positive, default=10.0, help="speedup of the autopilot it starts")
    mission.add_argument("--plot", type=Path, default=Path("out/mission_track.png"), help="PNG of planned vs flown")
    return p


def quiet_mavsdk_logs() -> None:
    """MAVSDK's own debug/info lines would drown the progress output; keep warnings and errors."""
    from mavsdk import LogLevel, log_subscribe
    log_subscribe(lambda level, message, file, line: level < LogLevel.WARN)


def main(argv=None) -> int:
    try:
        args = build_parser().parse_args(argv)
    except CliError as exc:
        print(f"groundstation: error: {exc}", file=sys.stderr)
        return 2
    quiet_mavsdk_logs()
    from .mission_files import MissionFileError
    from .vehicle_link import LinkError
    try:
        if args.command == "demo":
            from . import demo
            return demo.run(args.url, args.speedup, args.side, args.alt, args.plot)
        if args.command == "mission":
            from . import mission_runner
            return mission_runner.run(args.file, args.url, args.speedup, args.plot)
    except MissionFileError as exc:
        print(f"groundstation: error: {exc}", file=sys.stderr)
        return 2
    except LinkError as exc:
        print(f"groundstation: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    return 2


if __name__ == "__main__":
    sys.exit(main())
