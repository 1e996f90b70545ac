"""A real single-node Slurm cluster (Debian's slurm-wlm and munge): submit a sampling job array
and its merge, wait, and compare the merged library with a single-machine run."""
import os
import shutil
import socket
import subprocess
import time

import pytest

from conftest import QUICKSTART_BLEND

pytestmark = pytest.mark.skipif(
    os.geteuid() != 0 or not shutil.which("slurmctld") or not shutil.which("munged"),
    reason="needs root and Debian's slurm-wlm and munge packages (tests/setup.sh installs them)")


def slurm_conf(folder, host):
    ports = (16817, 16818)
    return f"""ClusterName=mwbtest
SlurmctldHost={host}
SlurmUser=root
SlurmctldPort={ports[0]}
SlurmdPort={ports[1]}
StateSaveLocation={folder}/state
SlurmdSpoolDir={folder}/spool
SlurmctldPidFile={folder}/slurmctld.pid
SlurmdPidFile={folder}/slurmd.pid
SlurmctldLogFile={folder}/slurmctld.log
SlurmdLogFile={folder}/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
ReturnToService=2
NodeName={host} CPUs={os.cpu_count()} State=UNKNOWN
PartitionName=main Nodes={host} Default=YES MaxTime=INFINITE State=UP
"""


@pytest.fixture
def cluster(tmp_path):
    host = socket.gethostname().split(".")[0]
    folder = tmp_path / "slurm"
    for sub in ("state", "spool"):
        (folder / sub).mkdir(parents=True)
    conf = folder / "slurm.conf"
    conf.write_text(slurm_conf(folder, host))
    env = dict(os.environ, SLURM_CONF=str(conf))
    started_munge = subprocess.run(["pgrep", "-x", "munged"], capture_output=True).returncode != 0
    if started_munge:
        os.makedirs("/run/munge", exist_ok=True)
        shutil.chown("/run/munge", "munge", "munge")
        subprocess.run(["runuser", "-u", "munge", "--", "munged"], check=True)
    subprocess.run(["slurmctld", "-f", str(conf)], check=True, env=env)
    subprocess.run(["slurmd", "-f", str(conf)], check=True, env=env)
    try:
        deadline = time.time() + 60
        while time.time() < deadline:
            state = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True, env=env).stdout
            if "idle" in state:
                break
            time.sleep(0.5)
        else:
            pytest.fail("the Slurm node never became idle: " + (folder / "slurmctld.log").read_text()[-2000:])
        yield env
    finally:
        for pid_file in ("slurmd.pid", "slurmctld.pid"):
            path = folder / pid_file
            if path.exists():
                subprocess.run(["kill", path.read_text().strip()])
        if started_munge:
            subprocess.run(["pkill", "-x", "munged"])


def job_state(job_id, env):
    out = subprocess.run(["scontrol", "show", "job", job_id], capture_output=True, text=True, env=env).stdout
    for field in out.split():
        if field.startswith("JobState="):
            return field.split("=", 1)[1]
    return "GONE"


def test_job_array_and_merge_reproduce_a_single_machine_run(cluster, tmp_path, single_machine_library, monkeypatch):
    from many_worlds.farm import slurm
    for key, value in cluster.items():
        monkeypatch.setenv(key, value)
    out = tmp_path / "run"
    array_id, merge_id = slurm.submit(QUICKSTART_BLEND, 0, 10, 4, str(out), threads=1)
    deadline = time.time() + 600
    while job_state(merge_id, cluster) not in ("COMPLETED", "FAILED", "CANCELLED", "TIMEOUT", "GONE"):
        assert time.time() < deadline, "the merge job did not finish in 10 minutes"
        time.sleep(1)
    logs = "\n".join(p.read_text()[-1500:] for p in (out / "logs").glob("*.log"))
    assert job_state(merge_id, cluster) in ("COMPLETED", "GONE"), logs
    assert sorted(p.name for p in out.glob("shard_*.mwb")) == [
        "shard_00000000_00000004.mwb", "shard_00000004_00000008.mwb", "shard_00000008_00000010.mwb"]
    assert (out / "merged.mwb").read_bytes() == single_machine_library, logs
