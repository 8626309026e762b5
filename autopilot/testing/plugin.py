"""Firefly's pytest plugin (registered through the `pytest11` entry point of the installed
package): a fresh simulated ArduCopter for every test that asks for one.

    async def test_returns_home(firefly):
        drone = await firefly.mavsdk()
        ...
        assert firefly.state().distance_from_home_m < 2

Fixtures: `firefly` (the vehicle, a FireflyVehicle) and `firefly_fleet` (every vehicle of the
test's process, when `@pytest.mark.firefly(count=N)` asks for several). Nothing starts for a
test that uses neither. See the README, "Testing your own drone code".
"""
from __future__ import annotations

import inspect
import shutil
from pathlib import Path
from typing import TYPE_CHECKING

import pytest

from . import evidence
from .settings import KEYS, FireflySettings, SettingsError, parse_speedup, seed_for, settings

if TYPE_CHECKING:
    from .run import FireflyRun  # imported when a test asks for a vehicle (below)

RUN_KEY = pytest.StashKey["FireflyRun"]()  # on a test item: its FireflyRun
REPORTS_KEY = pytest.StashKey[dict[str, pytest.TestReport]]()  # on a test item: its reports so far, by phase
SPEEDUP_KEY = pytest.StashKey[float]()  # on the config: --firefly-speedup
EVIDENCE_KEY = pytest.StashKey[Path]()  # on the config: the evidence root, made when a test first needs it


def pytest_addoption(parser):
    group = parser.getgroup("firefly", "Firefly simulated ArduCopter")
    group.addoption("--firefly-speedup", default="10", metavar="X",
                    help="default vehicle speedup for tests using the firefly fixtures (a number or 'inf'; "
                         "a test's @pytest.mark.firefly(speedup=...) wins). Default 10.")
    group.addoption("--firefly-keep", action="store_true",
                    help="keep every test's .tlog, state log and autopilot stderr, not only a failed test's")
    group.addoption("--firefly-evidence", default=None, metavar="DIR",
                    help="put each test's evidence directory under DIR (default: the ini setting firefly_evidence, "
                         "else <rootdir>/.firefly/evidence)")
    parser.addini(evidence.INI, "where Firefly keeps failed tests' evidence, relative to this file "
                                "(default <rootdir>/.firefly/evidence)", default="")


def pytest_configure(config):
    config.addinivalue_line(
        "markers", f"firefly({', '.join(k + '=...' for k in KEYS)}): how the test's simulated vehicle is "
                   "started (Firefly's pytest plugin)")
    try:
        config.stash[SPEEDUP_KEY] = parse_speedup(config.getoption("--firefly-speedup"), "--firefly-speedup")
    except SettingsError as exc:
        raise pytest.UsageError(str(exc)) from None


FIXTURES = ("firefly", "firefly_fleet")
OTHER_ASYNC_MARKERS = ("anyio", "trio")  # another plugin runs these coroutines


@pytest.hookimpl(wrapper=True, trylast=True)
def pytest_pycollect_makeitem(collector, name, obj):
    """An `async def` test that uses a vehicle runs under pytest-asyncio whatever its mode: in a
    project with no pytest configuration (pytest-asyncio's strict mode) the test is given the
    `asyncio` marker, as the user would otherwise have to. trylast makes this wrapper the
    innermost, so the marker is there when pytest-asyncio's own wrapper decides which items to
    take; a test already marked, or marked for anyio or trio, is left as it is."""
    collected = yield
    if not inspect.iscoroutinefunction(obj):
        return collected
    for item in collected if isinstance(collected, list) else [collected]:
        if (isinstance(item, pytest.Function) and any(f in item.fixturenames for f in FIXTURES)
                and not any(item.get_closest_marker(m) for m in ("asyncio", *OTHER_ASYNC_MARKERS))):
            item.add_marker(pytest.mark.asyncio)
    return collected


@pytest.hookimpl(wrapper=True, tryfirst=True)
def pytest_runtest_makereport(item, call):
    report = yield
    item.stash.setdefault(REPORTS_KEY, {})[report.when] = report
    run = item.stash.get(RUN_KEY, None)
    if run is not None and report.failed:
        report.sections.append(("firefly", run.describe()))
    return report


def pytest_sessionfinish(session):
    from .run import stop_all
    stop_all()


def test_identity(item) -> str:
    """The test's module and name ("tests.test_app::TestX::test_y[2]"): its node id without the
    file path, which is relative to pytest's rootdir and so changes with how pytest was invoked."""
    module = getattr(getattr(item, "module", None), "__name__", None)
    return f"{module}::{item.nodeid.split('::', 1)[1]}" if module and "::" in item.nodeid else item.nodeid


def _settings(request) -> FireflySettings:
    defaults = FireflySettings(speedup=request.config.stash[SPEEDUP_KEY], seed=seed_for(test_identity(request.node)))
    markers = list(request.node.iter_markers("firefly"))  # the closest first: test, class, module
    if not markers:
        return defaults
    keys, args = {}, ()
    for marker in reversed(markers):  # a module's marker sets keys a test's marker may override
        keys.update(marker.kwargs)
        args += marker.args
    try:
        return settings(keys, defaults, request.node.path.parent, args)
    except SettingsError as exc:
        problem = str(exc)
    pytest.fail(problem, pytrace=False)  # outside the except: one line, no chained traceback


def _evidence_dir(request) -> Path:
    config = request.config
    if EVIDENCE_KEY not in config.stash:
        config.stash[EVIDENCE_KEY] = evidence.evidence_root(config)
    return evidence.fresh_directory(config.stash[EVIDENCE_KEY], request.node.nodeid)


@pytest.fixture
def firefly_fleet(request):
    """Every vehicle of this test's autopilot process (one unless the marker says count=N)."""
    from .run import FireflyRun
    from .errors import FireflyError
    settings = _settings(request)
    kept = _evidence_dir(request)
    run = None
    try:
        run = FireflyRun(settings, kept)
        request.node.stash[RUN_KEY] = run
        run.start()
        run.prepare()
        problem = None
    except FireflyError as exc:
        problem = str(exc)  # the report's firefly section says the rest
    except BaseException:  # a bug, or Ctrl-C during start-up: the process must not outlive the test
        if run is not None:
            run.stop()
        raise
    if problem is not None:
        if run is not None:
            run.stop()
            run.copy_dataflash_logs()
        pytest.fail(problem, pytrace=False)
    assert run is not None  # started without a problem
    yield run.vehicles
    code = run.stop()
    internal = run.internal_errors()
    reports = request.node.stash.get(REPORTS_KEY, {})
    failed = code != 0 or bool(internal) or any(r.failed for r in reports.values())
    if failed:
        run.copy_dataflash_logs()
    elif not request.config.getoption("--firefly-keep"):
        shutil.rmtree(kept, ignore_errors=True)
    if code != 0:
        pytest.fail(f"firefly: the autopilot ended with status {code} (0 expected after SIGTERM): "
                    f"{run.stderr_tail() or 'it said nothing'}", pytrace=False)
    if internal:  # Firefly's own bug: what the test saw may not be what ArduCopter would do
        pytest.fail(f"firefly: the vehicle had an internal error (a Firefly bug, please report it): "
                    f"{internal[0]}", pytrace=False)


@pytest.fixture
def firefly(firefly_fleet):
    """The test's simulated vehicle (system id 1): MAVSDK and pymavlink clients, its true state,
    waits in vehicle time. Configure it with @pytest.mark.firefly(...)."""
    return firefly_fleet[0]
