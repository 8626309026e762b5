"""Decision layer: the MAVSDK companion that flies the autopilot over MAVLink and searches for a fire.

    cli.py        the `groundstation` command: explore, evaluate, mission, demo
    strategy/     pure decisions: belief, planner, policies, stopping rule, the search controller
    evaluation/   judging them: `evaluate`, the decision-level episodes, the flown episodes
    flight/       flying a vehicle: `explore`, `mission`, `demo`, the MAVSDK link, the readings'
                  feed of the controller, starting an autopilot process
    plots.py, progress.py   the PNGs and the progress display the commands share

It knows the vehicle only through MAVLink, and the world only through sim's scenario schema: it
imports nothing from autopilot/.
"""
