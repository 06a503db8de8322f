"""PELEA, the deliberative agent (paper, Section III-B), in its five parts:

- ``hle``: the High Level Executive, the loop every test shares: plans, executes, reacts;
  ``questionnaire_executive`` and ``gug_executive`` are the tests run on it;
- ``monitoring``: keeps the high-level state and turns deviations into facts for replanning;
- ``decision_support``: plans with a real automated planner on the PDDL domain of the test;
- ``high_to_low``: a high-level action as changes to the DSR;
- ``low_to_high``: the DSR's binary predicates as n-ary facts for Monitoring;
- ``result_delivery`` (beside them): a finished test's result on its way to CGAmed.

All pure; its ROS node is ``clarc_agents.nodes.pelea_node``.
"""
