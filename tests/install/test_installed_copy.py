"""The wheel of the checkout gives a working program that fits in: a package left out of
pyproject.toml's packages.find, or a file the build does not ship, fails here rather than on a
user's machine, and so does a top-level name besides `firefly` that could collide with a user's.

The checkout's files (tracked, and untracked but not ignored) are copied aside and a wheel is built
from there: an in-tree build would reuse build/lib, whose stale copies of packages could hide a
missing one. The wheel goes into a fresh venv that sees the test environment's dependencies but
not its editable install of this checkout, and runs from a directory outside the repository, so
nothing of the checkout can stand in for what the install left out.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
import time
from pathlib import Path

import pytest
from pymavlink import mavutil

from tests.sitl.conftest import REPO, free_udp_port
from tests.sitl.pymav import GUIDED, Gcs, mav

pytestmark = pytest.mark.sitl


def checkout_files() -> list[str]:
    """What a commit of the working tree would hold: tracked files and untracked unignored ones."""
    listed = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"], cwd=REPO,
                            capture_output=True, text=True, check=True).stdout
    return [name for name in listed.split("\0") if name and ((REPO / name).is_file() or (REPO / name).is_symlink())]


def dependency_dirs() -> list[str]:
    """Where this interpreter's installed packages live. Directories only: the .pth files in them
    (among them the editable install of the checkout) are not read when listed in another's .pth."""
    paths = sysconfig.get_paths()
    return sorted({paths["purelib"], paths["platlib"]})


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """`pip wheel --no-deps` of a copy of the checkout (the links under firefly/ copied as links)."""
    root = tmp_path_factory.mktemp("wheel")
    source = root / "source"
    for name in checkout_files():
        (source / name).parent.mkdir(parents=True, exist_ok=True)
        if (REPO / name).is_symlink():
            (source / name).symlink_to(os.readlink(REPO / name))
        else:
            shutil.copy2(REPO / name, source / name)
    built = subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "--wheel-dir",
                            str(root / "dist"), str(source)], cwd=root, capture_output=True, text=True)
    assert built.returncode == 0, f"pip wheel failed:\n{built.stdout}\n{built.stderr}"
    (found,) = (root / "dist").glob("firefly_sitl-*.whl")
    return found


@pytest.fixture(scope="module")
def installed(wheel, tmp_path_factory) -> Path:
    """A fresh venv holding the wheel (its commands too); returns its python."""
    venv = tmp_path_factory.mktemp("installed") / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    python = venv / "bin" / "python"
    pip = subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install", "--quiet", "--no-deps",
                          str(wheel)], capture_output=True, text=True)
    assert pip.returncode == 0, f"pip install of the wheel failed:\n{pip.stdout}\n{pip.stderr}"
    (site_packages(python) / "test-dependencies.pth").write_text("\n".join(dependency_dirs()) + "\n")
    return python


def site_packages(python: Path) -> Path:
    return Path(subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                               capture_output=True, text=True, check=True).stdout.strip())


def without_pythonpath() -> dict:
    return {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}


def run_installed(python: Path, *args: str, **kw) -> subprocess.CompletedProcess:
    """`python args` from the venv's own directory (outside the repository, no packages there),
    with nothing but the venv on its path."""
    return subprocess.run([str(python), *args], cwd=python.parents[1], env=without_pythonpath(), capture_output=True,
                          text=True, timeout=60, **kw)


def test_the_install_adds_one_import_name_and_two_commands(installed):
    """Only `firefly` (and the distribution's metadata) lands on the import path: a user's own
    `sim` or `autopilot` cannot be shadowed. The commands keep their names."""
    added = {p.name for p in site_packages(installed).iterdir()} - {"test-dependencies.pth", "_virtualenv.pth",
                                                                     "_virtualenv.py", "__pycache__"}
    assert {n for n in added if not n.endswith(".dist-info")} == {"firefly"}, sorted(added)
    scripts = installed.parent
    assert (scripts / "autopilot").exists() and (scripts / "groundstation").exists()
    run = subprocess.run([str(scripts / "autopilot"), "--help"], capture_output=True, text=True, timeout=60,
                         env=without_pythonpath(), cwd=scripts)
    assert run.returncode == 0 and "usage: autopilot" in run.stdout, run.stderr


def test_the_vehicle_and_plugin_need_no_science_or_plots(installed, wheel):
    """scipy and matplotlib are the decision layer's (the `explore` extra): the vehicle, its
    command line and the pytest plugin import without them."""
    import zipfile
    with zipfile.ZipFile(wheel) as zipped:
        (metadata,) = [n for n in zipped.namelist() if n.endswith(".dist-info/METADATA")]
        requires = [line for line in zipped.read(metadata).decode().splitlines() if line.startswith("Requires-Dist:")]
    plain = [r for r in requires if "extra ==" not in r]
    assert not [r for r in plain if "scipy" in r or "matplotlib" in r], plain
    assert any("pytest-asyncio" in r for r in plain), plain
    probe = run_installed(installed, "-c", (
        "import sys; sys.modules.update(scipy=None, matplotlib=None); "
        "import firefly.autopilot.cli.main, firefly.autopilot.testing.plugin, firefly.autopilot.vehicle"))
    assert probe.returncode == 0, probe.stderr
    search = run_installed(installed, "-c", (
        "import sys; sys.modules.update(scipy=None, matplotlib=None); "
        "from firefly.groundstation.cli import main; sys.exit(main(['evaluate', '--episodes', '1']))"))
    assert search.returncode == 2 and search.stderr.strip().splitlines() == [
        "groundstation: error: evaluate needs scipy, which comes with the explore extra: "
        "pip install 'firefly-sitl[explore]'"], search.stderr


def test_every_package_comes_from_the_installed_copy(installed):
    probe = run_installed(installed, "-c", (
        "import json; from firefly import autopilot, groundstation, sim; "
        "from firefly.autopilot.control import compiled; "
        "print(json.dumps({'files': [m.__file__ for m in (autopilot, groundstation, sim)], "
        "'compiled': compiled.available(), 'required': compiled.required(), 'why': compiled.why_missing()}))"))
    assert probe.returncode == 0, probe.stderr
    found = json.loads(probe.stdout)
    venv = installed.parents[1]
    assert all(Path(f).is_relative_to(venv) for f in found["files"]), found["files"]
    if found["required"]:  # in CI the install must have built the compiled cascade (setup.py)
        assert found["compiled"], found["why"]


def test_the_installed_groundstation_starts(installed):
    run = run_installed(installed, "-m", "firefly.groundstation", "--help")
    assert run.returncode == 0, run.stderr
    assert "usage: groundstation" in run.stdout


def heartbeat_or_exit(url: str, process: subprocess.Popen, timeout: float) -> bool:
    """Whether a HEARTBEAT arrives before the process exits (a broken install dies at once)."""
    conn = mavutil.mavlink_connection(url, source_system=255, source_component=190)
    try:
        deadline = time.monotonic() + timeout
        while process.poll() is None and time.monotonic() < deadline:
            if conn.recv_match(type="HEARTBEAT", blocking=True, timeout=0.2) is not None:
                return True
        return False
    finally:
        conn.close()


def test_the_installed_autopilot_answers_and_arms_in_guided(installed, tmp_path):
    port = free_udp_port()
    log = tmp_path / "autopilot.err"
    with open(log, "w") as err:
        process = subprocess.Popen(
            [str(installed), "-m", "firefly.autopilot", "--listen", "udp:127.0.0.1:0", "--out", f"udp:127.0.0.1:{port}",
             "--speedup", "inf", "--duration", "3600", "--state-dir", str(tmp_path / "state"), "--wipe", "--quiet"],
            cwd=tmp_path, stderr=err, env=without_pythonpath())
    url, gcs = f"udpin:127.0.0.1:{port}", None
    try:
        if not heartbeat_or_exit(url, process, timeout=20.0):
            process.kill()
            process.wait()
            pytest.fail(f"the installed autopilot sent no HEARTBEAT (exit {process.returncode}):\n{log.read_text()}")
        gcs = Gcs(url)
        assert gcs.command(mav.MAV_CMD_DO_SET_MODE, 1, GUIDED) == mav.MAV_RESULT_ACCEPTED
        assert gcs.command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1) == mav.MAV_RESULT_ACCEPTED
        armed = gcs.recv("HEARTBEAT", 10, lambda m: m.base_mode & mav.MAV_MODE_FLAG_SAFETY_ARMED
                         and m.custom_mode == GUIDED)
        assert armed is not None, "no armed GUIDED HEARTBEAT"
    finally:
        if gcs is not None:
            gcs.close()
        if process.poll() is None:
            process.terminate()
            process.wait(timeout=10)


def test_the_container_recipe_runs_as_written(installed, tmp_path):
    """The Dockerfile's ENTRYPOINT and CMD, run by the installed `autopilot` command (no Docker
    engine here: docs/container.md says what was and was not tested), serve TCP: a client there
    gets a HEARTBEAT. Only the published port and the volume's path are changed for the test."""
    text = (REPO / "Dockerfile").read_text()
    entrypoint = json.loads(next(line for line in text.splitlines() if line.startswith("ENTRYPOINT"))[len("ENTRYPOINT"):])
    command = json.loads(next(line for line in text.splitlines() if line.startswith("CMD"))[len("CMD"):])
    assert entrypoint[0] == "autopilot" and "tcp:0.0.0.0:5760" in entrypoint
    import socket
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    argv = [a.replace("tcp:0.0.0.0:5760", f"tcp:127.0.0.1:{port}").replace("/var/lib/firefly", str(tmp_path / "state"))
            for a in entrypoint[1:] + command]
    process = subprocess.Popen([str(installed.parent / "autopilot"), *argv, "--out", f"udp:127.0.0.1:{free_udp_port()}"],
                               cwd=tmp_path, env=without_pythonpath(), stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 20
        conn = None
        while conn is None and time.monotonic() < deadline and process.poll() is None:
            try:
                conn = mavutil.mavlink_connection(f"tcp:127.0.0.1:{port}", source_system=255, retries=0)
            except OSError:
                time.sleep(0.1)  # the server is not listening yet: nothing else to wait on
        assert conn is not None, f"no TCP server (exit {process.poll()})"
        try:
            assert conn.recv_match(type="HEARTBEAT", blocking=True, timeout=10) is not None
        finally:
            conn.close()
    finally:
        process.terminate()
        process.wait(timeout=10)
