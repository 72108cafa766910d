"""regress, validate and analyze --peaks on a Dask cluster give what they give on this machine.

One cluster serves the module: ``local_cluster(2)``, two worker processes (processes=True:
every task and result is pickled and crosses a process boundary, as on a real cluster, and a worker
is a process that can be killed). The shipped cases are copied into a temporary folder first, so a
run reads nothing from the source tree.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time
from contextlib import contextmanager
from pathlib import Path

import pytest

import linkstress
from linkstress import executors
from linkstress.cli import main
from linkstress.executors import CONNECT_SECONDS, DaskExecutor, local_cluster
from linkstress.validation.regression import packed_case, run_case, run_packed_case
from test_validate_blocks import without_timing

distributed = pytest.importorskip("distributed")

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"
QUICK = ("textbook_fourbar", "slider_crank_curved_rod", "banana_coupler")
"""Three shipped cases that regress in about 2.5 s together: bare joints, a DXF with a curved rod, arcs."""


@pytest.fixture(scope="module")
def client():
    with local_cluster(2) as cluster, distributed.Client(cluster) as client:
        yield client


@pytest.fixture(scope="module")
def cases(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("cases")
    for name in QUICK:
        shutil.copytree(CASES / name, folder / name)
    return folder


@pytest.fixture(scope="module")
def serial(cases, tmp_path_factory) -> tuple[str, dict]:
    """regress of the quick cases on this machine, one after another: (text, JSON)."""
    out = tmp_path_factory.mktemp("serial") / "regress.json"
    return run_cli(["regress", str(cases), "--json", str(out)], 0), json.loads(out.read_text())


def run_cli(argv: list[str], code: int) -> str:
    """``linkstress argv`` in this process; its stdout, after checking its exit code."""
    from contextlib import redirect_stdout
    from io import StringIO

    text = StringIO()
    with redirect_stdout(text):
        assert main(argv) == code
    return text.getvalue()


def test_regress_on_a_cluster_gives_the_serial_verdicts_numbers_and_report(client, cases, serial, tmp_path, monkeypatch):
    # the option wins over the variable, which would otherwise be refused as no address
    monkeypatch.setenv("LINKSTRESS_SCHEDULER", "not-an-address")
    out = tmp_path / "regress.json"
    text = run_cli(["regress", str(cases), "--scheduler", client.scheduler.address, "--json", str(out)], 0)
    remote = json.loads(out.read_text())
    assert text == serial[0]
    assert remote["cases"] == serial[1]["cases"]
    assert [c["case"] for c in remote["cases"]] == sorted(QUICK)
    assert (remote["scheduler"], remote["retried"]) == (client.scheduler.address, [])


def test_a_case_travels_by_content_with_a_sketch_outside_its_folder(client, tmp_path):
    # The case's sketch moves to a sibling folder; the copy is deleted before the task is sent, so
    # the worker can only have what the task carries.
    copy = tmp_path / "copy"
    shutil.copytree(CASES / "slider_crank_curved_rod", copy / "slider_crank_curved_rod")
    (copy / "sketches").mkdir()
    shutil.move(copy / "slider_crank_curved_rod" / "curved_rod.dxf", copy / "sketches" / "curved_rod.dxf")
    scene = copy / "slider_crank_curved_rod" / "scene.toml"
    scene.write_text(scene.read_text().replace('"curved_rod.dxf"', '"../sketches/curved_rod.dxf"'))
    packed = packed_case(copy / "slider_crank_curved_rod")
    shutil.rmtree(copy)
    assert sorted(packed.files) == [
        "copy/sketches/curved_rod.dxf", "copy/slider_crank_curved_rod/reference.json", "copy/slider_crank_curved_rod/scene.toml",
    ]
    [(result, reference)] = DaskExecutor(client, client.scheduler.address).map(run_packed_case, [packed], ["the case"])
    assert reference is None
    assert (result.name, result.error, result.checks) == ("slider_crank_curved_rod", "", run_case(CASES / "slider_crank_curved_rod").checks)


def test_update_on_a_cluster_writes_the_reference_beside_the_scene_here(client, tmp_path):
    # Two copies of a case whose stored reference lacks its validation: updated here and on the
    # cluster, both get the same new reference, written in their own folder on this machine.
    for where in ("here", "there"):
        shutil.copytree(CASES / "slider_crank_curved_rod", tmp_path / where / "slider_crank_curved_rod")
        reference = tmp_path / where / "slider_crank_curved_rod" / "reference.json"
        stored = json.loads(reference.read_text())
        del stored["validation"]
        reference.write_text(json.dumps(stored))
    run_cli(["regress", str(tmp_path / "here"), "--update"], 0)
    text = run_cli(["regress", str(tmp_path / "there"), "--update", "--scheduler", client.scheduler.address], 0)
    assert text == "slider_crank_curved_rod: reference rewritten\n"
    here, there = ((tmp_path / w / "slider_crank_curved_rod" / "reference.json").read_bytes() for w in ("here", "there"))
    assert there == here
    assert "validation" in json.loads(there)


def test_validate_on_a_cluster_writes_the_serial_json_and_text(client, tmp_path):
    # banana_coupler: three profiled links (three tasks), three positions on one mesh each
    scene = CASES / "banana_coupler" / "scene.toml"
    flags = ["--positions", "3", "--mesh-levels", "1"]
    text = run_cli(["validate", str(scene), *flags, "--json", str(tmp_path / "serial.json")], 0)
    remote_text = run_cli(["validate", str(scene), *flags, "--json", str(tmp_path / "remote.json"), "--scheduler", client.scheduler.address], 0)
    serial, remote = (json.loads((tmp_path / f"{n}.json").read_text()) for n in ("serial", "remote"))
    assert (remote.pop("scheduler"), remote.pop("retried")) == (client.scheduler.address, [])
    assert without_timing(remote) == without_timing(serial)
    assert list(remote["links"]) == ["crank", "coupler", "output"]
    assert remote_text == text


def test_validate_in_blocks_of_positions_on_a_cluster_writes_the_serial_json_and_text(client, tmp_path):
    # banana_coupler's three links at 12 positions, each in blocks of 8 and 4: six tasks, joined
    scene = CASES / "banana_coupler" / "scene.toml"
    flags = ["--positions", "12", "--mesh-levels", "1"]
    text = run_cli(["validate", str(scene), *flags, "--json", str(tmp_path / "serial.json")], 0)
    remote_text = run_cli([
        "validate", str(scene), *flags, "--json", str(tmp_path / "remote.json"), "--positions-per-task", "8",
        "--scheduler", client.scheduler.address,
    ], 0)
    serial, remote = (json.loads((tmp_path / f"{n}.json").read_text()) for n in ("serial", "remote"))
    assert (remote.pop("scheduler"), remote.pop("retried")) == (client.scheduler.address, [])
    assert without_timing(remote) == without_timing(serial)
    assert len(remote["positions_compared"]) == 12
    assert remote_text == text


def test_a_cluster_reports_its_workers_threads_to_size_the_blocks(client):
    assert DaskExecutor(client, client.scheduler.address).workers == 2


def test_analyze_peaks_on_a_cluster_writes_the_serial_json(client, tmp_path):
    # the seed four-bar at its one position: three stressed links, a task each
    scene = CASES / "seed_ansys_fourbar" / "scene.toml"
    run_cli(["analyze", str(scene), "--peaks", "--json", str(tmp_path / "serial.json")], 0)
    run_cli(["analyze", str(scene), "--peaks", "--json", str(tmp_path / "remote.json"), "--scheduler", client.scheduler.address], 0)
    serial, remote = (json.loads((tmp_path / f"{n}.json").read_text()) for n in ("serial", "remote"))
    assert (remote.pop("scheduler"), remote.pop("retried")) == (client.scheduler.address, [])
    assert without_timing(remote) == without_timing(serial)
    assert len(remote["links"]) == 3


def test_the_workers_fill_and_read_the_cache_the_task_carries(client, tmp_path):
    # With a scheduler the peaks are computed only on the workers: the entries are theirs.
    scene = CASES / "seed_ansys_fourbar" / "scene.toml"
    cache = tmp_path / "cache"
    for run in ("cold", "warm"):
        run_cli(["analyze", str(scene), "--peaks", "--cache", str(cache), "--scheduler", client.scheduler.address,
                 "--json", str(tmp_path / f"{run}.json")], 0)
        assert len(list((cache / "unit-loads").glob("*.npz"))) == 3  # a link each, read back on the warm run
    cold, warm = (json.loads((tmp_path / f"{n}.json").read_text()) for n in ("cold", "warm"))
    assert without_timing(warm) == without_timing(cold)
    solves = [(cold["links"][n]["peak_seconds"]["unit_solves"], warm["links"][n]["peak_seconds"]["unit_solves"])
              for n in ("crank", "coupler", "output")]
    assert all(first > 0 and second == 0 for first, second in solves), solves


def test_a_case_whose_worker_is_killed_runs_again_elsewhere_and_the_report_says_so(client, cases, serial, tmp_path):
    killed = []

    def kill_the_worker_running_a_case():
        # banana_coupler takes over a second: time to see it on its worker and kill that process
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and not killed:
            for worker, keys in client.processing().items():
                if any(str(k).startswith("linkstress-") for k in keys):
                    pid = client.run(os.getpid, workers=[worker])[worker]
                    os.kill(pid, signal.SIGKILL)
                    killed.append(worker)
                    return
            time.sleep(0.01)

    killer = threading.Thread(target=kill_the_worker_running_a_case)
    killer.start()
    out = tmp_path / "regress.json"
    text = run_cli(["regress", str(cases / "banana_coupler"), "--scheduler", client.scheduler.address, "--json", str(out)], 0)
    killer.join()
    remote = json.loads(out.read_text())
    assert len(killed) == 1
    assert remote["retried"] == [{"task": "banana_coupler", "reason": f"worker {killed[0]} lost"}]
    assert text.endswith(f"retried: banana_coupler (worker {killed[0]} lost)\n")
    assert remote["cases"] == [c for c in serial[1]["cases"] if c["case"] == "banana_coupler"]
    client.wait_for_workers(2, timeout=60)  # the nanny restarts the killed worker


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_regress_against_a_scheduler_and_worker_started_as_a_user_would(cases, serial, tmp_path):
    # `dask scheduler` and `dask worker` as separate processes whose folder is elsewhere, and the
    # CLI as a subprocess: nothing shared but the network
    dask = shutil.which("dask", path=str(Path(sys.executable).parent)) or pytest.skip("no dask command beside python")
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    # the environment docs/cluster.md gives workers: glibc's own malloc thresholds
    environment = {**os.environ, "DASK_DISTRIBUTED__NANNY__PRE_SPAWN_ENVIRON": '{"MALLOC_TRIM_THRESHOLD_": None}'}
    with running(
        [dask, "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
        [dask, "worker", address, "--nworkers", "1", "--nthreads", "1", "--no-dashboard"],
        cwd=elsewhere, env=environment,
    ):
        with distributed.Client(address, timeout=30) as watcher:
            watcher.wait_for_workers(1, timeout=60)
        done = subprocess.run(
            [sys.executable, "-m", "linkstress", "regress", str(cases), "--scheduler", address],
            capture_output=True, text=True, cwd=tmp_path, timeout=300,
        )
    assert (done.returncode, done.stderr) == (0, "")
    assert done.stdout == serial[0]


@contextmanager
def running(*commands: list[str], **options):
    """Each of ``commands`` as a process (its output discarded; ``options`` for subprocess.Popen),
    terminated on leaving, the last started first."""
    processes = [subprocess.Popen(c, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, **options) for c in commands]
    try:
        yield processes
    finally:
        for process in reversed(processes):
            process.terminate()
            process.wait(timeout=30)


@contextmanager
def scheduler_with_workers(*preludes: str):
    """A `dask scheduler` on a free port and one worker process per Python ``prelude`` run before the
    worker starts (no nanny: the worker is that process); yields the scheduler's address."""
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    start = "import sys; sys.argv[0] = 'dask-worker'; from distributed.cli.dask_worker import main; main()"
    with running(
        [sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
        *([sys.executable, "-c", f"{prelude}; {start}", address, "--no-nanny", "--nthreads", "1", "--no-dashboard"]
          for prelude in preludes),
    ):
        with distributed.Client(address, timeout=30) as watcher:
            if preludes:
                watcher.wait_for_workers(len(preludes), timeout=60)
        yield address


def test_a_worker_that_cannot_import_linkstress_is_refused_before_any_task(capsys):
    # a task it cannot unpickle would kill it; with no nanny to restart it, the run would wait forever
    with scheduler_with_workers("import sys; sys.modules['linkstress'] = None", "pass") as address:
        started = time.perf_counter()
        assert main(["regress", str(CASES / "textbook_fourbar"), "--scheduler", address]) == 2
        assert time.perf_counter() - started < 20
    err = capsys.readouterr().err
    assert "--scheduler: worker tcp://127.0.0.1:" in err and f"of {address} cannot import linkstress" in err
    assert 'pip install "linkstress[cluster]"' in err and "Traceback" not in err


def test_a_worker_with_another_version_of_linkstress_is_refused_naming_both(capsys):
    with scheduler_with_workers("import linkstress; linkstress.__version__ = '0.0.1'") as address:
        assert main(["regress", str(CASES / "textbook_fourbar"), "--scheduler", address]) == 2
    err = capsys.readouterr().err
    assert f"runs linkstress 0.0.1, this machine {linkstress.__version__}" in err


def test_a_scheduler_without_workers_is_refused_instead_of_waiting(capsys, monkeypatch):
    monkeypatch.setattr(executors, "WORKER_SECONDS", 1)
    with scheduler_with_workers() as address:
        assert main(["validate", str(CASES / "banana_coupler" / "scene.toml"), "--scheduler", address]) == 2
    assert f"the scheduler at {address} has no worker after 1 s: start some with `dask worker {address}`" in capsys.readouterr().err


def tls_settings(folder: Path) -> dict[str, str]:
    """A self-signed certificate for 127.0.0.1 (openssl) and Dask's TLS settings that use it for
    the scheduler, the worker and the client, as environment variables."""
    openssl = shutil.which("openssl") or pytest.skip("no openssl to make a certificate")
    cert, key = folder / "cert.pem", folder / "key.pem"
    subprocess.run(
        [openssl, "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-keyout", str(key), "-out", str(cert), "-days", "1",
         "-subj", "/CN=localhost", "-addext", "subjectAltName=IP:127.0.0.1"],
        check=True, capture_output=True,
    )
    settings = {"DASK_DISTRIBUTED__COMM__TLS__CA_FILE": str(cert), "DASK_DISTRIBUTED__COMM__REQUIRE_ENCRYPTION": "True"}
    for role in ("SCHEDULER", "WORKER", "CLIENT"):
        settings |= {f"DASK_DISTRIBUTED__COMM__TLS__{role}__CERT": str(cert), f"DASK_DISTRIBUTED__COMM__TLS__{role}__KEY": str(key)}
    return settings


def test_regress_on_a_tls_scheduler_with_dasks_tls_settings_and_a_clear_refusal_without(cases, serial, tmp_path):
    dask = shutil.which("dask", path=str(Path(sys.executable).parent)) or pytest.skip("no dask command beside python")
    environment = {**os.environ, **tls_settings(tmp_path)}
    port = free_port()
    address = f"tls://127.0.0.1:{port}"
    command = [sys.executable, "-m", "linkstress", "regress", str(cases), "--scheduler", address]
    with running(
        [dask, "scheduler", "--host", "127.0.0.1", "--port", str(port), "--protocol", "tls", "--no-dashboard"],
        [dask, "worker", address, "--nworkers", "1", "--nthreads", "1", "--no-dashboard"],
        cwd=tmp_path, env=environment,
    ):
        done = subprocess.run(command, capture_output=True, text=True, cwd=tmp_path, timeout=300, env=environment)
        plain = {k: v for k, v in os.environ.items() if not k.startswith("DASK_DISTRIBUTED__COMM__TLS")}
        refused = subprocess.run(command, capture_output=True, text=True, cwd=tmp_path, timeout=60, env=plain)
    assert (done.returncode, done.stderr) == (0, "")
    assert done.stdout == serial[0]
    assert refused.returncode == 2 and "Traceback" not in refused.stderr
    assert "--scheduler: a tls:// scheduler needs Dask's TLS settings here: distributed.comm.tls.ca-file" in refused.stderr


def test_a_malformed_address_is_refused_naming_the_option(capsys):
    assert main(["regress", str(CASES / "textbook_fourbar"), "--scheduler", "10.0.0.5:8786"]) == 2
    err = capsys.readouterr().err
    assert "--scheduler: '10.0.0.5:8786' is not a scheduler address: give tcp://HOST:PORT" in err
    assert "Traceback" not in err


def test_an_address_from_the_variable_is_refused_naming_the_variable(capsys, monkeypatch):
    monkeypatch.setenv("LINKSTRESS_SCHEDULER", "my-cluster")
    assert main(["regress", str(CASES / "textbook_fourbar")]) == 2
    assert "LINKSTRESS_SCHEDULER: 'my-cluster' is not a scheduler address" in capsys.readouterr().err


def test_an_unreachable_scheduler_is_refused_within_seconds(capsys):
    address = f"tcp://127.0.0.1:{free_port()}"  # nothing listens there
    start = time.monotonic()
    assert main(["regress", str(CASES / "textbook_fourbar"), "--scheduler", address]) == 2
    assert time.monotonic() - start < CONNECT_SECONDS + 10
    err = capsys.readouterr().err
    assert f"--scheduler: no Dask scheduler answered at {address} within {CONNECT_SECONDS} s" in err
    assert "Traceback" not in err


def test_without_dask_installed_the_message_says_what_to_install(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed raises ImportError
    assert main(["validate", str(CASES / "banana_coupler" / "scene.toml"), "--scheduler", "local"]) == 2
    assert 'running on a Dask cluster needs dask and distributed: pip install "linkstress[cluster]"' in capsys.readouterr().err


def test_analyze_refuses_a_scheduler_with_no_peaks_to_send_and_ignores_the_variable(capsys, monkeypatch):
    scene = str(CASES / "textbook_fourbar" / "scene.toml")
    assert main(["analyze", scene, "--scheduler", "tcp://127.0.0.1:8786"]) == 2
    assert "--scheduler: only the FEA peaks run on a cluster and this run computes none: add --peaks" in capsys.readouterr().err
    monkeypatch.setenv("LINKSTRESS_SCHEDULER", "tcp://127.0.0.1:8786")
    assert main(["analyze", scene]) == 0


def test_jobs_are_refused_beside_a_scheduler(capsys):
    assert main(["regress", str(CASES / "textbook_fourbar"), "--jobs", "2", "--scheduler", "local"]) == 2
    assert "--jobs: not with --scheduler" in capsys.readouterr().err


def test_a_plain_analyze_imports_no_dask():
    program = (
        "import sys; from linkstress.cli import main; main(['analyze', sys.argv[1]]); "
        "print(sorted({m.split('.')[0] for m in sys.modules} & {'dask', 'distributed'}))"
    )
    done = subprocess.run([sys.executable, "-c", program, str(CASES / "seed_ansys_fourbar" / "scene.toml")],
                          capture_output=True, text=True, check=True)
    assert done.stdout.strip().splitlines()[-1] == "[]"


def _threads_on_worker() -> tuple[str | None, int]:
    import os

    from linkstress.threads import cores

    return os.environ.get("LINKSTRESS_THREADS"), cores()


def test_the_workers_linkstress_starts_run_one_thread_each_and_this_process_keeps_its_own(monkeypatch):
    # a worker per core, each with a thread per core, would put cores^2 threads on the cores; the
    # workers get one even where this process asks for more, and a restarted worker leaves this
    # process's environment alone
    monkeypatch.setenv("LINKSTRESS_THREADS", "3")
    with local_cluster(1) as cluster, distributed.Client(cluster) as client:
        assert set(client.run(_threads_on_worker).values()) == {("1", 1)}
        assert os.environ.get("LINKSTRESS_THREADS") == "3"
        client.restart()
        assert set(client.run(_threads_on_worker).values()) == {("1", 1)}
        assert os.environ.get("LINKSTRESS_THREADS") == "3"
    assert os.environ.get("LINKSTRESS_THREADS") == "3"
