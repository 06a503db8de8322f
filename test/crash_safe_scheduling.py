"""pytest-xdist's ``--dist loadfile`` scheduling, made safe for a worker that dies.

A worker dies when the conftest watchdog ends it (a test stuck inside C, where no Python signal
reaches it). pytest-xdist 3.8.0 then hangs the whole run until CI's limit, for three reasons
(its issues 1323, 1327, 1378; fixes merged or proposed upstream, none released):
- the dead worker's files, finished ones included, go back on the queue; a finished file is sent
  as an empty batch that never completes, and no worker is ever given work again;
- a worker runs an item only once it holds the next one or is told there is none; a replacement
  given a single one-test file waits for ever;
- the test the worker died in goes back too: it runs again and takes the replacement down.
Here the test it died in is reported failed once (by xdist) and not run again, only the dead
worker's unfinished tests go back on the queue, and a worker is never left holding one item
with nothing more coming. Work sent to a worker already dead, before its death is told, waits
for the news instead of ending the run with an internal error (a loaded run saw it), and a
replacement is given work only once its collection is in (a loaded CI run saw that one).

Checked by test/system/test_crash_safe_scheduling.py, which runs a suite with a dying test.
"""

from __future__ import annotations

import pytest
from xdist.scheduler import LoadFileScheduling


@pytest.hookimpl(tryfirst=True, optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """conftest.py imports this hook: ``--dist loadfile`` then survives a worker's death."""
    if config.getvalue("dist") != "loadfile":
        return None
    return CrashSafeLoadFileScheduling(config, log)


class CrashSafeLoadFileScheduling(LoadFileScheduling):
    def remove_node(self, node) -> str | None:
        workload = self.assigned_work.pop(node)
        unfinished = {scope: unit for scope, unit in workload.items() if not all(unit.values())}
        if not unfinished:
            return None
        # the worker ran its files in the order it was given them: the first test not done
        # is the one it died in
        crashed = next(
            nodeid for unit in unfinished.values() for nodeid, done in unit.items() if not done
        )
        for scope, unit in unfinished.items():
            if crashed in unit:
                unit[crashed] = True
            if not all(unit.values()):
                self.workqueue[scope] = unit
        for other in self.assigned_work:
            self._reschedule(other)
        return crashed

    def _reschedule(self, node) -> None:
        # a replacement worker gets work once its collection is in: a unit popped for it before
        # would fail on its missing collection, after it had left the queue (and xdist drops a
        # KeyError from remove_node: the dead worker's crash went unreported, and the replacement
        # ended holding a file it was never sent)
        if node.shutting_down or node not in self.registered_collections:
            return
        try:
            if self.workqueue and self._pending_of(self.assigned_work[node]) <= 2:
                self._assign_work_unit(node)
            # a worker starts an item only when it holds the next one or knows there is none
            while self.workqueue and self._pending_of(self.assigned_work[node]) < 2:
                self._assign_work_unit(node)
            if not self.workqueue:
                node.shutdown()
        except OSError:
            # the worker died and its death is not told yet (its last test's report came
            # first): what was just given to it is in its workload, which remove_node puts
            # back on the queue when the death is told
            return
