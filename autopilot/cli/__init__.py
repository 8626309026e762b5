"""The `autopilot` command: options, the scenario tables the vehicle reads, scripted commands, assembly."""
