"""Where a test's evidence lives: one directory per test under a stable root, so that a failed
test's .tlog, state log, stderr and dataflash logs are still there after later pytest runs
(pytest's own temporary directories keep only the last three sessions).

The root is `--firefly-evidence DIR` (relative to where pytest was started), else the ini setting
`firefly_evidence` (relative to the ini file), else `<rootdir>/.firefly/evidence`. A test's
directory is named after its node id and emptied when the test starts again.
"""
from __future__ import annotations

import re
import shutil
import zlib
from pathlib import Path

DEFAULT_ROOT = Path(".firefly", "evidence")  # under pytest's rootdir
INI = "firefly_evidence"
MAX_NAME_CHARS = 120
PLAIN = r"A-Za-z0-9_.\-\[\]="  # kept as they are in a directory name


def evidence_root(config) -> Path:
    """The directory every test's evidence directory goes under (created, with a .gitignore when
    it is the default one)."""
    given = config.getoption("--firefly-evidence")
    if given:
        root = Path(config.invocation_params.dir, given)  # as the user typed it, not from a worker's cwd
    elif config.getini(INI):
        base = config.inipath.parent if config.inipath is not None else config.rootpath
        root = Path(base, config.getini(INI))
    else:
        root = config.rootpath / DEFAULT_ROOT
        ignore = root.parent / ".gitignore"
        if not ignore.exists():
            root.parent.mkdir(parents=True, exist_ok=True)
            ignore.write_text("# Firefly's pytest plugin: evidence of failed tests, not for version control\n*\n")
    root.mkdir(parents=True, exist_ok=True)
    return root


def directory_name(node_id: str) -> str:
    """A file name for a node id: "tests/test_app.py::TestX::test_y[2]" gives
    "tests_test_app.py__TestX__test_y[2]"; a name that lost other characters, or was cut short,
    ends in its node id's checksum so that two tests never share one."""
    path, _, inside = node_id.partition("::")  # the file's path; the class, test and parameters
    name = path.replace("/", "_") + ("__" + inside.replace("::", "__") if inside else "")
    plain = re.sub(f"[^{PLAIN}]+", "_", name)
    if plain != name or len(plain) > MAX_NAME_CHARS:
        plain = f"{plain[:MAX_NAME_CHARS]}-{zlib.crc32(node_id.encode()):08x}"
    return plain


def fresh_directory(root: Path, node_id: str) -> Path:
    """The test's directory under `root`, emptied of what an earlier run of the test left."""
    directory = root / directory_name(node_id)
    shutil.rmtree(directory, ignore_errors=True)
    directory.mkdir(parents=True)
    return directory


def dataflash_logs(state_dir: Path) -> list[Path]:
    """The dataflash logs (`logs/*.BIN`) the vehicles wrote under their state directory."""
    if not state_dir.is_dir():
        return []
    return sorted(p for p in state_dir.rglob("*.BIN") if p.parent.name == "logs" and p.is_file())


def copy_name(state_dir: Path, log: Path) -> str:
    """A dataflash log's name beside the .tlog: its path below the state directory without the
    `logs` folder ("instance-0/logs/00000001.BIN" gives "instance-0-00000001.BIN")."""
    return "-".join(part for part in log.relative_to(state_dir).parts if part != "logs")


def copy_dataflash_logs(state_dir: Path, evidence_dir: Path) -> list[Path]:
    """Copy each dataflash log to the top of the evidence directory; the copies."""
    copies = []
    for log in dataflash_logs(state_dir):
        copy = evidence_dir / copy_name(state_dir, log)
        shutil.copyfile(log, copy)
        copies.append(copy)
    return copies
