"""PELEA, the deliberative agent (paper, Section III-B), in its five parts:

- ``hle``: the High Level Executive, the loop every test shares: plans, executes, reacts;
  ``questionnaire_executive`` and ``gug_executive`` are the tests run on it;
- ``monitoring``: keeps the high-level state and turns deviations into facts for replanning;
- ``decision_support``: plans with a real automated planner on the PDDL domain of the test;
- ``high_to_low``: a high-level action as changes to the DSR;
- ``low_to_high``: the DSR's binary predicates as n-ary facts for Monitoring;
- ``result_delivery`` (beside them): a finished test's result on its way to CGAmed.

The core knows no test: here are the parts every test shares (sentences, the person coming and
going; the test node is ``clarc_agents/test_node.py``). Each test kind has one home for its DSR
layout, its HighToLow, LowToHigh, Monitoring and planning problem: ``clarc_agents/questionnaire/``
(``high_to_low``, ``low_to_high``, ``monitoring``, ``planning``, ``item_options``) and
``clarc_agents/gug/`` (``high_to_low``, ``planning``, ``record``); its executive gives the core
its flags (``PROGRESS_FLAGS``, ``NEEDS``, ``CLOSING``) and its times (``QuestionnaireTimes``).

All pure; its ROS node is ``clarc_agents.nodes.pelea_node``.
"""
