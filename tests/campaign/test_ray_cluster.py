"""`atd campaign run --ray ADDRESS` on a real two-node Ray cluster, started on this machine
with `ray start` as a user starts one on theirs: its records are the local pool's.

Each node is one CPU and its own `ray start`, with its own --temp-dir, in its own process
group; the teardown ends those two groups and nothing else. (`ray stop` is not scoped: it
ends every Ray process on the machine it may signal, another user's campaign included.)
"""

from __future__ import annotations

import os
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

import pytest

from atd.campaign.store import Store
from tests.campaign.conftest import RAY_WORKERS_AT_OUR_PRIORITY, outcomes
from tests.conftest import REPO

SPEC = REPO / "tests" / "data" / "campaign" / "small.toml"  # 4 trials of the Melfa in MuJoCo
RAY = Path(sys.executable).parent / "ray"  # this venv's: its workers import this checkout's atd
HOST = "127.0.0.1"  # the cluster stays on this machine's loopback


@dataclass(frozen=True)
class Cluster:
    address: str
    env: dict[str, str]  # what a driver needs to join: the cluster's token
    nodes: tuple[Path, ...]  # each node's --temp-dir

    def trials_run(self, node: Path) -> int:
        """How many trials the node's workers ran: a Ray worker writes a `:task_name:` line
        to its log for every task it starts."""
        return sum(log.read_text().count(":task_name:run_trial") for log in node.glob("session_latest/logs/worker-*.out"))


def _free_port() -> int:
    with socket.socket() as s:
        s.bind((HOST, 0))
        return s.getsockname()[1]


def _start_node(args: list[str], temp_dir: Path, env: dict[str, str], groups: list[int]) -> None:
    """`ray start` for one node, in a new process group (noted in `groups` at once, for the
    teardown); it returns when the node has joined."""
    temp_dir.mkdir()
    process = subprocess.Popen(
        [str(RAY), "start", *args, "--num-cpus=1", f"--node-ip-address={HOST}", f"--temp-dir={temp_dir}",
         f"--dashboard-agent-listen-port={_free_port()}", "--disable-usage-stats"],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
    groups.append(process.pid)
    out, _ = process.communicate(timeout=120)
    assert process.returncode == 0, out


def _alive(groups: list[int]) -> bool:
    """Whether a process of these groups is still running (a zombie waits for its parent only)."""
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            state, _, group = stat.read_text().rpartition(")")[2].split()[:3]
        except (OSError, ValueError):  # it has just ended
            continue
        if int(group) in groups and state != "Z":
            return True
    return False


def _stop(groups: list[int]) -> None:
    """SIGTERM to the nodes' processes, SIGKILL to those left after 5 s. Their workers, in
    groups of their own, end with their raylet."""
    for sig in (signal.SIGTERM, signal.SIGKILL):
        for group in groups:
            try:
                os.killpg(group, sig)
            except ProcessLookupError:
                pass
        deadline = time.monotonic() + 5
        while _alive(groups) and time.monotonic() < deadline:
            time.sleep(0.2)


@pytest.fixture(scope="module")
def cluster() -> Iterator[Cluster]:
    """A head and a second node, one CPU each, behind a token made for the test."""
    base = Path(tempfile.mkdtemp(prefix="ray", dir="/tmp"))  # Ray's socket paths must stay under 108 bytes
    token = base / "token"
    token.write_text(secrets.token_hex(32))
    env = {**os.environ, "RAY_AUTH_MODE": "token", "RAY_AUTH_TOKEN_PATH": str(token),
           "RAY_USAGE_STATS_ENABLED": "0", **RAY_WORKERS_AT_OUR_PRIORITY}
    port = _free_port()
    groups: list[int] = []
    try:
        _start_node(["--head", f"--port={port}", "--include-dashboard=false", f"--dashboard-port={_free_port()}"],
                    base / "head", env, groups)
        _start_node([f"--address={HOST}:{port}"], base / "second", env, groups)
        yield Cluster(f"{HOST}:{port}", env, (base / "head", base / "second"))
    finally:
        _stop(groups)
        shutil.rmtree(base, ignore_errors=True)


def _campaign(tmp_path: Path, store: str, *options: str, env: dict[str, str] | None = None
              ) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "atd", "campaign", "run", str(SPEC), "-q", "--store",
                           str(tmp_path / store), *options], cwd=tmp_path, capture_output=True, text=True,
                          timeout=300, env=env)


def _report(store: Path) -> str:
    result = subprocess.run([sys.executable, "-m", "atd", "campaign", "report", str(store), "--format", "json"],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    return result.stdout


def test_a_campaign_on_a_two_node_cluster_stores_the_local_pools_records(tmp_path: Path, cluster: Cluster) -> None:
    on_ray = _campaign(tmp_path, "ray.sqlite", "--ray", cluster.address, env=cluster.env)
    assert on_ray.returncode == 0, on_ray.stderr
    ran = [cluster.trials_run(node) for node in cluster.nodes]
    assert sum(ran) == 4 and min(ran) >= 1, f"trials run by the head and the second node: {ran}"
    local = _campaign(tmp_path, "local.sqlite", "-j", "2")
    assert local.returncode == 0, local.stderr
    with Store.open_read(tmp_path / "ray.sqlite") as ray, Store.open_read(tmp_path / "local.sqlite") as pool:
        assert outcomes(ray.records()) == outcomes(pool.records())
    assert _report(tmp_path / "ray.sqlite") == _report(tmp_path / "local.sqlite")


def test_a_driver_whose_token_cannot_be_read_is_told_so_before_any_store_is_written(
        tmp_path: Path, cluster: Cluster) -> None:
    result = _campaign(tmp_path, "ray.sqlite", "--ray", cluster.address,
                       env={**cluster.env, "RAY_AUTH_TOKEN_PATH": str(tmp_path / "no-token")})
    assert result.returncode == 2, result.stderr
    assert result.stderr.splitlines()[-1].startswith(f"error: --ray {cluster.address}: Ray could not join the cluster")
    assert "no-token" in result.stderr and "Traceback" not in result.stderr
    assert not (tmp_path / "ray.sqlite").exists()


def test_an_address_where_nothing_answers_is_refused_at_once(tmp_path: Path) -> None:
    """Ray itself would retry for minutes (seen: over 5, printing a warning every few seconds)."""
    address = f"{HOST}:{_free_port()}"  # closed again: nothing listens there
    started = time.monotonic()
    result = _campaign(tmp_path, "ray.sqlite", "--ray", address)
    assert result.returncode == 2 and time.monotonic() - started < 60
    assert result.stderr.strip() == (f"error: --ray {address}: nothing answers there (Connection refused); start the "
                                     f"cluster's head with `ray start --head --port=PORT` and give HOST:PORT as it "
                                     f"prints it")
    assert not (tmp_path / "ray.sqlite").exists()
