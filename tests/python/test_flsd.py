"""The flsd Python module against the real skilld: the same answers as the library and the C++
client, tasks waited on to their result, refusals raised with their reply, control taken and
released by `with`, Ctrl-C stopping the robot, and the examples run as a user runs them."""
import json
import os
import re
import signal
import subprocess
import threading
import time

import pytest

import flsd
from conftest import SOURCE_DIR, BIN_DIR

EXAMPLES = SOURCE_DIR / "examples"


def connect(server, **kwargs):
    return flsd.Client(domain=server.domain, partition=server.partition, wait=15.0, **kwargs)


def wait_for(client, predicate, timeout=10.0):
    """The first state sample that satisfies `predicate`, or None."""
    deadline = time.monotonic() + timeout
    tick = 0
    while time.monotonic() < deadline:
        s = client.next_state(tick, timeout=1.0)
        if s is not None:
            if predicate(s):
                return s
            tick = s.tick
    return None


def standing(s):
    return s.mode == flsd.Mode.STAND and s.position[2] > 0.22


def test_without_a_server_the_client_raises_timeout_error():
    with pytest.raises(TimeoutError, match="no skilld answers on DDS domain 231, partition 'nobody'"):
        flsd.Client(domain=231, partition="nobody", wait=0.3)
    with pytest.raises(ValueError, match="wait must be a finite number of seconds"):
        flsd.Client(domain=231, partition="nobody", wait=float("nan"))
    with pytest.raises(ValueError, match=r"domain must be in \[0, 232\] \(DDS\), got 233"):
        flsd.Client(domain=233)


def test_a_security_file_that_does_not_load_is_a_value_error_naming_it(tmp_path):
    missing = tmp_path / "missing.yaml"
    with pytest.raises(ValueError, match=f"security: .*{missing}"):
        flsd.Client(domain=231, partition="nobody", wait=0.3, security=str(missing))


def test_an_operators_identity_commands_a_secured_skilld_and_none_is_not_answered(secured_server, pki, python):
    # Each in a process of its own: Cyclone keeps one security configuration per process.
    script = ("import sys, flsd\n"
              "try:\n"
              "    c = flsd.Client(domain=int(sys.argv[1]), partition=sys.argv[2], security=sys.argv[3], wait=float(sys.argv[4]))\n"
              "    print(c.id)\n"
              "    c.acquire_control()\n"
              "    print(c.stand())\n"
              "except TimeoutError as e:\n"
              "    print('timeout:', e)\n")
    run = lambda security, wait: subprocess.run(
        [python, "-c", script, str(secured_server.domain), secured_server.partition, security, str(wait)],
        capture_output=True, text=True, timeout=120)
    operator = run(str(pki / "op" / "security.yaml"), 30)
    lines = operator.stdout.splitlines()
    assert operator.returncode == 0 and len(lines) == 2, operator.stdout + operator.stderr
    # The client's id is its authenticated identity: the subject's fingerprint, then its own part.
    assert re.fullmatch(r"[0-9a-f]{12}-[0-9a-f]{12}", lines[0]), lines
    assert lines[1].startswith("ok: "), lines
    assert f"identity {lines[0]}" in secured_server.log.read_text()
    # Without credentials, a secured skilld never answers.
    stranger = run("", 3)
    assert stranger.stdout.startswith("timeout: no skilld answers"), stranger.stdout + stranger.stderr


def test_skills_match_what_skillctl_lists(server):
    client = connect(server)
    skills = client.list_skills()
    assert len(skills) == 15
    assert [s.id for s in skills] == list(range(15))
    out = subprocess.run([str(BIN_DIR / "skillctl"), *server.args(), "--timeout", "10", "list"],
                         capture_output=True, text=True, check=True).stdout.splitlines()[1:]
    for s, line in zip(skills, out):
        k, vx, vy, wz, height, gait, survival = line.split()
        assert int(k) == s.id
        assert float(vx) == pytest.approx(s.linear_velocity[0], abs=0.005)
        assert float(vy) == pytest.approx(s.linear_velocity[1], abs=0.005)
        assert float(wz) == pytest.approx(s.angular_velocity[2], abs=0.005)
        assert float(height) == pytest.approx(s.base_height, abs=0.0005)
        assert float(gait) == pytest.approx(s.gait_frequency, abs=0.005)
        assert int(survival) == s.survival_steps
    assert set(skills[0].as_dict()) == {"id", "linear_velocity", "angular_velocity", "base_height", "gait_frequency",
                                        "survival_steps"}
    assert repr(skills[3]).startswith("SkillInfo(id=3, linear_velocity=")


def test_state_is_typed_and_arrives_at_the_control_rate(server):
    client = connect(server)
    first = wait_for(client, lambda s: True)
    assert first is not None
    time.sleep(1.0)
    later = client.state()
    assert 44 <= later.tick - first.tick <= 56
    assert later.time - first.time == pytest.approx((later.tick - first.tick) * 0.02, abs=1e-9)
    assert later.backend == "sim"
    assert len(later.joint_position) == 12 and len(later.orientation) == 4 and len(later.foot_contact) == 4
    assert str(later.mode) in ("idle", "stand")
    assert later.controller == ""
    assert "joint_torque" in later.as_dict()
    try:
        import numpy
    except ImportError:
        assert isinstance(later.position, tuple) and isinstance(later.task.path, tuple)
    else:
        assert later.joint_position.shape == (12,) and later.foot_contact.dtype == bool
        assert later.task.path.shape[1:] == (2,)


def test_a_skill_runs_to_its_result_under_with(server):
    client = connect(server)
    with client as robot:
        robot.stand()
        assert wait_for(robot, standing) is not None, "the robot did not stand"
        task = robot.execute_skill(0, 1.5)
        assert "skill 0 for 1.50 s accepted" in task.reply.message
        assert task.reply.status == flsd.ReplyStatus.OK
        assert task.wait(timeout=15.0)
        result = task.progress()
        assert result.state == flsd.TaskState.SUCCEEDED, result.message
        assert task.succeeded and task.done()
        assert result.call == "execute_skill"
        assert result.client_id == robot.id
        assert result.elapsed >= 1.48
        assert robot.state().controller == robot.id
    # Leaving the block released control.
    assert wait_for(client, lambda s: s.controller == "", timeout=5.0) is not None


def test_refusals_raise_call_error_with_the_reply(server):
    client = connect(server)
    with pytest.raises(flsd.CallError, match="not in control") as refused:
        client.execute_skill(0, 1.0)
    assert refused.value.reply.status == flsd.ReplyStatus.NOT_IN_CONTROL
    with client:
        with pytest.raises(flsd.CallError, match=r"skill 99 is not in \[0, 15\)") as bad:
            client.execute_skill(99, 1.0)
        assert bad.value.reply.status == flsd.ReplyStatus.INVALID_ARGUMENT
        assert str(bad.value.reply.status) == "invalid argument"
        with pytest.raises(flsd.CallError, match="duration must be in"):
            client.track_velocity(0.3, 0.0, 0.0, -1.0)
        with pytest.raises(ValueError, match="timeout must be a finite number"):
            client.next_state(0, timeout=-1.0)
        walled_in = client.navigate(1.0, 0.0, "bounds: [-5, 5, -5, 5]\nrobot_radius: 0.35\n"
                                              "circles: [{center: [1.0, 0.0], radius: 0.5}]\n")
        assert walled_in.wait(15.0)
        assert walled_in.progress().state == flsd.TaskState.NO_PATH
        assert "goal" in walled_in.progress().message
        other = connect(server)
        with pytest.raises(flsd.CallError, match="control is held by " + client.id):
            other.acquire_control()


def test_an_exception_in_the_with_block_stops_the_robot(server):
    client = connect(server)
    task = None
    with pytest.raises(RuntimeError, match="the script failed"):
        with client:
            client.stand()
            assert wait_for(client, standing) is not None
            task = client.track_velocity(0.3, 0.0, 0.0, 30.0)
            assert wait_for(client, lambda s: s.mode == flsd.Mode.VELOCITY) is not None
            raise RuntimeError("the script failed")
    assert task.wait(5.0)
    assert task.progress().state == flsd.TaskState.CANCELLED
    assert task.progress().message == "stopped by " + client.id


def test_control_released_and_taken_again_at_once_keeps_the_next_task(server):
    client = connect(server)
    with client:
        client.stand()
        assert wait_for(client, standing) is not None
    with client:
        task = client.track_velocity(0.3, 0.0, 0.0, 2.0)
        assert task.wait(15.0)
        assert task.progress().state == flsd.TaskState.SUCCEEDED, task.progress().message


def test_ctrl_c_during_wait_stops_the_robot(server):
    client = connect(server)
    with client:
        client.stand()
        assert wait_for(client, standing) is not None
        task = client.track_velocity(0.3, 0.0, 0.0, 30.0)
        assert wait_for(client, lambda s: s.mode == flsd.Mode.VELOCITY) is not None
        threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT)).start()
        started = time.monotonic()
        with pytest.raises(KeyboardInterrupt):
            task.wait()
        assert time.monotonic() - started < 5.0
        assert task.wait(5.0)
        assert task.progress().state == flsd.TaskState.CANCELLED
        assert "stopped by " + client.id in task.progress().message


def test_python_and_cxx_status_round_trips_are_alike(server):
    """The binding's cost: status() round trips from Python against skillctl bench's C++ ones, both
    at 200 calls/s (the server drops a client's calls beyond 1000/s)."""
    client = connect(server)
    for _ in range(50):  # warm-up: the server may still be in its first seconds
        client.status()
    times = []
    for _ in range(200):
        start = time.perf_counter()
        client.status()
        times.append(time.perf_counter() - start)
        time.sleep(max(0.0, 0.005 - times[-1]))
    times.sort()
    python_p50_us = times[len(times) // 2] * 1e6
    bench = subprocess.run([str(BIN_DIR / "skillctl"), *server.args(), "--timeout", "10", "bench", "--rate", "200",
                            "--blocks", "1", "--block-seconds", "1"], capture_output=True, text=True, check=True)
    cxx_p50_us = json.loads(bench.stdout)["rtt_p50_us"]
    print(f"status() round trip p50: python {python_p50_us:.0f} us, C++ {cxx_p50_us:.0f} us")
    assert python_p50_us < 3 * cxx_p50_us + 1000


@pytest.mark.parametrize("script, args, expect", [
    ("list_and_run_skills.py", ["--skills", "0", "--seconds", "1"], "execute_skill 0: succeeded"),
    ("walk_square.py", ["--side-seconds", "1"], "square done"),
])
def test_examples_run_as_written(server, python, tmp_path, script, args, expect):
    run = subprocess.run([python, str(EXAMPLES / script), *server.args(), *args], capture_output=True, text=True,
                         timeout=180, cwd=tmp_path, env={**os.environ})
    assert run.returncode == 0, run.stdout + run.stderr
    assert expect in run.stdout


def test_navigation_example_writes_its_picture(server, python, tmp_path):
    picture = tmp_path / "path.svg"
    run = subprocess.run([python, str(EXAMPLES / "navigate_and_plot.py"), *server.args(), "--goal", "0.1", "0.05",
                          "--picture", str(picture)], capture_output=True, text=True, timeout=180, cwd=tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "navigate: succeeded" in run.stdout
    svg = picture.read_text()
    assert svg.startswith("<svg") and "<polyline" in svg
