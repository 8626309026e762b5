"""`groundstation`: the decision-layer companion. Subcommands: explore and evaluate (the fire search,
flown and judged), mission and demo."""
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
    mission.add_argument("--camera-url", help="pymavlink URL where the vehicle's messages arrive, to show its "
                                              "photos (CAMERA_FEEDBACK) with --url; a started autopilot needs none")
    explore = sub.add_parser("explore", help="find the fire: fly the exploration strategy (starts its own autopilot unless --url)")
    explore.add_argument("--url", help="MAVSDK connection URL of a running vehicle (with --vehicles K: K URLs, "
                                       "comma-separated, the first vehicle's home being the area's origin)")
    explore.add_argument("--vehicles", type=count, default=1, metavar="K",
                         help="search with K vehicles together (default 1); without --url one autopilot process "
                              "with K vehicles is started")
    explore.add_argument("--scenario", type=Path, default=None, help="scenario TOML (world geometry; truth for the report)")
    explore.add_argument("--policy", default=None,
                         help="strategy policy (gig, infotaxis, greedy, lawnmower, ...; default gig) or, with "
                              "--vehicles above 1, team policy (joint, independent, strips; default joint)")
    explore.add_argument("--speedup", type=positive, default=20.0, help="speedup of the autopilot it starts")
    explore.add_argument("--plot", type=Path, default=Path("out/explore.png"), help="PNG of track over final belief")
    explore.add_argument("--no-truth", action="store_true", help="do not mark the scenario's fire (unknown world)")
    explore.add_argument("--max-fires", type=count, default=None,
                         help="fires to look for at most (default: not told, as many as there are; a team: 1); "
                              "the search goes on after a find until it has them all or is confident there is "
                              "no other")
    explore.add_argument("--told-wind", action="store_true",
                         help="tell the search the wind the vehicle reports in WIND (zero unless its EKF fuses drag, "
                              "as ArduCopter's EK3_DRAG_*); default: the search estimates it from how the vehicle leans")
    explore.add_argument("--sensor", choices=("point", "camera"), default="point",
                         help="point: the downward temperature sensor alone (default); camera: also a thermal "
                              "still at each observation point, taken through the camera protocol (component 100) "
                              "and downloaded by MAVLink FTP (a started autopilot is fitted with the camera)")
    ev = sub.add_parser("evaluate", help="judge the fire-localization policies on seeded decision-level episodes")
    ev.add_argument("--scenario", type=Path, default=Path("scenarios/default.toml"), help="scenario TOML file")
    ev.add_argument("--episodes", type=count, default=200, help="episodes per policy (default 200)")
    ev.add_argument("--seed", type=integer, default=None, help="episode seed (default: the scenario's seed)")
    ev.add_argument("--policies", default=None,
                    help="comma-separated: gig, infotaxis, greedy, lawnmower, zigzag, random, gradient (default "
                         "gig,lawnmower,zigzag); with --vehicles above 1: joint, independent, strips (default all)")
    ev.add_argument("--vehicles", type=count, default=1, metavar="K",
                    help="K vehicles search each episode together (team policies); flown with --flight as one "
                         "autopilot process with K vehicles")
    ev.add_argument("--start", choices=("corner", "centre", "spread"), default="corner",
                    help="where the vehicle starts (spread: a team's vehicles one per corner)")
    ev.add_argument("--kernel", choices=("R", "G"), default=None, help="override the scenario's kernel")
    ev.add_argument("--sensor", choices=("point", "camera"), default="point",
                    help="point: the downward temperature sensor alone (default); camera: a thermal frame "
                         "(nadir, 160x120, 57 deg) besides every reading, and planners that score the frame's footprint")
    ev.add_argument("--noise", type=non_negative, default=None, help="override the sensor noise [K]")
    ev.add_argument("--survey-alt", type=positive, default=None, metavar="M",
                    help="override the scenario's survey height [m] (the episodes start and search there)")
    ev.add_argument("--threshold", type=fraction, default=0.99, help="3x3 belief mass that declares (default 0.99)")
    ev.add_argument("--confirm", type=non_negative, default=10.0, metavar="M",
                    help="declare only after a reading within M metres of the cell's centre (default 10)")
    ev.add_argument("--no-confirm", action="store_true", help="declare as soon as the belief is confident")
    ev.add_argument("--subcells", type=count, default=3, help="sub-positions per cell side in the belief (default 3)")
    ev.add_argument("--outlier-rate", type=share, default=0.02,
                    help="the belief's prior share of wild readings (default 0.02; 0 = the plain Gaussian model)")
    ev.add_argument("--further-prior", type=probability, default=0.5, metavar="P",
                    help="not told how many fires: prior probability of no further fire once one is found "
                         "(default 0.5)")
    ev.add_argument("--clear", type=fraction, default=0.98, metavar="P",
                    help="not told how many fires: probability of no further fire that ends the search "
                         "(default 0.98)")
    ev.add_argument("--fires", type=count, default=1,
                    help="fires drawn per episode (default 1); found fires are counted per fire")
    ev.add_argument("--fire-spacing", type=positive, default=None, metavar="M",
                    help="with --fires 2: the second fire M metres from the first, as strong (a random bearing)")
    ev.add_argument("--max-fires", type=count, default=None,
                    help="fires the search looks for at most (default: not told, as many as there are; a team: "
                         "1); it goes on after a find until it has them all or is confident there is no other")
    winds = ev.add_mutually_exclusive_group()
    winds.add_argument("--told-wind", action="store_true",
                       help="tell the search the scenario's wind, as a vehicle fusing drag reports it in WIND; "
                            "flown episodes read the vehicle's WIND (default: the search estimates it from how "
                            "the vehicle leans)")
    winds.add_argument("--ignore-wind", action="store_true",
                       help="the search takes the air as calm: neither told nor estimating (the search before issue 30; "
                            "not with --flight)")
    ev.add_argument("--budget", type=positive, default=6000.0, help="path budget [m] before a forced declaration")
    ev.add_argument("--speed", type=positive, default=5.0,
                    help="survey speed [m/s], flown too with --flight; one observation per second")
    ev.add_argument("--fixed-fire", action="store_true", help="use the scenario's fires and ambient in every episode")
    ev.add_argument("--jobs", type=count, default=1, help="worker processes (default 1: decision times undisturbed)")
    ev.add_argument("--json", type=Path, default=None, help="write every episode's result to this JSON file")
    ev.add_argument("--plot", type=Path, default=None, help="write a PNG of the path-length distributions")
    ev.add_argument("--flight", type=count, default=None, metavar="K",
                    help="also fly the first K episodes end to end through the real autopilot with the first policy")
    ev.add_argument("--flight-speedup", type=positive, default=20.0, help="speedup of the flown episodes (default 20)")
    ev.add_argument("--flight-plots", type=Path, default=None, metavar="DIR",
                    help="write each flown episode's track over its belief to DIR/flight_K.png")
    camp = sub.add_parser("campaign", help="run a campaign file: episodes over a sweep of conditions, decided and "
                                           "flown, on a local process pool or on Ray; resumable")
    camp.add_argument("campaign", type=Path, help="campaign TOML file (see groundstation/campaign/spec.py)")
    camp.add_argument("--out", type=Path, default=None,
                      help="folder for results.jsonl, report.md/json and the PNGs (default out/campaign/NAME)")
    camp.add_argument("--jobs", type=count, default=None, help="local worker processes (default: one per core)")
    camp.add_argument("--resume", action="store_true", help="run only what the results file does not hold yet")
    where = camp.add_mutually_exclusive_group()
    where.add_argument("--ray", action="store_true", help="run on a Ray started here (pip install 'firefly-sitl[ray]')")
    where.add_argument("--ray-address", default=None, metavar="ADDR",
                       help="run on the Ray cluster at ADDR (HOST:PORT of its head, ray://HOST:PORT, or auto)")
    return p


def count(text: str) -> int:
    value = integer(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {text!r}")
    return value


def integer(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None


def non_negative(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not value >= 0 or math.isinf(value):
        raise argparse.ArgumentTypeError(f"must be zero or positive, got {text!r}")
    return value


def share(text: str) -> float:
    """A proportion in [0, 1)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not 0 <= value < 1:
        raise argparse.ArgumentTypeError(f"must be within [0, 1), got {text!r}")
    return value


def fraction(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not 0 < value <= 1:
        raise argparse.ArgumentTypeError(f"must be within (0, 1], got {text!r}")
    return value


def probability(text: str) -> float:
    """A prior probability: within (0, 1), both excluded (a prior of 0 or 1 no reading can move)."""
    value = fraction(text)
    if value == 1:
        raise argparse.ArgumentTypeError(f"must be within (0, 1), got {text!r}")
    return value


def main(argv=None) -> int:
    try:
        args = build_parser().parse_args(argv)
    except CliError as exc:
        print(f"groundstation: error: {exc}", file=sys.stderr)
        return 2
    if args.command not in ("evaluate", "campaign") or getattr(args, "flight", None):
        from .flight.mavsdk_logs import quiet_mavsdk_logs
        quiet_mavsdk_logs()
    try:
        return guarded(args)
    except ModuleNotFoundError as exc:
        if (exc.name or "").split(".")[0] not in EXPLORE_EXTRA:
            raise
        print(f"groundstation: error: {args.command} needs {exc.name.split('.')[0]}, which comes with the "
              f"explore extra: pip install 'firefly-sitl[explore]'", file=sys.stderr)
        return 2


def guarded(args) -> int:
    """The command, its expected failures said in one line."""
    from .evaluation.evaluate import EvaluateError
    from .flight.autopilot_process import AutopilotExited
    from .flight.mission_files import MissionFileError
    from .flight.vehicle_link import LinkError
    try:
        return run_command(args)
    except (EvaluateError, MissionFileError, ValueError) as exc:  # ScenarioError is a ValueError
        print(f"groundstation: error: {exc}", file=sys.stderr)
        return 2
    except (LinkError, AutopilotExited) as exc:
        print(f"groundstation: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130


EXPLORE_EXTRA = ("scipy", "matplotlib")  # pyproject.toml's `explore` extra: the search's science and plots


def run_command(args) -> int:
    if args.command == "campaign":
        from .campaign.run import run
        return run(args)
    if args.command == "evaluate":
        from .evaluation.evaluate import evaluate
        return evaluate(args)
    if args.command == "demo":
        from .flight import demo
        return demo.run(args.url, args.speedup, args.side, args.alt, args.plot)
    if args.command == "explore" and args.vehicles > 1 and args.sensor != "point":
        print("explore: --sensor camera flies one vehicle; a team carries the point sensor only", file=sys.stderr)
        return 2
    if args.command == "explore" and args.vehicles > 1:
        from .flight import team_explore
        return team_explore.run(args.url, args.scenario, args.policy or "joint", args.speedup, args.plot,
                                not args.no_truth, args.vehicles, args.max_fires or 1)
    if args.command == "explore":
        from .flight import explore
        return explore.run(args.url, args.scenario, args.policy or "gig", args.speedup, args.plot, not args.no_truth,
                           args.max_fires, args.told_wind, args.sensor)
    from .flight import mission
    return mission.run(args.file, args.url, args.speedup, args.plot, args.camera_url)


if __name__ == "__main__":
    sys.exit(main())
