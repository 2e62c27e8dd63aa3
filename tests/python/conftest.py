"""A real skilld (sim backend, shipped library) on loopback for each test, on a partition of its own.

CTest sets PYTHONPATH to build/python and FLSD_BIN_DIR to build/bin; FLSD_SOURCE_DIR is the source tree.
"""
import os
import pathlib
import subprocess
import sys

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("FLSD_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BIN_DIR = pathlib.Path(os.environ.get("FLSD_BIN_DIR", SOURCE_DIR / "build" / "bin"))
os.environ.setdefault("CYCLONEDDS_URI", f"file://{SOURCE_DIR}/configs/cyclonedds_loopback.xml")
# The examples run in a folder of their own: a relative PYTHONPATH (build/python) must still find flsd.
os.environ["PYTHONPATH"] = os.pathsep.join(os.path.abspath(p) for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p)


class Server:
    """Where a test's skilld listens, and the log it writes."""

    def __init__(self, domain, partition, log):
        self.domain, self.partition, self.log = domain, partition, log

    def args(self):
        """skillctl's or an example's --domain and --partition for this server."""
        return ["--domain", str(self.domain), "--partition", self.partition]


def start_skilld(request, tmp_path, config):
    """skilld with `config`, until the test ends; it must exit cleanly."""
    domain = 100 + os.getpid() % 130
    partition = f"pytest-{os.getpid()}-{request.node.name}"
    log = tmp_path / "skilld.log"
    with open(log, "w") as out:
        process = subprocess.Popen(
            [str(BIN_DIR / "skilld"), "--backend", "sim", "--library", str(SOURCE_DIR / "models/a1_flsd.safetensors"),
             "--config", str(config), "--domain", str(domain), "--partition", partition],
            stdout=out, stderr=subprocess.STDOUT)
    try:
        yield Server(domain, partition, log)
    finally:
        process.terminate()
        code = process.wait(timeout=20)
        assert code == 0, f"skilld exited with {code}:\n{log.read_text()}"


@pytest.fixture
def server(request, tmp_path):
    yield from start_skilld(request, tmp_path, SOURCE_DIR / "configs/server.yaml")


@pytest.fixture
def pki(tmp_path):
    """A deployment's PKI from scripts/make_pki.sh: identities skilld, operator op and observer obs."""
    folder = tmp_path / "pki"
    subprocess.run(["bash", str(SOURCE_DIR / "scripts/make_pki.sh"), str(folder), "--operators", "op", "--observers", "obs"],
                   check=True, stdout=subprocess.DEVNULL)
    return folder


@pytest.fixture
def secured_server(request, tmp_path, pki):
    """skilld with DDS Security on, as pki's identity skilld."""
    yield from start_skilld(request, tmp_path, pki / "skilld" / "security.yaml")


@pytest.fixture
def python():
    """Debian's interpreter running the tests, for the examples."""
    return sys.executable
