"""A finished test's result on its way to CGAmed, shared by every executive: sent until CGAmed
answers; stored, it ends the test; refused (CGAmed checked it and never will store it), the
clinician is told once and the test ends too, the result kept aside by the port rather than
sent again forever. Pure logic over the executive's ``Port``."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

STORED = "stored"  # CGAmed stored it (or had it already)
REFUSED = "refused"  # CGAmed answered that it will not store it: final
NOT_YET = "not yet"  # no answer (CGAmed down, restarting, not found): send it again later

Outcome = Callable[[str, str], None]  # (STORED | REFUSED | NOT_YET, error)


def deliver(
    port,
    result: dict[str, Any],
    retry_after: float,
    log,
    still_current: Callable[[], bool],
    on_end: Callable[[str], None],
    set_timer: Callable[[Any], None],
) -> None:
    """Send ``result`` through ``port.store_result`` until it is stored or refused, then call
    ``on_end(STORED | REFUSED)``; ``still_current()`` false (the test was abandoned) stops it."""

    def answered(outcome: str, error: str) -> None:
        if not still_current():
            return
        if outcome == NOT_YET:
            log.warning(f"result not stored yet ({error}); retrying")
            set_timer(port.after(retry_after, lambda: port.store_result(result, answered)))
            return
        if outcome == REFUSED:
            log.error(f"CGAmed refused the result of {result.get('patient')!r}: {error}")
            port.notify_clinician(
                f"CGAmed refused the {result.get('test', 'test')} result of "
                f"{result.get('patient')!r} started {result.get('started')}: {error}. It is kept "
                "in PELEA's outbox (refused/) for you to check; it will not be sent again."
            )
        on_end(outcome)

    port.store_result(result, answered)
