"""An agent's tick (ros/agent.py's ``_pace``): every ``TICK`` while its core waits on something,
every ``IDLE_TICK`` otherwise, and back to ``TICK`` at once when something comes to wait on."""

from __future__ import annotations

from dsr_graph.protocol.agent_core import IDLE_TICK, TICK, AgentCore
from dsr_graph.ros.agent import DsrAgent


class Timer:
    """rclpy's Timer as _pace uses it: its period, and whether it was restarted."""

    def __init__(self, seconds: float):
        self.timer_period_ns = int(seconds * 1e9)
        self.resets = 0

    def reset(self) -> None:
        self.resets += 1


def _agent(describes: bool) -> tuple[DsrAgent, Timer]:
    agent = DsrAgent(describe=describes)
    agent._tick_timer, agent._ticking_every = Timer(TICK), TICK
    return agent, agent._tick_timer


def test_an_idle_agent_ticks_slowly_and_a_busy_one_at_once(monkeypatch):
    busy = {"now": False}
    monkeypatch.setattr(AgentCore, "busy", property(lambda core: busy["now"]))
    agent, timer = _agent(describes=False)
    agent._pace()
    assert timer.timer_period_ns == int(IDLE_TICK * 1e9) and timer.resets == 0
    busy["now"] = True  # a request sent, a delta missing, a snapshot asked for
    agent._pace()
    assert timer.timer_period_ns == int(TICK * 1e9)
    assert timer.resets == 1  # the next tick TICK from now, not what was left of IDLE_TICK
    agent._pace()
    assert timer.resets == 1  # already ticking every TICK: the timer is left alone
    busy["now"] = False
    agent._pace()
    assert timer.timer_period_ns == int(IDLE_TICK * 1e9)


def test_an_agent_ticks_every_tick_until_it_first_looked_at_its_info_node(monkeypatch):
    monkeypatch.setattr(AgentCore, "busy", property(lambda core: False))
    agent, timer = _agent(describes=True)
    agent._pace()
    assert timer.timer_period_ns == int(TICK * 1e9)  # its readiness is written without delay
    agent._described = 12.5
    agent._pace()
    assert timer.timer_period_ns == int(IDLE_TICK * 1e9)


def test_an_agent_not_set_up_has_no_timer_to_pace():
    DsrAgent()._pace()  # nothing to change, and no error
