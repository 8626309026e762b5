"""Autopilot processes started warm: a server that has imported the autopilot once forks each one.

`python -m firefly.autopilot` spends about a second of CPU importing before its first heartbeat,
and a test suite or an evaluation campaign starts hundreds of vehicles. Here one server process per
(interpreter, working directory, environment) imports the autopilot's modules and, asked, forks a
child that runs `python -m firefly.autopilot` with the caller's arguments, working directory,
environment and standard streams (passed as file descriptors, so a child's stderr goes where a
Popen's would). A start then takes a few milliseconds.

The server is single-threaded and imports only, so each child starts as a fresh process would,
the autopilot's own code unrun. What differs from a cold start: the child's parent is the server
(so `--exit-with-parent` is always given the caller's pid), its command line in `ps` is the
server's, and Python's hash seed is the server's.

WarmProcess stands in for subprocess.Popen (pid, poll, wait, send_signal, terminate, kill,
returncode). FIREFLY_COLD_START=1 turns the server off: every start is a plain Popen.
"""
from __future__ import annotations

import array
import errno
import json
import os
import select
import signal
import socket
import struct
import subprocess
import sys
import threading
import time
import traceback
from collections.abc import Sequence

PRELOAD = ("firefly.autopilot.cli.main", "firefly.autopilot.cli.scenario", "firefly.autopilot.mavlink.session",
           "firefly.autopilot.mavlink.link", "firefly.autopilot.io.runner", "firefly.autopilot.io.ports",
           "firefly.autopilot.dataflash.recorder", "firefly.autopilot.vehicle", "numpy.random")
MODULE = "firefly.autopilot"
_HEADER = struct.Struct("<I")
_STREAMS = 3  # stdin, stdout, stderr: passed with each request
START_WALL_S = 30.0  # a server that has not answered a start in this long is broken


def _send(sock: socket.socket, message: dict, fds: Sequence[int] = ()) -> None:
    data = json.dumps(message).encode()
    frame = _HEADER.pack(len(data)) + data
    if fds:
        sock.sendmsg([frame], [(socket.SOL_SOCKET, socket.SCM_RIGHTS, array.array("i", fds))])
    else:
        sock.sendall(frame)


class _Reader:
    """Length-prefixed JSON messages (and the descriptors that came with them) off a stream socket."""

    def __init__(self, sock: socket.socket):
        self.sock, self.buffer = sock, b""
        self.fds: list[int] = []

    def read(self) -> bool:
        """One receive; False at end of stream."""
        fds = array.array("i")
        data, ancillary, _, _ = self.sock.recvmsg(65536, socket.CMSG_LEN(_STREAMS * fds.itemsize))
        for level, kind, payload in ancillary:
            if level == socket.SOL_SOCKET and kind == socket.SCM_RIGHTS:
                fds.frombytes(payload[:len(payload) - len(payload) % fds.itemsize])
        self.fds.extend(fds)
        self.buffer += data
        return bool(data)

    def messages(self):
        while len(self.buffer) >= _HEADER.size:
            (size,) = _HEADER.unpack_from(self.buffer)
            if len(self.buffer) < _HEADER.size + size:
                return
            body, self.buffer = self.buffer[_HEADER.size:_HEADER.size + size], self.buffer[_HEADER.size + size:]
            yield json.loads(body)


# ----- the caller's side -----------------------------------------------------------------------

class WarmServer:
    """A server process and the one connection to it; its children's exits as they are reported."""

    def __init__(self, cwd: str | None, env: dict):
        self.sock, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_STREAM)
        self.process = subprocess.Popen([sys.executable, "-m", "firefly.groundstation.flight.warm_start",
                                         str(theirs.fileno())], cwd=cwd, env=env, pass_fds=[theirs.fileno()],
                                        stdin=subprocess.DEVNULL)
        theirs.close()
        self.reader = _Reader(self.sock)
        self.lock = threading.Lock()
        self.exits: dict[int, int] = {}
        self.started: list[int] = []
        self.broken = False

    def start(self, argv: list[str], cwd: str | None, env: dict, streams: list[int]) -> int:
        with self.lock:
            _send(self.sock, {"argv": argv, "cwd": cwd, "env": env}, streams)
            deadline = time.monotonic() + START_WALL_S
            while not self.started:
                self._pump(max(0.0, deadline - time.monotonic()))
                if time.monotonic() >= deadline and not self.started:
                    raise OSError("the warm-start server did not answer")
            pid = self.started.pop(0)
        if pid < 0:
            raise OSError(-pid, os.strerror(-pid))
        return pid

    def exit_code(self, pid: int, timeout_s: float | None) -> int | None:
        """The child's exit status once reported (Popen's returncode), waiting up to timeout_s."""
        deadline = None if timeout_s is None else time.monotonic() + timeout_s
        with self.lock:
            while pid not in self.exits:
                left = None if deadline is None else max(0.0, deadline - time.monotonic())
                self._pump(left)
                if pid not in self.exits and left == 0.0:
                    return None
            return self.exits[pid]

    def _pump(self, timeout_s: float | None) -> None:
        self.sock.settimeout(timeout_s)
        try:
            alive = self.reader.read()
        except (socket.timeout, BlockingIOError):
            return
        if not alive:
            self.broken = True
            raise OSError("the warm-start server exited")
        for message in self.reader.messages():
            if "pid" in message:
                self.started.append(message["pid"])
            else:
                self.exits[message["exited"]] = message["code"]


class WarmProcess:
    """A child of the warm server, as a Popen: pid, poll(), wait(), send_signal(), terminate(), kill()."""

    def __init__(self, server: WarmServer, pid: int, args: list[str]):
        self.server, self.pid, self.args = server, pid, args
        self.returncode: int | None = None

    def poll(self) -> int | None:
        if self.returncode is None:
            self.returncode = self.server.exit_code(self.pid, 0.0)
        return self.returncode

    def wait(self, timeout: float | None = None) -> int:
        if self.returncode is None:
            self.returncode = self.server.exit_code(self.pid, timeout)
            if self.returncode is None:
                raise subprocess.TimeoutExpired(self.args, timeout or 0.0)
        return self.returncode

    def send_signal(self, sig: int) -> None:
        if self.poll() is None:  # (its pid is not reused before the server reaps it and says so)
            try:
                os.kill(self.pid, sig)
            except ProcessLookupError:
                pass

    def terminate(self) -> None:
        self.send_signal(signal.SIGTERM)

    def kill(self) -> None:
        self.send_signal(signal.SIGKILL)


_servers: dict[tuple, WarmServer] = {}
_servers_lock = threading.Lock()


def popen_autopilot(args: list[str], cwd=None, env: dict | None = None, stdin=None, stdout=None, stderr=None):
    """`python -m firefly.autopilot *args`, warm where it can be (else a plain Popen). The streams
    are file objects or descriptors (None: this process's own), as Popen takes them."""
    env = dict(os.environ if env is None else env)
    cmd = [sys.executable, "-m", MODULE, *args]
    if os.environ.get("FIREFLY_COLD_START") or not hasattr(os, "fork") or not hasattr(socket, "AF_UNIX"):
        return subprocess.Popen(cmd, cwd=cwd, env=env, stdin=stdin, stdout=stdout, stderr=stderr)
    cwd = str(cwd) if cwd is not None else os.getcwd()
    # (the working directory is in the key: `-m` puts it first on the server's import path)
    key = (sys.executable, cwd, env.get("PYTHONPATH"), os.getpid())
    with _servers_lock:
        server = _servers.get(key)
        if server is None or server.broken or server.process.poll() is not None:
            server = _servers[key] = WarmServer(cwd, env)
    opened: list[int] = []
    streams = [_fd(stream, default, opened) for stream, default in ((stdin, 0), (stdout, 1), (stderr, 2))]
    try:
        return WarmProcess(server, server.start(args, cwd, env, streams), cmd)
    except OSError:
        server.broken = True
        return subprocess.Popen(cmd, cwd=cwd, env=env, stdin=stdin, stdout=stdout, stderr=stderr)
    finally:
        for fd in opened:  # (the server holds its own copy once sent)
            os.close(fd)


def _fd(stream, default: int, opened: list[int]) -> int:
    if stream is None:
        return default
    if stream == subprocess.DEVNULL:
        opened.append(os.open(os.devnull, os.O_RDWR))
        return opened[-1]
    return stream if isinstance(stream, int) else stream.fileno()


# ----- the server's side -----------------------------------------------------------------------

def serve(fd: int) -> None:
    """Import the autopilot, then fork a child per request until the caller's end closes."""
    sock = socket.socket(fileno=fd)
    for name in PRELOAD:
        try:
            __import__(name)
        except Exception:  # noqa: BLE001 - a module that will not import fails in the child, as cold
            pass
    wake_r, wake_w = os.pipe()
    os.set_blocking(wake_w, False)
    signal.set_wakeup_fd(wake_w)
    signal.signal(signal.SIGCHLD, lambda *_: None)  # (a handler, so that the wake-up fd is written)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the caller's Ctrl-C is the caller's
    reader = _Reader(sock)
    while True:
        try:
            ready, _, _ = select.select([sock.fileno(), wake_r], [], [])
        except InterruptedError:
            continue
        if wake_r in ready:
            os.read(wake_r, 4096)
        _reap(sock)
        if sock.fileno() in ready:
            if not reader.read():
                return
            for request in reader.messages():
                streams, reader.fds = reader.fds[:_STREAMS], reader.fds[_STREAMS:]
                pid = _fork_child(request, streams, (sock.fileno(), wake_r, wake_w))
                for stream in streams:
                    os.close(stream)
                _send(sock, {"pid": pid})


def _reap(sock: socket.socket) -> None:
    while True:
        try:
            pid, status = os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            return
        if pid == 0:
            return
        _send(sock, {"exited": pid, "code": os.waitstatus_to_exitcode(status)})


def _fork_child(request: dict, streams: list[int], server_fds: tuple) -> int:
    try:
        pid = os.fork()
    except OSError as exc:
        return -(exc.errno or errno.EAGAIN)
    if pid:
        return pid
    code = 1
    try:
        signal.set_wakeup_fd(-1)
        signal.signal(signal.SIGCHLD, signal.SIG_DFL)
        signal.signal(signal.SIGINT, signal.default_int_handler)  # a cold Python's: KeyboardInterrupt
        for fd in server_fds:
            os.close(fd)
        for target, fd in enumerate(streams):
            os.dup2(fd, target)
            os.close(fd)
        if request["cwd"] is not None:
            os.chdir(request["cwd"])
        os.environ.clear()
        os.environ.update(request["env"])
        if request["env"].get("PYTHONUNBUFFERED"):
            sys.stdout.reconfigure(write_through=True)  # type: ignore[union-attr]
        import runpy
        sys.argv = [MODULE, *request["argv"]]
        try:
            runpy.run_module(MODULE, run_name="__main__", alter_sys=True)
            code = 0
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
            if exc.code is not None and not isinstance(exc.code, int):
                print(exc.code, file=sys.stderr)
    except KeyboardInterrupt:  # uncaught: a cold interpreter ends as killed by the signal
        traceback.print_exc()
        code = -signal.SIGINT
    except BaseException:  # noqa: BLE001 - as an uncaught exception ends a cold process
        traceback.print_exc()
    finally:
        try:  # what a cold interpreter does at its end: wait for its threads, then run atexit
            threading._shutdown()  # type: ignore[attr-defined]
            import atexit
            atexit._run_exitfuncs()
        except BaseException:  # noqa: BLE001
            traceback.print_exc()
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except Exception:  # noqa: BLE001
                pass
        if code == -signal.SIGINT:
            signal.signal(signal.SIGINT, signal.SIG_DFL)
            os.kill(os.getpid(), signal.SIGINT)
        os._exit(code)


if __name__ == "__main__":
    serve(int(sys.argv[1]))
