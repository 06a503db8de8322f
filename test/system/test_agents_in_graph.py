"""Agents announce themselves in the DSR (issue "Ready before it asks"): ``dsr agents --json``
lists each running agent with its state; Panel is ``starting`` until the touch screen it listens
to is there, then ``ready``; killed, it is ``gone`` within 5 s, and ready again once restarted."""

import json
import time

from ros_processes import wait_for


def agents(ros) -> dict[str, dict]:
    r = ros.procs.run("dsr", "agents", "--json", "--timeout", "10")
    assert r.returncode == 0, r.stderr
    return {a["name"]: a for a in json.loads(r.stdout)}


def state_of(ros, name: str) -> str:
    return agents(ros).get(name, {}).get("state", "")


def test_an_agent_is_starting_then_ready_then_gone_when_killed_and_ready_again(ros):
    ros.procs.start_server(ros.tmp / "state")
    ros.procs.start("panel", ["panel"])
    wait_for(lambda: state_of(ros, "/panel") == "starting", 60, "panel starting")
    time.sleep(2.0)  # no touch screen: it stays starting
    panel = agents(ros)["/panel"]
    assert panel["state"] == "starting" and panel["listens_to"] == ["/clarc/panel/tap"]
    assert "show" in panel["can_do"] and panel["pid"] > 0

    ros.procs.start("touchscreen", ["touchscreen"])
    wait_for(lambda: state_of(ros, "/panel") == "ready", 60, "panel ready")

    ros.procs.kill9("panel")
    killed = time.monotonic()
    wait_for(lambda: state_of(ros, "/panel") == "gone", 30, "panel gone")
    took = time.monotonic() - killed
    assert took < 5 + 2, took  # the promise is 5 s; `dsr agents` itself takes up to ~1 s

    ros.procs.start("panel", ["panel"])
    wait_for(lambda: state_of(ros, "/panel") == "ready", 60, "panel ready again")
    r = ros.procs.run("dsr", "agents")
    assert r.returncode == 0 and "/panel" in r.stdout and "ready" in r.stdout, r.stdout
